// Focus surfaces (B-spline near/far surfaces, --surfaces): parsed, then
// evaluated over a small frame, where the knots and control points are used.
#include "fuzz_support.h"
#include "gdof/focus_surfaces.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto r = gdof::parse_focus_surfaces(gdof::fuzz::text(data, size));
    if (!r) return 0;
    (void)gdof::desired_from_surfaces(r.value(), 7, 5);
    return 0;
}
