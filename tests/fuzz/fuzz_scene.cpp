// Scene JSON (--render): cameras, lights, materials, meshes. Mesh files are
// looked up in the scratch folder, where fuzz_obj may have left one.
#include "fuzz_support.h"
#include "gdof/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)gdof::parse_scene(gdof::fuzz::text(data, size), gdof::fuzz::scratch_dir(), "fuzz.json");
    return 0;
}
