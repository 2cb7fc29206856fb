#include "stack_pixels.h"

#include <algorithm>
#include <cmath>

namespace gdof::ofx {

DesiredFocus crop(const DesiredFocus& d, const Roi& window) {
    DesiredFocus c;
    c.window = intersect(window, d.window);
    c.near.resize(c.npixels());
    c.far.resize(c.npixels());
    for (int y = c.window.y0; y < c.window.y1; ++y)
        for (int x = c.window.x0; x < c.window.x1; ++x) {
            c.near[c.offset(x, y)] = d.near[d.offset(x, y)];
            c.far[c.offset(x, y)] = d.far[d.offset(x, y)];
        }
    return c;
}

Image reduce(const Image& full, const Roi& target, double sx, double sy) {
    std::vector<std::string> names;
    for (const ChannelSpec& c : full.channels()) names.push_back(c.name);
    Image out = Image::with_channels(names, target);
    const Roi src = full.data_window();
    for (int y = target.y0; y < target.y1; ++y) {
        const int ya = std::max(src.y0, int(std::floor(y / sy + 1e-9))), yb = std::min(src.y1, int(std::ceil((y + 1) / sy - 1e-9)));
        for (int x = target.x0; x < target.x1; ++x) {
            const int xa = std::max(src.x0, int(std::floor(x / sx + 1e-9))), xb = std::min(src.x1, int(std::ceil((x + 1) / sx - 1e-9)));
            const int n = std::max(0, xb - xa) * std::max(0, yb - ya);
            for (int c = 0; c < full.nchannels(); ++c) {
                double s = 0;
                for (int v = ya; v < yb; ++v)
                    for (int u = xa; u < xb; ++u) s += full.at(c, u, v);
                out.at(c, x, y) = n ? float(s / n) : 0.0f;
            }
        }
    }
    return out;
}

}  // namespace gdof::ofx
