// One layer of the defocus pipeline, diffused: its radii extrapolated beyond
// its coverage (the paper's Figure 7), its RGBA copied into a zero-padded
// buffer over the work region so colour and coverage can spread outward, and
// the heat equation run on the four planes with the same operator.
#include <chrono>
#include <cmath>

#include "diffusion/defocus_internal.h"
#include "gdof/fill.h"

namespace gdof::defocus_detail {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The largest radius the solver will see in a radius map, computed exactly as
// diffuse_planes does (through the float diffusivity). A frame-sized map is
// scanned in fixed blocks in parallel (a max: the same for any thread count).
double solver_max_radius(const RadiusMap& radius_map, const Exec& exec) {
    constexpr std::size_t kBlock = 1 << 16;
    const std::size_t nb = (radius_map.size() + kBlock - 1) / kBlock;
    std::vector<float> block_max(nb, 0.0f);
    parallel_for(exec, long(nb), [&](long b0, long b1) {
        for (long b = b0; b < b1; ++b) {
            float dmax = 0.0f;
            const std::size_t i1 = std::min(radius_map.size(), std::size_t(b + 1) * kBlock);
            for (std::size_t i = std::size_t(b) * kBlock; i < i1; ++i)
                dmax = std::max(dmax, float(diffusivity_from_radius(radius_map[i])));
            block_max[std::size_t(b)] = dmax;
        }
    });
    float dmax = 0.0f;
    for (float d : block_max) dmax = std::max(dmax, d);
    return radius_from_diffusivity(dmax);
}

}  // namespace

DiffusionOptions layer_solver_settings(const DiffusionOptions& base, double layer_max_radius,
                                        const RadiusMap& radius_map, const Exec& exec) {
    DiffusionOptions s = base;
    const double r_layer = radius_from_diffusivity(float(diffusivity_from_radius(layer_max_radius)));
    // Auto is decided by the whole layer's largest radius, so every tile of a
    // layer runs the same solver.
    s.solver = choose_solver(r_layer, base);
    if (s.solver == DiffusionSolver::Adi) {
        s.adi_steps = adi_steps_for(r_layer, base);
        return s;
    }
    // Explicit: the solver derives its iteration count from the map's largest
    // radius; scale the safety factor so the count is the whole layer's.
    const int target = explicit_iterations(r_layer, base);
    const double r_map = solver_max_radius(radius_map, exec);
    if (!(r_map > 0.0) || explicit_iterations(r_map, base) == target) return s;
    const double per_safety = diffusivity_from_radius(r_map) * 10.0 / 3.0;
    double safety = std::clamp((double(target) - 0.5) / per_safety, 1.0, 100.0);
    for (int k = 0; k < 8; ++k) {
        s.explicit_safety = safety;
        const int it = explicit_iterations(r_map, s);
        if (it == target) break;
        safety = std::clamp(safety * (it < target ? 1.0 + 1e-9 : 1.0 - 1e-9), 1.0, 100.0);
    }
    return s;
}

RadiusMap extrapolated_radius(const Layer& layer, const LayerAnalysis& analysis, const Roi& extrapolation,
                              const Roi& work, const Exec& exec) {
    const Image& img = layer.image;
    const Roi win = img.data_window();
    const Roi ext = unite(extrapolation, work);
    const int EW = ext.width();
    // Weights everywhere, radii only where the weight is > 0: the fill reads
    // no other value and writes all of them (nothing is zeroed first).
    RadiusMap full(ext.npixels()), weight(ext.npixels());
    const KnownWeight known(analysis, layer);
    parallel_for(exec, ext.height(), [&, known](long r0, long r1) {
        for (int y = ext.y0 + int(r0); y < ext.y0 + int(r1); ++y) {
            float* f = full.data() + std::size_t(y - ext.y0) * std::size_t(EW);
            float* wt = weight.data() + std::size_t(y - ext.y0) * std::size_t(EW);
            // The layer's columns on this row (none outside its rows): weights
            // 0 on either side.
            const bool in_win = y >= win.y0 && y < win.y1;
            const int xa = in_win ? std::clamp(win.x0, ext.x0, ext.x1) : ext.x1;
            const int xb = in_win ? std::clamp(win.x1, xa, ext.x1) : ext.x1;
            std::fill(wt, wt + (xa - ext.x0), 0.0f);
            std::fill(wt + (xb - ext.x0), wt + EW, 0.0f);
            if (xa >= xb) continue;
            const std::size_t src0 = img.offset(xa, y);
            for (int x = xa; x < xb; ++x) {
                const std::size_t src = src0 + std::size_t(x - xa);
                const float wgt = known(src);  // 0 or in (0, 1]
                if (wgt > 0.0f) f[x - ext.x0] = known.radius[src];
                wt[x - ext.x0] = wgt;
            }
        }
    }, 16);
    // One grid (FillGrids::Single), unlike the colour's extension: this fill
    // covers the layer's whole window, spinning it cost 6% of a 1080p plate's
    // wall time, and a pan (tests/bench/run --pan) moved the result only
    // 12-20% less.
    if (!push_pull_fill(ImageView::planar(full.data(), 1, ext), ConstImageView::planar(weight.data(), 1, ext), exec)) {
        // No known radius at all: use the layer's largest.
        std::fill(full.begin(), full.end(), float(analysis.max_radius));
    }
    weight = {};
    radius_past_coverage(layer, analysis, ext, full, exec);
    const float rmax = float(analysis.max_radius);
    if (ext == work) {  // the usual case (a whole render): in place
        parallel_for(exec, ext.height(), [&](long r0, long r1) {
            for (std::size_t i = std::size_t(r0) * std::size_t(EW); i < std::size_t(r1) * std::size_t(EW); ++i)
                full[i] = std::clamp(full[i], 0.0f, rmax);  // guard rounding
        }, 16);
        return full;
    }
    const int W = work.width();
    RadiusMap radius(work.npixels());  // every element set below
    parallel_for(exec, work.height(), [&](long r0, long r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < W; ++x) {
                const float r = full[std::size_t(y + work.y0 - ext.y0) * std::size_t(EW) + std::size_t(x + work.x0 - ext.x0)];
                radius[std::size_t(y) * std::size_t(W) + std::size_t(x)] = std::clamp(r, 0.0f, rmax);  // guard rounding
            }
    }, 16);
    return radius;
}

