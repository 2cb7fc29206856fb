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
#include <algorithm>
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
    if (s.filter != DefocusFilter::Diffusion)
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

// One layer's regions (the file comment): whole V_i and work W_i; empty
// for empty and sharp layers.
struct LayerWindows {
    Roi whole, work;
};

LayerWindows layer_windows(const LayerAnalysis& a, const Roi& limit, const Roi& clip, const DefocusOptions& settings) {
    LayerWindows w;
    if (!a.empty && a.max_radius > 0.0) {
        w.whole = intersect(a.content.grown(work_margin(settings, a.max_radius)), limit);
        w.work = intersect(w.whole, clip);
    }
    return w;
}

// Step 3 for one layer: skipped (empty, or out of reach of the output),
// passed through (sharp) or diffused, then composited onto `out`; `exec`
// reports this layer's progress from 0 to 1.
Status render_layer(const Layer& layer, int i, const LayerAnalysis& a, double frame_radius, const LayerWindows& w,
                    const Roi& output, const DefocusOptions& settings, const BokehFilter* bokeh, const Roi& frame,
                    Image& out, DefocusStats& S, const Exec& exec) {
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
    if (intersect(w.work, output).empty()) {  // cannot reach the output (sub-regions)
        S.pixels_skipped += lwin.npixels();
        return Status::ok();
    }
    DiffusedLayer d;
    Status st = diffuse_layer(layer, i, a, frame_radius, w.work, w.whole, settings.diffusion, bokeh, frame,
                              sub_exec(exec, 0.0, 0.95), d, S);
    if (!st) return st;
    S.pixels_diffused += w.work.npixels();
    S.pixels_skipped += lwin.npixels() - intersect(lwin, w.work).npixels();
    const auto t0 = std::chrono::steady_clock::now();
    st = composite_over(out, {d.rgba.plane(0), d.rgba.plane(1), d.rgba.plane(2), d.rgba.plane(3)}, w.work, exec);
    S.t_composite += seconds_since(t0);
    return st;
}

// Layer i of the source, made (its time counted as the layers' stage).
Result<const Layer*> make_layer(const LayerSource& source, int i, Layer& storage, DefocusStats& S, const Exec& exec) {
    const auto t0 = std::chrono::steady_clock::now();
    auto made = source.make(i, storage, exec);
    S.t_layers += seconds_since(t0);
    if (!made) return made.status().prefix("defocus");
    return made;
}

Result<LayerAnalysis> analyse(const Layer& layer, int i, const BlurField& field, const Camera& camera,
                              const DefocusOptions& settings, DefocusStats& S, const Exec& exec) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = analyse_layer(layer, i, field, camera, settings.diffusion, exec);
    S.t_blur += seconds_since(t0);
    if (r) S.max_radius_px = std::max(S.max_radius_px, r->max_radius);
    return r;
}

// The whole result, one layer at a time, back to front: each layer is made,
// analysed, diffused and composited, then dropped, so only one layer's
// pixels are in memory. The result is accumulated over the frame L and
// cropped to the output window O at the end (the same bits: outside every
// work region and layer window nothing is composited).
Result<Image> defocus_streamed(const LayerSource& source, const BlurField& field, const Camera& camera,
                               const DefocusOptions& settings, const BokehFilter* bokeh, DefocusStats& S,
                               const Exec& exec) {
    const int nl = source.size();
    const Roi display = source.display_window();
    const Roi limit = unite(display, source.frame());
    const Roi frame = display.empty() ? limit : display;
    Image out = Image::with_channels({"R", "G", "B", "A"}, limit);
    out.set_display_window(display);
    Roi output;
    for (int i = nl - 1; i >= 0; --i) {  // back to front
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const double p0 = double(nl - 1 - i) / nl, p1 = double(nl - i) / nl;  // this layer's share of the bar
        Layer storage;
        auto made = make_layer(source, i, storage, S, sub_exec(exec, p0, p0 + 0.2 * (p1 - p0)));
        if (!made) return made.status();
        const Layer& layer = **made;
        auto a = analyse(layer, i, field, camera, settings, S, sub_exec(exec, p0 + 0.2 * (p1 - p0), p0 + 0.3 * (p1 - p0)));
        if (!a) return a.status();
        const LayerWindows w = layer_windows(*a, limit, limit, settings);
        output = unite(output, w.work);
        output = unite(output, intersect(layer.image.data_window(), limit));
        if (Status st = render_layer(layer, i, *a, source.largest_blur_radius(), w, limit, settings, bokeh, frame, out, S,
                                     sub_exec(exec, p0 + 0.3 * (p1 - p0), p1));
            !st)
            return st;
        exec.report(p1);
    }
    output = intersect(output, limit);
    if (output == limit) return out;
    Image cropped = Image::with_channels({"R", "G", "B", "A"}, output);
    cropped.set_display_window(display);
    for (int c = 0; c < 4; ++c)
        for (int y = output.y0; y < output.y1; ++y)
            std::copy_n(out.plane(c) + out.offset(output.x0, y), output.width(), cropped.plane(c) + cropped.offset(output.x0, y));
    return cropped;
}

