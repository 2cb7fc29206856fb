// OBJ with its MTL: the input is the OBJ text, then optionally "\n#MTL\n" and
// the text of m.mtl beside it (seeds name it with "mtllib m.mtl").
#include "fuzz_support.h"
#include "gdof/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto [obj, mtl] = gdof::fuzz::split(gdof::fuzz::text(data, size), "\n#MTL\n");
    gdof::fuzz::write_file("m.mtl", mtl);
    auto r = gdof::load_obj(gdof::fuzz::write_file("in.obj", obj));
    if (!r) return 0;
    // Every index of a loaded model must point into its arrays.
    const gdof::ObjModel& m = r.value();
    volatile float sum = 0;
    for (const auto& shape : m.shapes) {
        for (int v : shape.vertex) sum = sum + m.positions[std::size_t(v) * 3];
        for (int n : shape.normal)
            if (n >= 0) sum = sum + m.normals[std::size_t(n) * 3];
        for (int k : shape.material)
            if (k >= 0) sum = sum + float(m.materials[std::size_t(k)].name.size());
    }
    return 0;
}
