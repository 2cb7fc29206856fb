// Focus from the picture: the depth at a pixel (a window's median, so noise,
// holes and a silhouette next to the pixel do not move it) and a probe of
// what the pipeline sees there.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gdof/plate.h"

#include "common/format_number.h"
#include "plate/plate_internal.h"

namespace gdof {

double depth_at(const PlateDepth& pd, int x, int y, int r) {
    const Roi& w = pd.window;
    std::vector<float> v;
    bool sky = false;
    for (int yy = std::max(w.y0, y - r); yy < std::min(w.y1, y + r + 1); ++yy)
        for (int xx = std::max(w.x0, x - r); xx < std::min(w.x1, x + r + 1); ++xx) {
            const float d = pd.depth[std::size_t(yy - w.y0) * std::size_t(w.width()) + std::size_t(xx - w.x0)];
            if (std::isfinite(d)) v.push_back(d);
            else if (std::isinf(d)) sky = true;
        }
    if (v.empty()) return sky ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
    const std::size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(m), v.end());
    double med = v[m];
    if (v.size() % 2 == 0) {  // the mean of the two middle values
        const float lo = *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(m));
        med = 0.5 * (double(lo) + med);
    }
    return med;
}

Result<FocusDistance> focus_distance_at(const Image& plate, int depth_channel, const DepthDecode& decode,
                                        const Camera& camera, int x, int y, const DepthCleanupOptions& cleanup,
                                        const Exec& exec, int r) {
    const std::string at = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
    if (!plate.data_window().contains(x, y))
        return Status::error("focus at " + at + ": outside the image " + to_string(plate.data_window()),
                             StatusCode::InvalidArgument, "focus_at");
    if (depth_channel < 0 || depth_channel >= plate.nchannels())
        return Status::error("focus at " + at + ": no depth channel", StatusCode::NotFound, "depth_channel");
    if (plate.channel(depth_channel).type == PixelType::UInt)
        return Status::error("focus at " + at + ": depth channel '" + plate.channel(depth_channel).name +
                                 "' is not a float channel",
                             StatusCode::InvalidArgument, "depth_channel");
    auto dec = resolve_depth_decode(decode, camera);
    if (!dec) return dec.status().prefix("focus at " + at);
    // The window decoded as prepare_plate_depth decodes (holes stay NaN and
    // drop out of the median): no whole-frame preparation for a measured pixel.
    PlateDepth pd;
    pd.window = intersect(plate.data_window(), Roi{x - r, y - r, x + r + 1, y + r + 1});
    for (int yy = pd.window.y0; yy < pd.window.y1; ++yy)
        for (int xx = pd.window.x0; xx < pd.window.x1; ++xx) {
            double z = decode_depth(plate.at(depth_channel, xx, yy), *dec);
            if (dec->range && std::isfinite(z)) z /= length(camera.depth_line(xx + 0.5, yy + 0.5).per_depth);
            pd.depth.push_back(float(z));
        }
    const double d = depth_at(pd, x, y, r);
    if (!std::isnan(d)) return FocusDistance{d, false};
    auto whole = prepare_plate_depth(plate, depth_channel, decode, camera, cleanup, exec);
    if (!whole) return whole.status().prefix("focus at " + at);
    return FocusDistance{depth_at(*whole, x, y, r), true};
}

Result<FocusedCamera> focus_camera_at(const Metadata& metadata, const Roi& display, const LensOverrides& lens,
                                      const Image& plate, int depth_channel, const DepthDecode& decode,
                                      const DepthCleanupOptions& cleanup, int x, int y, const Exec& exec) {
    auto camera = resolve_camera(metadata, display, lens);
    if (!camera) return camera.status();
    auto picked = focus_distance_at(plate, depth_channel, decode, *camera, x, y, cleanup, exec);
    if (!picked) return picked.status();
    LensOverrides focused = lens;
    focused.focus_distance = picked->distance;
    auto cam = resolve_camera(metadata, display, focused);
    if (!cam) return cam.status();
    // A depth inside the focal length is no scene a lens can focus on: most
    // often an integer depth file read as 0..1 (as OFX hosts deliver clips
    // too) and decoded as metres. Said so here, not as a bad focus distance.
    const double focal = plate_detail::focal_length_scene_units(*cam);
    if (std::isfinite(focal) && picked->distance <= focal)
        return Status::error("focus at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                 "): the depth there decodes to " + format_number(picked->distance, 6) +
                                 " scene units, within the focal length (" + format_number(focal, 6) + "): " +
                                 plate_detail::kDepthScaleHint,
                             StatusCode::InvalidArgument, "depth_scale");
    return FocusedCamera{std::move(cam).value(), *picked};
}

