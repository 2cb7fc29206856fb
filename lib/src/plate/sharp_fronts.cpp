// Mixed pixels at the edge of a front sharper than its background (plate.h,
// step 4): the pixel moved to the front keeps its background's share of
// colour as a sharp line along the front's edge (a pole in focus over a
// blurred wall: its edge pixels half wall, unblurred). Their parts are found
// here from the colour; the defocus, which knows the blur, splits those
// whose front is sharper (split_sharp_fronts).
#include <algorithm>
#include <cmath>
#include <utility>

#include "plate/plate_internal.h"

namespace gdof {

namespace plate_detail {

std::vector<MixedPixel> front_parts(const std::vector<float>& depth, const std::vector<MixedStep>& steps,
                                    const std::vector<unsigned char>& was_hole, int W, int H, double continuity,
                                    const float* const rgb[3], const float* alpha) {
    std::vector<MixedPixel> out;
    if (!rgb[0] || !rgb[1] || !rgb[2] || steps.empty()) return out;
    // Only opaque pixels: a pixel partly transparent (an element's edge over
    // nothing) is its front's coverage already, with no background to blur.
    auto opaque = [alpha](std::size_t j) { return !alpha || alpha[j] >= kOpaque; };
    std::vector<unsigned char> moved(depth.size(), 0);
    for (const MixedStep& m : steps) moved[m.index] = 1;
    constexpr int kR = 2;  // a 5x5 window
    for (const MixedStep& st : steps) {
        if (!opaque(st.index)) continue;
        const int x = int(st.index % std::size_t(W)), y = int(st.index / std::size_t(W));
        // Each side's measured, unmoved pixels nearest to this one: within
        // `continuity` of the nearer depth it lay between, or of the farther
        // (sky included). A filled hole's depth is a guess (a sensor's
        // shadow band lies right beside the step).
        SideColour fg, bg;
        for (int yy = std::max(0, y - kR); yy <= std::min(H - 1, y + kR); ++yy)
            for (int xx = std::max(0, x - kR); xx <= std::min(W - 1, x + kR); ++xx) {
                const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                const float q = depth[j];
                if (moved[j] || std::isnan(q) || (!was_hole.empty() && was_hole[j]) || !opaque(j)) continue;
                const bool is_fg = double(q) <= double(st.near) * continuity;
                const bool is_bg = double(q) * continuity >= double(st.far) && double(q) <= double(st.far) * continuity;
                if (is_fg == is_bg) continue;
                (is_fg ? fg : bg).add((xx - x) * (xx - x) + (yy - y) * (yy - y), rgb, j, q);
            }
        if (!fg.n || !bg.n) continue;
        double f[3], b[3];
        fg.mean(f);
        bg.mean(b);
        const float pixel[3] = {rgb[0][st.index], rgb[1][st.index], rgb[2][st.index]};
        const double share = colour_share(f, b, pixel);
        // Nearly all foreground: whole at its depth, as moved. A share at or
        // below 0 keeps a trace of the front (it is next to the front).
        if (std::isnan(share) || share >= 1.0 - kPureShare) continue;
        MixedPixel m;
        m.index = st.index;
        m.fg_depth = depth[st.index];
        m.bg_depth = float(bg.depth / bg.n);
        m.fg_share = float(std::max(share, kMinFrontShare));
        unmix(m, pixel, f, b);
        out.push_back(m);
    }
    return out;
}

}  // namespace plate_detail

std::size_t split_sharp_fronts(PlateDepth& pd, std::span<float> radius, std::vector<float>& fg_radius,
                               std::span<const float> bg_radius, double min_dr) {
    std::vector<MixedPixel> front = std::move(pd.front_mixed);
    pd.front_mixed.clear();
    if (front.empty() || bg_radius.size() != front.size() || radius.size() != pd.depth.size() ||
        fg_radius.size() != pd.mixed.size())
        return 0;
    std::vector<MixedPixel> mixed;
    std::vector<float> rf;
    mixed.reserve(pd.mixed.size() + front.size());
    rf.reserve(mixed.capacity());
    std::size_t a = 0, n = 0;
    for (std::size_t k = 0; k < front.size(); ++k) {
        const std::size_t i = front[k].index;
        if (!front_is_sharper(radius[i], bg_radius[k], min_dr)) continue;
        for (; a < pd.mixed.size() && pd.mixed[a].index < i; ++a) {
            mixed.push_back(pd.mixed[a]);
            rf.push_back(fg_radius[a]);
        }
        if (a < pd.mixed.size() && pd.mixed[a].index == i) continue;  // split already (step 5)
        mixed.push_back(front[k]);
        rf.push_back(radius[i]);  // the front's: the pixel was whole at its depth
        pd.depth[i] = front[k].bg_depth;
        radius[i] = bg_radius[k];
        ++n;
    }
    if (n == 0) return 0;
    for (; a < pd.mixed.size(); ++a) {
        mixed.push_back(pd.mixed[a]);
        rf.push_back(fg_radius[a]);
    }
    pd.mixed = std::move(mixed);
    fg_radius = std::move(rf);
    pd.stats.sharp_fronts = n;
    return n;
}

}  // namespace gdof