Status diffuse_layer(const Layer& layer, int index, const LayerAnalysis& analysis, double frame_radius,
                     const Roi& work, const Roi& extrapolation, const DiffusionOptions& settings,
                     const BokehFilter* bokeh, const Roi& frame, const Exec& exec, DiffusedLayer& out,
                     DefocusStats& stats) {
    const Image& img = layer.image;
    const Roi win = img.data_window();
    const int W = work.width();
    const std::size_t n = work.npixels();
    out.work = work;
    out.rgba = Image::uninitialized({{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float}, {"A", PixelType::Float}},
                                    work, work);  // every row written below
    if (n == 0) return Status::ok();
    const Roi overlap = intersect(win, work);

    // Radii over the extrapolation region, cropped to the work region.
    auto t0 = std::chrono::steady_clock::now();
    RadiusMap radius = extrapolated_radius(layer, analysis, extrapolation, work, exec);
    stats.t_extrapolate += seconds_since(t0);

    // Colour and coverage, zero-padded.
    const int src_c[4] = {analysis.rgba.r, analysis.rgba.g, analysis.rgba.b, analysis.rgba.a};
    parallel_for(exec, work.height(), [&](long r0, long r1) {
        for (int y = work.y0 + int(r0); y < work.y0 + int(r1); ++y)
            for (int c = 0; c < 4; ++c) {
                float* d = out.rgba.plane(c) + std::size_t(y - work.y0) * std::size_t(W);
                if (y < overlap.y0 || y >= overlap.y1 || overlap.empty()) {
                    std::fill_n(d, W, 0.0f);
                    continue;
                }
                const int xa = overlap.x0 - work.x0, xb = overlap.x1 - work.x0;
                std::fill(d, d + xa, 0.0f);
                std::copy_n(img.plane(src_c[c]) + img.offset(overlap.x0, y), overlap.width(), d + xa);
                std::fill(d + xb, d + W, 0.0f);
            }
    }, 16);

    // Cancelled: the loops above stopped and left the radii (their rounding
    // guard) and the planes unfinished; a filter would judge them as input.
    if (exec.is_cancelled()) return Status::cancelled(layer_label(layer, index));

    t0 = std::chrono::steady_clock::now();
    const int margin = spread_margin(bokeh != nullptr, analysis.max_radius);
    if (bokeh) {
        ++stats.layers_bokeh;
        const SpreadSeams spread = [&](const ImageView& planes, const RadiusMap& r, const Exec& e) {
            return spread_planes(planes, ConstImageView::planar(r.data(), 1, planes.window), *bokeh, frame, e);
        };
        Status st = spread(out.rgba.channels_view(), radius, exec);
        if (st) st = continue_across_seams(layer, radius, work, margin, spread, out, exec);
        stats.t_diffuse += seconds_since(t0);
        if (!st) return st.prefix(layer_label(layer, index));
        return Status::ok();
    }
    PyramidSolve how;
    Status st = diffuse_pyramid(out.rgba.channels_view(), radius, analysis.max_radius, frame_radius, extrapolation,
                                settings, exec, how);
    if (st) {
        PyramidSolve seams_how;  // the layer's solve is the one counted
        const SpreadSeams spread = [&](const ImageView& planes, const RadiusMap& r, const Exec& e) {
            return diffuse_pyramid(planes, r, analysis.max_radius, frame_radius, extrapolation, settings, e, seams_how);
        };
        st = continue_across_seams(layer, radius, work, margin, spread, out, exec);
    }
    stats.t_diffuse += seconds_since(t0);
    if (!st) return st.prefix(layer_label(layer, index));
    // Counted by the solver that ran: on the pyramid, the levels' one.
    ++(how.solver == DiffusionSolver::Explicit ? stats.layers_explicit : stats.layers_adi);
    if (how.on_pyramid) ++stats.layers_pyramid;
    return Status::ok();
}

int spread_margin(bool bokeh, double max_radius_px) {
    const int m = defocus_margin(max_radius_px);
    if (!bokeh || !(max_radius_px > 0.0)) return m;
    return std::max(m, int(std::ceil(2.0 * max_radius_px)) + 2);
}

int work_margin(const DefocusOptions& settings, double max_radius_px) {
    return spread_margin(settings.filter == DefocusFilter::Bokeh, max_radius_px);
}

}  // namespace gdof::defocus_detail
