// The benchmark's open aperture, shared by bench_methods and
// bench_focus_pull so that the focus pull is judged at the method
// benchmark's thin lens.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "gdof/camera.h"
#include "gdof/image.h"

namespace gdof::bench {

// The plate's depth range: the 2nd and 98th percentiles of its finite Z
// (robust to a stray pixel). Dies, naming `what`, without finite depth.
struct DepthRange {
    double near = 0, far = 0;
};
inline DepthRange depth_range(const Image& plate, const std::string& what) {
    const int zc = plate.channel_index("Z");
    if (zc < 0) die(what + " has no Z");
    std::vector<float> zs;
    for (std::size_t i = 0; i < plate.npixels(); ++i)
        if (std::isfinite(plate.plane(zc)[i])) zs.push_back(plate.plane(zc)[i]);
    if (zs.empty()) die(what + ": no finite depth");
    std::sort(zs.begin(), zs.end());
    return {zs[zs.size() / 50], zs[zs.size() * 49 / 50]};
}

// The f-number that blurs the nearest geometry (znear) by 10 px per 640 px of
// width with the scene camera's focus: the benchmark's thin-lens field, and
// the widest aperture of its stack (so compositing can reach that blur).
inline double open_f_number(const Camera& cam, double scale, double znear) {
    const ThinLens tl = take(cam.thin_lens(), "scene camera");
    return tl.f_number * tl.coc_radius_px(znear) / (10 * scale);
}

}  // namespace gdof::bench