Result<FocusedCamera> focus_camera_at(const ImageSet& set, std::size_t part, const LensOverrides& lens,
                                      const PositionSource& source, const DepthCleanupOptions& cleanup, int x, int y,
                                      const Exec& exec) {
    if (part >= set.size())
        return Status::error("focus at: no part " + std::to_string(part) + " (the image has " +
                                 std::to_string(set.size()) + ")",
                             StatusCode::InvalidArgument);
    // The part with the depth: this one, else the first flat one that has it.
    const Image* plate = nullptr;
    int zc = -1;
    for (std::size_t k = 0; k <= set.size() && !plate; ++k) {
        const std::size_t i = k == 0 ? part : k - 1;
        if (i >= set.size() || set.is_deep(i)) continue;
        auto z = find_depth_channel(set.flat(i), source.depth_channel);
        if (z && *z >= 0) plate = &set.flat(i), zc = *z;
    }
    if (!plate)
        return Status::error("focus at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                 "): no flat part with a depth channel '" +
                                 (source.depth_channel.empty() ? std::string("Z") : source.depth_channel) + "'",
                             StatusCode::NotFound, "depth_channel");
    const Roi display = set.is_deep(part) ? set.deep(part).display_window() : set.flat(part).display_window();
    return focus_camera_at(set.metadata(part), display, lens, *plate, zc, source.depth_decode, cleanup, x, y, exec);
}

Result<PixelProbe> probe_pixel(const PlateDepth& pd, const Camera* camera, const BlurField* field, int x, int y,
                               int r) {
    if (!pd.window.contains(x, y))
        return Status::error("probe: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the image " +
                                 to_string(pd.window),
                             StatusCode::InvalidArgument, "probe");
    PixelProbe p;
    p.x = x, p.y = y;
    p.depth = depth_at(pd, x, y, r);
    const std::size_t i = std::size_t(y - pd.window.y0) * std::size_t(pd.window.width()) + std::size_t(x - pd.window.x0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    p.position = camera && std::isfinite(p.depth) ? camera->unproject(x + 0.5, y + 0.5, p.depth) : Vec3{nan, nan, nan};
    // The field's blur at the pixel's centre at `depth` (NaN when unknown).
    auto blur_at = [&](double depth, double& out) {
        out = nan;
        if (!camera || !field || std::isnan(depth)) return Status::ok();
        const PixelDepth s{x + 0.5, y + 0.5, depth};
        float blur = 0;
        if (Status st = field->evaluate(*camera, std::span<const PixelDepth>(&s, 1), std::span<float>(&blur, 1)); !st)
            return st.prefix("probe");
        out = blur;
        return Status::ok();
    };
    if (Status st = blur_at(p.depth, p.blur_px); !st) return st;
    // A split silhouette pixel: step 5's (its own depth the background's), or
    // step 4's (its own depth the front's) where the defocus will split it.
    const MixedPixel* hole = pd.mixed_at(i);
    const MixedPixel* m = hole ? hole : pd.front_mixed_at(i);
    if (!m) return p;
    const double bg_depth = hole ? double(pd.depth[i]) : double(m->bg_depth);
    double fg_blur = nan, bg_blur = nan;
    if (Status st = blur_at(m->fg_depth, fg_blur); !st) return st;
    if (Status st = blur_at(bg_depth, bg_blur); !st) return st;
    if (!hole && !front_is_sharper(fg_blur, bg_blur)) return p;
    p.mixed = true;
    p.fg_share = m->fg_share;
    p.fg_depth = m->fg_depth;
    p.bg_depth = bg_depth;
    p.fg_blur_px = fg_blur;
    p.bg_blur_px = bg_blur;
    return p;
}

Result<PixelProbe> probe_pixel(const PlateDepth& pd, const Camera& camera, const BlurField& field, int x, int y, int r) {
    return probe_pixel(pd, &camera, &field, x, y, r);
}

Result<PixelProbe> probe_plate(const Image& plate, int depth_channel, const DepthDecode& decode,
                               const DepthCleanupOptions& cleanup, const Camera* camera, const BlurField* field, int x,
                               int y, const Exec& exec) {
    auto pd = camera ? prepare_plate_depth(plate, depth_channel, decode, *camera, cleanup, exec)
                     : prepare_plate_depth(plate, depth_channel, decode, cleanup, exec);
    if (!pd) return pd.status();
    return probe_pixel(*pd, camera, field, x, y);
}

}  // namespace gdof
