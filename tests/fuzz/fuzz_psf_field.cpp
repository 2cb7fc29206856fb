// PSF-field JSON through PsfField::parse (its blend weights are blur-field
// nodes, so image_maps named in it load relative to the scratch folder). A
// parsed field is asked for its weights and displacements at a few points
// and aperture samples, so the values it was built from are exercised too.
#include "fuzz_support.h"
#include <algorithm>
#include <vector>

#include "gdof/camera.h"
#include "gdof/io/blur_field_io.h"
#include "gdof/psf_field.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto r = gdof::PsfField::parse(gdof::fuzz::text(data, size), gdof::io::blur_field_context(gdof::fuzz::scratch_dir()));
    if (!r) return 0;
    const gdof::PsfField& field = r.value();
    const gdof::Camera camera;
    const gdof::Roi frame{0, 0, 64, 36};
    std::vector<float> weights(std::size_t(std::max(0, field.weight_count())) + 1, 0.0f);
    volatile double sum = double(field.samples()) + double(field.moves_depth()) + double(field.describe().size());
    for (double depth : {0.0, 0.5, 2.0, 1e6})
        for (double px : {-1.0, 0.5, 31.5, 70.0}) {
            field.evaluate_weights(camera, px, 17.5, depth, weights.data());
            const gdof::PsfPoint p{px, 17.5, depth, 12.0, weights.data()};
            for (double u : {-1.0, 0.0, 0.3, 1.0}) {
                const gdof::PsfDisplacement d = field.displace(p, u, 0.5 * u, frame);
                sum = sum + d.dx + d.dy + d.dz;
            }
        }
    return 0;
}
