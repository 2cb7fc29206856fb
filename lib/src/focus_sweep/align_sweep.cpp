// align_sweep (focus_sweep.h): each frame matched to its neighbour towards
// the middle frame (neighbours differ little in blur, so their difference is
// mostly motion), the matches chained, every frame resampled once.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "focus_sweep/align_internal.h"
#include "gdof/focus_sweep.h"

namespace gdof {

std::string SweepAlignment::report() const {
    double worst_before = 0, worst_after = 0, smin = 1e30, smax = 0;
    for (std::size_t i = 0; i < maps.size(); ++i) {
        worst_before = std::max(worst_before, residual_before[i]);
        worst_after = std::max(worst_after, residual_after[i]);
        smin = std::min(smin, maps[i].scale());
        smax = std::max(smax, maps[i].scale());
    }
    char b[300];
    std::snprintf(b, sizeof b,
                  "align: %zu frames to frame %zu, scale %.4f..%.4f, neighbour residual up to %.4f -> %.4f, common %s",
                  maps.size(), reference + 1, smin, smax, worst_before, worst_after, to_string(common).c_str());
    return b;
}

namespace {

// The inverse of z -> A z + B: z -> (z - B) / A.
Similarity inverse(const Similarity& s) {
    const double d = s.a * s.a + s.b * s.b;
    Similarity r;
    r.a = s.a / d;
    r.b = -s.b / d;
    r.tx = -(r.a * s.tx - r.b * s.ty);
    r.ty = -(r.b * s.tx + r.a * s.ty);
    return r;
}

// The reference pixels whose image under `map` lies inside a w x h frame:
// an axis-aligned box inside the mapped-back frame (near identity maps).
Roi seen_window(const Similarity& map, int w, int h) {
    const Similarity back = inverse(map);
    double x[4], y[4];
    back.apply(0, 0, x[0], y[0]);
    back.apply(w, 0, x[1], y[1]);
    back.apply(0, h, x[2], y[2]);
    back.apply(w, h, x[3], y[3]);
    const int x0 = int(std::ceil(std::max(x[0], x[2]))), x1 = int(std::floor(std::min(x[1], x[3])));
    const int y0 = int(std::ceil(std::max(y[0], y[1]))), y1 = int(std::floor(std::min(y[2], y[3])));
    return {std::clamp(x0, 0, w), std::clamp(y0, 0, h), std::clamp(x1, 0, w), std::clamp(y1, 0, h)};
}

}  // namespace

Result<SweepAlignment> align_sweep(std::vector<Image>& frames, const AlignOptions& options, const Exec& exec) {
    const std::size_t n = frames.size();
    if (n < 2) return Status::error("align: a sweep needs at least 2 frames, got " + std::to_string(n), StatusCode::InvalidArgument);
    for (std::size_t i = 1; i < n; ++i)
        if (frames[i].data_window() != frames[0].data_window())
            return Status::error("align: frame " + std::to_string(i + 1) + " is " + to_string(frames[i].data_window()) +
                                     ", frame 1 " + to_string(frames[0].data_window()),
                                 StatusCode::InvalidArgument);
    SweepAlignment out;
    out.reference = (n - 1) / 2;
    out.maps.assign(n, Similarity{});
    out.residual_before.assign(n, 0.0);
    out.residual_after.assign(n, 0.0);
    if (Status st = sweep_detail::check_align_options(options); !st) return st;
    const int w = frames[0].width(), h = frames[0].height();
    auto pyramid = [&](std::size_t k) {
        return sweep_detail::make_align_pyramid(frames[k], "align: frame " + std::to_string(k + 1), exec);
    };
    // Frame k against its neighbour towards the reference (whose map is
    // done: the chains run outwards from the reference, each frame's pyramid
    // built once and kept while its outer neighbour is matched to it).
    std::size_t links = 0;
    auto chain = [&](std::size_t k, std::size_t towards, sweep_detail::AlignPyramid& inner) -> Status {
        auto outer = pyramid(k);
        if (!outer) return outer.status();
        auto fit = sweep_detail::fit_similarity(outer.value(), inner, w, h, options, Similarity{}, exec);
        if (!fit) {
            if (fit.status().code() == StatusCode::Cancelled) return fit.status();
            return Status::error("frame " + std::to_string(k + 1) + " against frame " + std::to_string(towards + 1) + ": " +
                                     fit.message(),
                                 fit.status().code());
        }
        out.maps[k] = fit.value().map.after(out.maps[towards]);
        out.residual_before[k] = fit.value().residual_before;
        out.residual_after[k] = fit.value().residual_after;
        inner = std::move(outer).value();
        exec.report(0.8 * double(++links) / double(n - 1));
        return Status::ok();
    };
    {
        auto ref = pyramid(out.reference);
        if (!ref) return ref.status();
        sweep_detail::AlignPyramid inner = ref.value();
        for (std::size_t k = out.reference + 1; k < n; ++k)
            if (Status st = chain(k, k - 1, inner); !st) return st;
        inner = std::move(ref).value();
        for (std::size_t k = out.reference; k-- > 0;)
            if (Status st = chain(k, k + 1, inner); !st) return st;
    }
    out.common = Roi{0, 0, w, h};
    for (std::size_t k = 0; k < n; ++k) {
        out.common = intersect(out.common, seen_window(out.maps[k], w, h));
        if (k != out.reference) frames[k] = warp_similarity(frames[k], out.maps[k], exec);
        if (exec.is_cancelled()) return Status::cancelled("align");
        exec.report(0.8 + 0.2 * double(k + 1) / double(n));
    }
    const Roi dw = frames[0].data_window();
    out.common = Roi{out.common.x0 + dw.x0, out.common.y0 + dw.y0, out.common.x1 + dw.x0, out.common.y1 + dw.y0};
    return out;
}

}  // namespace gdof
