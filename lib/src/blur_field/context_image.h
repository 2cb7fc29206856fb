// An image_map's "image" resolved in a BlurField::Context (a name the
// program supplied, else a path relative to base_dir for its loader), and
// where a frame pixel samples it. The blur field's image_map and the PSF
// field's (psf_field) read and sample their maps this way.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "common/json_read.h"
#include "gdof/blur_field.h"

namespace gdof::blur_field_detail {

// Fails (json_read::fail at `path`) when the image cannot be had, is null or
// has no channels or an empty display window.
inline std::shared_ptr<const Image> context_image(const BlurField::Context& ctx, const std::string& ref,
                                                  const std::string& path) {
    std::shared_ptr<const Image> img;
    if (auto it = ctx.images.find(ref); it != ctx.images.end()) {
        img = it->second;
    } else if (ctx.load_image) {
        std::filesystem::path p(ref);
        if (p.is_relative() && !ctx.base_dir.empty()) p = std::filesystem::path(ctx.base_dir) / p;
        auto r = ctx.load_image(p.string());
        if (!r) json_read::fail(path, "cannot load \"" + p.string() + "\": " + r.message(), r.status().code());
        img = r.value();
    } else {
        json_read::fail(path, "no image named \"" + ref + "\" was supplied (and no image loader is set)",
                        StatusCode::NotFound);
    }
    if (!img) json_read::fail(path, "image \"" + ref + "\" is null");
    if (img->nchannels() == 0) json_read::fail(path, "image \"" + ref + "\" has no channels");
    if (img->display_window().empty()) json_read::fail(path, "image \"" + ref + "\" has an empty display window");
    return img;
}

// Where a frame pixel (continuous, centres at +0.5) samples a map whose
// display window is stretched over the frame's: the four bilinear taps
// (clamped to the map's data window) and the weights between them. `ok` is
// false for an empty data window or frame, or a NaN position.
struct MapTaps {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double fx = 0, fy = 0;
    bool ok = false;
};
inline MapTaps map_taps(const Image& map, const Roi& frame, double px, double py) {
    MapTaps t;
    const Roi& md = map.display_window();
    const Roi& dw = map.data_window();
    if (dw.empty() || frame.empty() || std::isnan(px) || std::isnan(py)) return t;
    const double u = md.x0 + (px - frame.x0) * (double(md.width()) / frame.width()) - 0.5;
    const double v = md.y0 + (py - frame.y0) * (double(md.height()) / frame.height()) - 0.5;
    const double uc = std::clamp(u, double(dw.x0), double(dw.x1 - 1));
    const double vc = std::clamp(v, double(dw.y0), double(dw.y1 - 1));
    t.x0 = int(std::floor(uc));
    t.y0 = int(std::floor(vc));
    t.x1 = std::min(t.x0 + 1, dw.x1 - 1);
    t.y1 = std::min(t.y0 + 1, dw.y1 - 1);
    t.fx = uc - t.x0;
    t.fy = vc - t.y0;
    t.ok = true;
    return t;
}

}  // namespace gdof::blur_field_detail
