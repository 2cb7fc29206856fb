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
#include <optional>

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
    if (s.filter == DefocusFilter::Bokeh)
        if (Status st = validate(s.aperture); !st) return st;
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

// Step 1: every layer analysed over its whole window.
struct Analysis {
    std::vector<LayerAnalysis> layers;
    Roi display, frame;  // unions of the layers' display and data windows
    double max_radius = 0.0;
};

Result<Analysis> analyse_layers(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                                const DiffusionOptions& settings, DefocusStats& S, const Exec& exec) {
    const int nl = int(layers.size());
    Analysis an;
    an.layers.resize(static_cast<std::size_t>(nl));
    for (int i = 0; i < nl; ++i) {
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const auto t0 = std::chrono::steady_clock::now();
        const Exec e = sub_exec(exec, kAnalysisShare * i / nl, kAnalysisShare * (i + 1) / nl);
        auto r = analyse_layer(layers[std::size_t(i)], i, field, camera, settings, e);
        S.t_blur += seconds_since(t0);
        if (!r) return r.status();
        an.layers[std::size_t(i)] = std::move(r).value();
        an.display = unite(an.display, layers[std::size_t(i)].image.display_window());
        an.frame = unite(an.frame, layers[std::size_t(i)].image.data_window());
        an.max_radius = std::max(an.max_radius, an.layers[std::size_t(i)].max_radius);
    }
    return an;
}

// Step 2: the windows of the file comment (limit L, clip C, whole V_i, work
// W_i, output O).
struct Windows {
    Roi limit, clip, output;
    std::vector<Roi> whole, work;  // empty for empty and sharp layers
};

Windows plan_windows(const std::vector<Layer>& layers, const Analysis& an, const DefocusOptions& settings) {
    const Roi& roi = settings.roi;
    const std::size_t nl = layers.size();
    Windows w;
    w.limit = unite(an.display, an.frame);
    w.clip = roi.empty() ? w.limit : intersect(defocus_input_region(roi, an.max_radius), w.limit);
    w.whole.resize(nl);
    w.work.resize(nl);
    for (std::size_t i = 0; i < nl; ++i) {
        const LayerAnalysis& a = an.layers[i];
        if (!a.empty && a.max_radius > 0.0) {
            w.whole[i] = intersect(a.content.grown(work_margin(settings, a.max_radius)), w.limit);
            w.work[i] = intersect(w.whole[i], w.clip);
        }
        w.output = unite(w.output, w.work[i]);
        w.output = unite(w.output, intersect(layers[i].image.data_window(), w.limit));
    }
    w.output = roi.empty() ? intersect(w.output, w.limit) : roi;
    return w;
}

// Progress over step 3: after the analysis share, in proportion to the
// work-region pixels of the layers that reach the output.
struct DiffusionProgress {
    double total = 0.0, done = 0.0;
    double at(double d) const { return kAnalysisShare + (1.0 - kAnalysisShare) * (total > 0 ? d / total : 1.0); }
};

// Step 3 for one layer: skipped (empty, or out of reach of the output),
// passed through (sharp) or diffused, then composited onto `out`.
Status render_layer(const Layer& layer, int i, const LayerAnalysis& a, const Windows& w, const DefocusOptions& settings,
                    const BokehFilter* bokeh, const Roi& frame, Image& out, DiffusionProgress& progress, DefocusStats& S,
                    const Exec& exec) {
    const Roi lwin = layer.image.data_window();
    if (a.empty) {
        ++S.layers_empty;
        S.pixels_skipped += lwin.npixels();
        return Status::ok();
    }
    if (a.max_radius <= 0.0) {
        ++S.layers_sharp;
        S.pixels_skipped += lwin.npixels();
        const auto t0 = std::chrono::steady_clock::now();
        const Image& img = layer.image;
        Status st = composite_over(out, {img.plane(a.rgba.r), img.plane(a.rgba.g), img.plane(a.rgba.b), img.plane(a.rgba.a)},
                                   lwin, exec);
        S.t_composite += seconds_since(t0);
        return st;
    }
    const Roi& work = w.work[std::size_t(i)];
    if (intersect(work, w.output).empty()) {  // cannot reach the output (sub-regions)
        S.pixels_skipped += lwin.npixels();
        return Status::ok();
    }
    const double share = double(work.npixels());
    DiffusedLayer d;
    Status st = diffuse_layer(layer, i, a, work, w.whole[std::size_t(i)], settings.diffusion, bokeh, frame,
                              sub_exec(exec, progress.at(progress.done), progress.at(progress.done + share)), d, S);
    if (!st) return st;
    S.pixels_diffused += work.npixels();
    S.pixels_skipped += lwin.npixels() - intersect(lwin, work).npixels();
    const auto t0 = std::chrono::steady_clock::now();
    st = composite_over(out, {d.rgba.plane(0), d.rgba.plane(1), d.rgba.plane(2), d.rgba.plane(3)}, work, exec);
    S.t_composite += seconds_since(t0);
    if (!st) return st;
    progress.done += share;
    exec.report(progress.at(progress.done));
    return Status::ok();
}

}  // namespace

Result<Image> defocus_layers(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                             const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    if (Status st = validate(settings); !st) return st;
    DefocusStats local;
    DefocusStats& S = stats ? *stats : local;
    S = DefocusStats{};
    const int nl = int(layers.size());
    S.layers = nl;

    auto an = analyse_layers(layers, field, camera, settings.diffusion, S, exec);
    if (!an) return an.status();
    S.max_radius_px = an->max_radius;
    const Windows w = plan_windows(layers, *an, settings);

    // The bokeh filter's aperture, prepared once for every layer.
    std::optional<BokehFilter> bokeh;
    if (settings.filter == DefocusFilter::Bokeh) {
        auto f = BokehFilter::create(settings.aperture);
        if (!f) return f.status();
        bokeh = std::move(f).value();
    }
    const Roi frame = an->display.empty() ? w.limit : an->display;

    Image out = Image::with_channels({"R", "G", "B", "A"}, w.output);
    out.set_display_window(an->display);
    DiffusionProgress progress;
    for (int i = 0; i < nl; ++i)
        if (!intersect(w.work[std::size_t(i)], w.output).empty()) progress.total += double(w.work[std::size_t(i)].npixels());
    for (int i = nl - 1; i >= 0; --i) {  // back to front
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        if (Status st = render_layer(layers[std::size_t(i)], i, an->layers[std::size_t(i)], w, settings, bokeh ? &*bokeh : nullptr,
                                     frame, out, progress, S, exec);
            !st)
            return st;
    }
    exec.report(1.0);
    return out;
}

const char* to_string(DefocusFilter f) { return f == DefocusFilter::Bokeh ? "bokeh" : "diffusion"; }

}  // namespace gdof