// A sub-region: every layer's largest blur sets the input region needed, so
// all layers are made and analysed first, then diffused back to front.
Result<Image> defocus_region(const LayerSource& source, const BlurField& field, const Camera& camera,
                             const DefocusOptions& settings, const BokehFilter* bokeh, DefocusStats& S,
                             const Exec& exec) {
    const int nl = source.size();
    std::vector<Layer> storage(static_cast<std::size_t>(nl));
    std::vector<const Layer*> layers(static_cast<std::size_t>(nl));
    std::vector<LayerAnalysis> an(static_cast<std::size_t>(nl));
    Roi display, data;
    double max_radius = 0.0;
    constexpr double kAnalysisShare = 0.1;  // of the progress bar
    for (int i = 0; i < nl; ++i) {
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const Exec e = sub_exec(exec, kAnalysisShare * i / nl, kAnalysisShare * (i + 1) / nl);
        auto made = make_layer(source, i, storage[std::size_t(i)], S, e);
        if (!made) return made.status();
        layers[std::size_t(i)] = *made;
        auto a = analyse(**made, i, field, camera, settings, S, e);
        if (!a) return a.status();
        an[std::size_t(i)] = std::move(a).value();
        display = unite(display, (*made)->image.display_window());
        data = unite(data, (*made)->image.data_window());
        max_radius = std::max(max_radius, an[std::size_t(i)].max_radius);
    }
    const Roi limit = unite(display, data);
    const Roi clip = intersect(defocus_input_region(settings.roi, max_radius), limit);
    const Roi& output = settings.roi;
    const Roi frame = display.empty() ? limit : display;
    std::vector<LayerWindows> w(static_cast<std::size_t>(nl));
    double total = 0.0;
    for (int i = 0; i < nl; ++i) {
        w[std::size_t(i)] = layer_windows(an[std::size_t(i)], limit, clip, settings);
        if (!intersect(w[std::size_t(i)].work, output).empty()) total += double(w[std::size_t(i)].work.npixels());
    }
    Image out = Image::with_channels({"R", "G", "B", "A"}, output);
    out.set_display_window(display);
    double done = 0.0;
    auto at = [&](double d) { return kAnalysisShare + (1.0 - kAnalysisShare) * (total > 0 ? d / total : 1.0); };
    for (int i = nl - 1; i >= 0; --i) {  // back to front
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        const LayerWindows& lw = w[std::size_t(i)];
        const double share = intersect(lw.work, output).empty() ? 0.0 : double(lw.work.npixels());
        if (Status st = render_layer(*layers[std::size_t(i)], i, an[std::size_t(i)], source.largest_blur_radius(), lw,
                                     output, settings, bokeh, frame,
                                     out, S, sub_exec(exec, at(done), at(done + share)));
            !st)
            return st;
        done += share;
        exec.report(at(done));
        storage[std::size_t(i)] = Layer{};  // made layers are not needed any more
    }
    return out;
}

}  // namespace

Result<Image> defocus_layers(const LayerSource& source, const BlurField& field, const Camera& camera,
                             const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    if (Status st = validate(settings); !st) return st;
    DefocusStats local;
    DefocusStats& S = stats ? *stats : local;
    S = DefocusStats{};
    S.layers = source.size();
    // The bokeh filter's aperture, prepared once for every layer.
    std::optional<BokehFilter> bokeh;
    if (settings.filter == DefocusFilter::Bokeh) {
        auto f = BokehFilter::create(settings.aperture);
        if (!f) return f.status();
        bokeh = std::move(f).value();
    }
    const BokehFilter* b = bokeh ? &*bokeh : nullptr;
    if (settings.filter == DefocusFilter::Vibrate) {
        auto out = defocus_vibrate(source, field, camera, settings, S, exec);
        if (out) exec.report(1.0);
        return out;
    }
    auto out = settings.roi.empty() ? defocus_streamed(source, field, camera, settings, b, S, exec)
                                    : defocus_region(source, field, camera, settings, b, S, exec);
    if (out) exec.report(1.0);
    return out;
}

Result<Image> defocus_layers(const std::vector<Layer>& layers, const BlurField& field, const Camera& camera,
                             const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    auto largest = defocus_detail::largest_layer_radius(layers, field, camera, settings, exec);
    if (!largest) return largest.status();
    return defocus_layers(*with_largest_blur_radius(source_of(layers), *largest), field, camera, settings, stats, exec);
}

Result<double> defocus_detail::largest_layer_radius(const std::vector<Layer>& layers, const BlurField& field,
                                                    const Camera& camera, const DefocusOptions& settings,
                                                    const Exec& exec) {
    if (Status st = validate(settings); !st) return st;
    double largest = 0.0;
    if (settings.filter != DefocusFilter::Diffusion) return largest;
    for (int i = 0; i < int(layers.size()); ++i) {
        auto a = analyse_layer(layers[std::size_t(i)], i, field, camera, settings.diffusion, exec);
        if (!a) return a.status();
        largest = std::max(largest, a->max_radius);
    }
    return largest;
}

const char* to_string(DefocusFilter f) {
    switch (f) {
        case DefocusFilter::Bokeh: return "bokeh";
        case DefocusFilter::Vibrate: return "vibrate";
        default: return "diffusion";
    }
}

}  // namespace gdof
