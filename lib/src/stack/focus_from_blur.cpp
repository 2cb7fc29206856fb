// Desired near/far from a blur field and a depth/position image
// (focus_surfaces.h): in-focus intervals along the pixels' central rays,
// searched once for depth-only fields, else on a grid of rays with bilinear
// interpolation in between.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gdof/focus_surfaces.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Depth of every pixel of the image's data window (NaN where unknown).
Result<std::vector<float>> pixel_depths(const Image& img, const Camera& camera, const PositionSource& source) {
    std::vector<float> z(img.npixels(), std::numeric_limits<float>::quiet_NaN());
    auto pos = find_position_channels(img, source.position_channels);
    if (!pos) return pos.status();
    const Roi w = img.data_window();
    if (*pos) {
        const auto [cx, cy, cz] = **pos;
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x) {
                const Vec3 p{img.sample(cx, x, y), img.sample(cy, x, y), img.sample(cz, x, y)};
                z[img.offset(x, y)] = float(camera.project(p).depth);
            }
        return z;
    }
    auto dc = find_depth_channel(img, source.depth_channel);
    if (!dc) return dc.status();
    if (*dc < 0)
        return Status::error("no position channels (P.x/P.y/P.z, ...) and no depth channel '" +
                             (source.depth_channel.empty() ? std::string("Z") : source.depth_channel) + "'");
    if (source.depth_decode.range) {
        auto p = depth_to_positions(img, *dc, camera, source.depth_decode);
        if (!p) return p.status();
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x) {
                const Vec3 q{p->at(0, x, y), p->at(1, x, y), p->at(2, x, y)};
                z[img.offset(x, y)] = float(camera.project(q).depth);
            }
        return z;
    }
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x)
            z[img.offset(x, y)] = float(decode_depth(img.sample(*dc, x, y), source.depth_decode));
    return z;
}

// Distance from depth z to [n, f] in inverse depth (0 inside).
double inverse_gap(const DepthInterval& iv, double z) {
    const double iz = 1.0 / z;  // z = +inf -> 0
    const double in = 1.0 / iv.near, ifar = 1.0 / iv.far;
    if (iz > in) return iz - in;
    if (iz < ifar) return ifar - iz;
    return 0.0;
}

}  // namespace

DepthInterval choose_interval(const InFocusIntervals& iv, double z) {
    if (iv.intervals.empty() || std::isnan(z) || z <= 0) return iv.primary();
    std::size_t best = 0;
    double best_gap = kInf;
    for (std::size_t i = 0; i < iv.intervals.size(); ++i) {
        if (iv.intervals[i].contains(z)) return iv.intervals[i];
        const double g = inverse_gap(iv.intervals[i], z);
        if (g < best_gap) best_gap = g, best = i;
    }
    return iv.intervals[best];
}

Result<DesiredFocus> desired_from_blur_field(const BlurField& field, const Camera& camera, const Image& img,
                                             const BlurFocusOptions& settings, const Exec& exec) {
    if (img.data_window().empty()) return Status::error("the depth/position image has an empty data window");
    if (!(settings.coc_px >= 0)) return Status::error("coc_px must be >= 0");
    auto zr = pixel_depths(img, camera, settings.source);
    if (!zr) return zr.status();
    const std::vector<float>& z = zr.value();
    const Roi w = img.data_window();
    const int W = w.width(), H = w.height();

    DesiredFocus d;
    d.window = {0, 0, W, H};
    d.near.resize(d.npixels());
    d.far.resize(d.npixels());

    auto search = [&](double px, double py) -> Result<InFocusIntervals> {
        return field.in_focus_interval(camera, px, py, settings.coc_px, settings.depth_min, settings.depth_max);
    };

    if (field.depth_only()) {
        // B is a function of depth: every ray sees the same intervals.
        auto iv = search(w.x0 + 0.5 * W, w.y0 + 0.5 * H);
        if (!iv) return iv.status();
        for (std::size_t i = 0; i < d.npixels(); ++i) {
            const DepthInterval c = choose_interval(iv.value(), z[i]);
            d.near[i] = float(c.near);
            d.far[i] = float(c.far);
        }
        return d;
    }

    const int step = settings.grid_step > 0 ? settings.grid_step : 8;
    // Grid nodes at pixel centres x = 0, step, 2 step, ..., and the last pixel.
    auto nodes = [&](int n) {
        std::vector<int> v;
        for (int i = 0; i < n; i += step) v.push_back(i);
        if (v.back() != n - 1) v.push_back(n - 1);
        return v;
    };
    const std::vector<int> gx = nodes(W), gy = nodes(H);
    std::vector<InFocusIntervals> grid(gx.size() * gy.size());
    std::vector<Status> errors(gy.size());
    bool ok = parallel_for(exec, long(gy.size()), [&](long j0, long j1) {
        for (long j = j0; j < j1; ++j)
            for (std::size_t i = 0; i < gx.size(); ++i) {
                auto iv = search(w.x0 + gx[i] + 0.5, w.y0 + gy[std::size_t(j)] + 0.5);
                if (!iv) {
                    errors[std::size_t(j)] = iv.status();
                    return;
                }
                grid[std::size_t(j) * gx.size() + i] = std::move(iv).value();
            }
    });
    if (!ok) return Status::cancelled();
    for (const Status& e : errors)
        if (!e) return e;

    ok = parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            const std::size_t j = std::size_t(std::upper_bound(gy.begin(), gy.end(), int(y)) - gy.begin()) - 1;
            const std::size_t j1 = std::min(j + 1, gy.size() - 1);
            const double ty = j1 == j ? 0.0 : double(y - gy[j]) / double(gy[j1] - gy[j]);
            std::size_t i = 0;
            for (int x = 0; x < W; ++x) {
                while (i + 1 < gx.size() && gx[i + 1] <= x) ++i;
                const std::size_t i1 = std::min(i + 1, gx.size() - 1);
                const double tx = i1 == i ? 0.0 : double(x - gx[i]) / double(gx[i1] - gx[i]);
                const std::size_t o = std::size_t(y) * std::size_t(W) + std::size_t(x);
                const double zz = z[o];
                double n = 0, f = 0;
                const double wts[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
                const std::size_t idx[4] = {j * gx.size() + i, j * gx.size() + i1, j1 * gx.size() + i, j1 * gx.size() + i1};
                for (int k = 0; k < 4; ++k) {
                    if (wts[k] == 0.0) continue;
                    const DepthInterval c = choose_interval(grid[idx[k]], zz);
                    n += wts[k] * c.near;
                    f = std::isinf(c.far) || std::isinf(f) ? kInf : f + wts[k] * c.far;
                }
                d.near[o] = float(n);
                d.far[o] = float(f);
            }
        }
    }, 8);
    if (!ok) return Status::cancelled();
    return d;
}

}  // namespace gdof
