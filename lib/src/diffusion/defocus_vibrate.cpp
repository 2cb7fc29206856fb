// Method 4 through the defocus pipeline: the same layers as --diffuse and
// --bokeh (deep inputs with their hidden samples revealed by the extension,
// plates with the extended layers of method 3), each with its radii
// extrapolated over the whole frame, handed to vibrate_layers together,
// because visibility after the move is decided per output pixel across
// layers.
#include <chrono>

#include "diffusion/defocus_internal.h"

namespace gdof::defocus_detail {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Result<Image> defocus_vibrate(const LayerSource& source, const BlurField& field, const Camera& camera,
                              const DefocusOptions& settings, DefocusStats& S, const Exec& exec) {
    const int nl = source.size();
    std::vector<Layer> storage(static_cast<std::size_t>(nl));
    std::vector<const Layer*> layers(static_cast<std::size_t>(nl));
    std::vector<LayerAnalysis> an(static_cast<std::size_t>(nl));
    Roi display, data;
    for (int i = 0; i < nl; ++i) {
        if (exec.is_cancelled()) return Status::cancelled("defocus");
        auto t0 = std::chrono::steady_clock::now();
        auto made = source.make(i, storage[std::size_t(i)], exec);
        S.t_layers += seconds_since(t0);
        if (!made) return made.status().prefix("defocus");
        layers[std::size_t(i)] = *made;
        t0 = std::chrono::steady_clock::now();
        auto a = analyse_layer(**made, i, field, camera, settings.diffusion, exec);
        S.t_blur += seconds_since(t0);
        if (!a) return a.status();
        S.max_radius_px = std::max(S.max_radius_px, a->max_radius);
        an[std::size_t(i)] = std::move(a).value();
        display = unite(display, (*made)->image.display_window());
        data = unite(data, (*made)->image.data_window());
    }
    const Roi limit = unite(display, data);
    const Roi frame = display.empty() ? limit : display;

    // Radii over the frame, extrapolated beyond each layer's coverage.
    auto t0 = std::chrono::steady_clock::now();
    std::vector<RadiusMap> radius(static_cast<std::size_t>(nl));
    std::vector<VibrateLayer> vl;
    for (int i = 0; i < nl; ++i) {
        const LayerAnalysis& a = an[std::size_t(i)];
        if (a.empty) {
            ++S.layers_empty;
            continue;
        }
        ++S.layers_vibrated;
        if (a.max_radius > 0.0) radius[std::size_t(i)] = extrapolated_radius(*layers[std::size_t(i)], a, limit, limit, exec);
        else radius[std::size_t(i)].assign(limit.npixels(), 0.0f);
        const Image& img = layers[std::size_t(i)]->image;
        vl.push_back({&img, a.rgba, img.channel_index("Z"), limit, radius[std::size_t(i)].data()});
    }
    S.t_extrapolate += seconds_since(t0);

    t0 = std::chrono::steady_clock::now();
    auto out = vibrate_layers(vl, settings.psf_field, settings.aperture, camera, frame, limit, settings.vibrate,
                              &S.vibrate, exec);
    S.t_diffuse += seconds_since(t0);
    if (!out) return out.status().prefix("defocus");
    S.pixels_diffused = S.vibrate.splats;
    out->set_display_window(display);
    if (settings.roi.empty()) return out;
    const Roi roi = settings.roi;
    Image cropped = Image::with_channels({"R", "G", "B", "A"}, roi);
    cropped.set_display_window(display);
    const Roi both = intersect(roi, limit);
    for (int c = 0; c < 4; ++c)
        for (int y = both.y0; y < both.y1; ++y)
            std::copy_n(out->plane(c) + out->offset(both.x0, y), both.width(), cropped.plane(c) + cropped.offset(both.x0, y));
    return cropped;
}

}  // namespace gdof::defocus_detail
