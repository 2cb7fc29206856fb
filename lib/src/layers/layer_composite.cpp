// Back-to-front `over` of layers into one RGBA image.
#include <algorithm>

#include "gdof/layers.h"

namespace gdof {

Result<Image> composite_layers(const std::vector<const Image*>& front_to_back, const Roi& window, const Exec& exec) {
    Image out = Image::with_channels({"R", "G", "B", "A"}, window);
    for (const Image* l : front_to_back)
        if (l) {
            out.set_display_window(l->display_window());
            break;
        }
    if (window.empty()) return out;
    struct Src {
        const Image* img;
        Roi box;
        const float* ch[4];  // R, G, B, A (nullptr: 0, or 1 for a missing A)
    };
    std::vector<Src> srcs;
    for (auto it = front_to_back.rbegin(); it != front_to_back.rend(); ++it) {  // back first
        const Image* l = *it;
        if (!l) continue;
        const Roi box = intersect(l->data_window(), window);
        if (box.empty()) continue;
        const RgbaIndices ix = find_rgba(*l);
        Src s{l, box, {}};
        const int idx[4] = {ix.r, ix.g, ix.b, ix.a};
        for (int c = 0; c < 4; ++c) s.ch[c] = idx[c] >= 0 ? l->plane(idx[c]) : nullptr;
        srcs.push_back(s);
    }
    float* o[4] = {out.plane(0), out.plane(1), out.plane(2), out.plane(3)};
    const bool ok = parallel_for(exec, window.height(), [&](long r0, long r1) {
        for (long row = r0; row < r1; ++row) {
            const int y = window.y0 + int(row);
            for (const Src& s : srcs) {
                if (y < s.box.y0 || y >= s.box.y1) continue;
                for (int x = s.box.x0; x < s.box.x1; ++x) {
                    const std::size_t so = s.img->offset(x, y);
                    const std::size_t oo = out.offset(x, y);
                    const float a = s.ch[3] ? s.ch[3][so] : 1.0f;
                    const float t = 1.0f - a;
                    for (int c = 0; c < 3; ++c) o[c][oo] = (s.ch[c] ? s.ch[c][so] : 0.0f) + t * o[c][oo];
                    o[3][oo] = a + t * o[3][oo];
                }
            }
        }
    });
    if (!ok) return Status::cancelled("compositing layers");
    return out;
}

}  // namespace gdof
