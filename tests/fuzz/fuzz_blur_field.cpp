// Blur-field JSON through io::parse_blur_field, which also loads mask images
// named in it (relative to the scratch folder, where the EXR harness's last
// input may lie). A parsed field is queried along a ray and over a small
// grid, so the values it was built from are exercised too.
#include "fuzz_support.h"
#include "gdof/blur_field.h"
#include "gdof/io/blur_field_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto r = gdof::io::parse_blur_field(gdof::fuzz::text(data, size), gdof::fuzz::scratch_dir());
    if (!r) return 0;
    const gdof::BlurField& field = r.value();
    const gdof::Camera camera;  // the identity camera: one pixel, looking down its axis
    volatile double sum = 0;
    for (double depth : {0.0, 0.5, 1.0, 10.0, 1e6})
        for (double px : {-1.0, 0.0, 0.5, 2.0}) sum = sum + field.evaluate_pixel(camera, px, 0.5, depth);
    auto interval = field.in_focus_interval(camera, 0.5, 0.5, 1.0, 0.01, 1e3);
    if (interval) sum = sum + double(interval.value().primary().near);
    sum = sum + double(field.describe().size());
    return 0;
}
