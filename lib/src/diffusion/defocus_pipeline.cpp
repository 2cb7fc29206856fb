// defocus_layers: analyse every layer (blur map, content), choose the work
// regions and the output window from the largest blur, diffuse the blurred
// layers one at a time and composite them back to front.
//
// Windows (absolute pixels; m(R) = defocus_margin(R)):
//   limit    L   = the frame: display window ∪ the layers' data windows. Heat
//                  does not leave it (insulated, i.e. reflected, like an
//                  edge-clamped blur), so a full-frame plate keeps opaque,
//                  undarkened edges; existing overscan still receives spread.
//   clip     C   = L (whole result) or defocus_input_region(roi, R_max) ∩ L
//   whole    V_i = (content bbox of layer i) grown by m(R_i), ∩ L
//   work     W_i = V_i ∩ C   (radii are extrapolated over V_i, then cropped)
//   output   O   = (∪ W_i ∪ layer windows) ∩ L (whole result), or roi
// A layer's statistics (R_i, solver step count, extrapolated radii) always
// come from the whole layer, so a sub-region runs the same operator as the
// whole render and differs only by the insulated boundary of C, at least
// m(R_max) away from the output.
#include <chrono>
#include <cmath>

#include "diffusion/defocus_internal.h"

namespace gdof {

using namespace defocus_detail;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Status validate(const DefocusOptions& s) {
    const DiffusionOptions& d = s.diffusion;
    if (!(d.max_radius > 0.0) || !std::isfinite(d.max_radius) || d.max_radius > 1.0e6)
        return Status::error("defocus: max_radius must be a finite number in (0, 1e6], got " + std::to_string(d.max_radius));
    if (d.adi_steps < 0 || d.adi_steps > 1000)
        return Status::error("defocus: adi_steps must be in 0..1000 (0: automatic), got " + std::to_string(d.adi_steps));
    if (!(d.explicit_safety >= 1.0) || d.explicit_safety > 100.0)
        return Status::error("defocus: explicit_safety must be in 1..100, got " + std::to_string(d.explicit_safety));
    if (s.roi.x1 < s.roi.x0 || s.roi.y1 < s.roi.y0)
        return Status::error("defocus: roi " + to_string(s.roi) + " is inverted");
    return Status::ok();
}

// An Exec whose progress maps 0..1 onto [a, b] of the caller's.
Exec sub_exec(const Exec& exec, double a, double b) {
    Exec e = exec;
    if (exec.progress) {
        auto parent = exec.progress;
        e.progress = [parent, a, b](double f) { parent(a + (b - a) * std::clamp(f, 0.0, 1.0)); };
    }
    return e;
}

constexpr double kAnalysisShare = 0.1;  // of the progress bar

}  // namespace

Result<Image> defocus_layers(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                             const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    if (Status st = validate(settings); !st) return st;
    DefocusStats local;
    DefocusStats& S = stats ? *stats : local;
    S = DefocusStats{};
    const int nl = int(layers.size());
    S.layers = nl;

    // 1. Analysis of every layer over its whole window.
    std::vector<LayerAnalysis> an(static_cast<std::size_t>(nl));
    Roi display, frame;
    double rmax = 0.0;
    for (int i = 0; i < nl; ++i) {
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const auto t0 = std::chrono::steady_clock::now();
        const Exec e = sub_exec(exec, kAnalysisShare * i / nl, kAnalysisShare * (i + 1) / nl);
        auto r = analyse_layer(layers[std::size_t(i)], i, field, camera, settings.diffusion, e);
        S.t_blur += seconds_since(t0);
        if (!r) return r.status();
        an[std::size_t(i)] = std::move(r).value();
        display = unite(display, layers[std::size_t(i)].image.display_window());
        frame = unite(frame, layers[std::size_t(i)].image.data_window());
        rmax = std::max(rmax, an[std::size_t(i)].max_radius);
    }
    S.max_radius_px = rmax;

    // 2. Windows.
    const Roi limit = unite(display, frame);
    const Roi clip = settings.roi.empty() ? limit : intersect(defocus_input_region(settings.roi, rmax), limit);
    std::vector<Roi> work(static_cast<std::size_t>(nl)), whole(static_cast<std::size_t>(nl));
    Roi out_win;
    for (int i = 0; i < nl; ++i) {
        const LayerAnalysis& a = an[std::size_t(i)];
        if (!a.empty && a.max_radius > 0.0) {
            whole[std::size_t(i)] = intersect(a.content.grown(defocus_margin(a.max_radius)), limit);
            work[std::size_t(i)] = intersect(whole[std::size_t(i)], clip);
        }
        out_win = unite(out_win, work[std::size_t(i)]);
        out_win = unite(out_win, intersect(layers[std::size_t(i)].image.data_window(), limit));
    }
    out_win = settings.roi.empty() ? intersect(out_win, limit) : settings.roi;

    Image out = Image::with_channels({"R", "G", "B", "A"}, out_win);
    out.set_display_window(display);

    // 3. Back to front: diffuse (or pass through) and composite.
    double total = 0.0;
    for (int i = 0; i < nl; ++i)
        if (!intersect(work[std::size_t(i)], out_win).empty()) total += double(work[std::size_t(i)].npixels());
    double done = 0.0;
    auto progress_at = [&](double d) { return kAnalysisShare + (1.0 - kAnalysisShare) * (total > 0 ? d / total : 1.0); };
    for (int i = nl - 1; i >= 0; --i) {
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const Layer& layer = layers[std::size_t(i)];
        const LayerAnalysis& a = an[std::size_t(i)];
        const Roi lwin = layer.image.data_window();
        if (a.empty) {
            ++S.layers_empty;
            S.pixels_skipped += lwin.npixels();
            continue;
        }
        if (a.max_radius <= 0.0) {
            ++S.layers_sharp;
            S.pixels_skipped += lwin.npixels();
            const auto t0 = std::chrono::steady_clock::now();
            const Image& img = layer.image;
            Status st = composite_over(out, {img.plane(a.rgba.r), img.plane(a.rgba.g), img.plane(a.rgba.b), img.plane(a.rgba.a)},
                                       lwin, exec);
            S.t_composite += seconds_since(t0);
            if (!st) return st;
            continue;
        }
        const Roi& w = work[std::size_t(i)];
        if (intersect(w, out_win).empty()) {  // cannot reach the output (sub-regions)
            S.pixels_skipped += lwin.npixels();
            continue;
        }
        const double share = double(w.npixels());
        DiffusedLayer d;
        Status st = diffuse_layer(layer, i, a, w, whole[std::size_t(i)], settings.diffusion, sub_exec(exec, progress_at(done), progress_at(done + share)),
                                  d, S);
        if (!st) return st;
        S.pixels_diffused += w.npixels();
        S.pixels_skipped += lwin.npixels() - intersect(lwin, w).npixels();
        const auto t0 = std::chrono::steady_clock::now();
        st = composite_over(out, {d.rgba.plane(0), d.rgba.plane(1), d.rgba.plane(2), d.rgba.plane(3)}, w, exec);
        S.t_composite += seconds_since(t0);
        if (!st) return st;
        done += share;
        exec.report(progress_at(done));
    }
    exec.report(1.0);
    return out;
}

}  // namespace gdof
