// Stored depth values -> metric depth, and depth map + camera -> positions.
#include <cmath>
#include <limits>
#include <string>

#include "gdof/camera.h"

namespace gdof {

const char* to_string(DepthEncoding e) {
    switch (e) {
        case DepthEncoding::Metric: return "metric";
        case DepthEncoding::Inverse: return "inverse";
        case DepthEncoding::Scaled: return "scaled";
        case DepthEncoding::NearFarLinear: return "near_far_linear";
        case DepthEncoding::NearFarInverse: return "near_far_inverse";
        case DepthEncoding::Disparity: return "disparity";
    }
    return "?";
}

Result<DepthEncoding> parse_depth_encoding(const std::string& name) {
    for (DepthEncoding e : {DepthEncoding::Metric, DepthEncoding::Inverse, DepthEncoding::Scaled,
                            DepthEncoding::NearFarLinear, DepthEncoding::NearFarInverse, DepthEncoding::Disparity})
        if (name == to_string(e)) return e;
    return Status::error("depth encoding: unknown \"" + name +
                             "\" (expected metric, inverse, scaled, near_far_linear, near_far_inverse or disparity)",
                         StatusCode::InvalidArgument, "depth_encoding");
}

Status DepthDecode::validate() const {
    auto bad = [](const std::string& what, const std::string& subject) {
        return Status::error(what, StatusCode::InvalidArgument, subject);
    };
    if (!(scale > 0) || !std::isfinite(scale))
        return bad("depth scale: must be > 0 and finite, got " + std::to_string(scale), "depth_scale");
    if (encoding == DepthEncoding::NearFarLinear || encoding == DepthEncoding::NearFarInverse) {
        if (!(near > 0) || !std::isfinite(near))
            return bad("depth near: must be > 0 and finite, got " + std::to_string(near), "depth_near");
        if (!(far > near) || (encoding == DepthEncoding::NearFarLinear && !std::isfinite(far)))
            return bad("depth far: must be > near (" + std::to_string(near) + "), got " + std::to_string(far),
                       "depth_far");
    }
    if (!(std::isnan(invalid) || (std::isinf(invalid) && invalid > 0)))
        return bad("depth invalid: must be a hole (NaN) or sky (+inf), got " + std::to_string(invalid), "depth_invalid");
    if (!(max_depth > 0))
        return bad("depth max_depth: must be > 0, got " + std::to_string(max_depth), "depth_max");
    if (invalid_value && std::isnan(*invalid_value))
        return bad("depth invalid_value: must be a number (NaN is always invalid)", "depth_invalid_value");
    if (!std::isnan(baseline)) {
        if (!(baseline > 0) || !std::isfinite(baseline))
            return bad("depth baseline: must be > 0 and finite, got " + std::to_string(baseline), "baseline");
        if (encoding != DepthEncoding::Disparity)
            return bad("depth baseline: only a disparity encoding takes a baseline", "baseline");
        if (!(focal_px > 0) || !std::isfinite(focal_px))
            return bad("depth baseline: a disparity with a baseline needs the camera's focal length in pixels",
                       "focal_length_mm");
    }
    return {};
}

Result<DepthDecode> resolve_depth_decode(const DepthDecode& d, const Camera& camera) {
    DepthDecode r = d;
    if (r.encoding == DepthEncoding::Disparity && !std::isnan(r.baseline)) {
        if (camera.projection() != Projection::Perspective)
            return Status::error("depth encoding disparity: needs a perspective camera", StatusCode::InvalidArgument,
                                 "depth_encoding");
        r.focal_px = camera.focal_length_px();
    }
    if (Status st = r.validate(); !st) return st;
    return r;
}

namespace {

double decode_raw(double v, const DepthDecode& d) {
    switch (d.encoding) {
        case DepthEncoding::Metric:
            if (v <= 0) return d.invalid;
            return v * d.scale;
        case DepthEncoding::Inverse:
            if (v < 0) return d.invalid;
            if (v == 0) return std::numeric_limits<double>::infinity();
            return d.scale / v;
        case DepthEncoding::Scaled:
            if (!(v > 0) || std::isinf(v)) return d.invalid;
            return v * d.scale;
        case DepthEncoding::NearFarLinear:
        case DepthEncoding::NearFarInverse: {
            if (v < 0 || v > 1) return d.invalid;
            const double t = d.flip ? 1.0 - v : v;
            if (d.encoding == DepthEncoding::NearFarLinear) return d.near + t * (d.far - d.near);
            const double inv = 1.0 / d.near + t * (1.0 / d.far - 1.0 / d.near);
            return inv > 0 ? 1.0 / inv : std::numeric_limits<double>::infinity();
        }
        case DepthEncoding::Disparity: {
            if (!(v > 0) || std::isinf(v)) return d.invalid;
            const double fb = std::isnan(d.baseline) ? d.scale : d.focal_px * d.baseline;
            return fb / v;
        }
    }
    return d.invalid;
}

}  // namespace

double decode_depth(double v, const DepthDecode& d) {
    if (std::isnan(v) || (d.invalid_value && v == *d.invalid_value)) return d.invalid;
    const double z = decode_raw(v, d);
    if (std::isnan(z) || z <= 0) return d.invalid;
    if (std::isinf(z)) return z;  // explicit infinity: sky
    return z > d.max_depth ? d.invalid : z;
}

void decode_depth(std::span<float> values, const DepthDecode& d) {
    for (float& v : values) v = float(decode_depth(v, d));
}

Result<Image> depth_to_positions(const Image& depth_image, int channel, const Camera& camera,
                                 const DepthDecode& decode) {
    if (channel < 0 || channel >= depth_image.nchannels())
        return Status::error("depth_to_positions: channel index " + std::to_string(channel) + " out of range");
    if (auto s = decode.validate(); !s) return s;
    const Roi win = depth_image.data_window();
    Image out = Image::with_channels({"P.x", "P.y", "P.z"}, win);
    out.set_display_window(depth_image.display_window());
    float* px = out.plane(0);
    float* py = out.plane(1);
    float* pz = out.plane(2);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            const std::size_t o = depth_image.offset(x, y);
            double depth = decode_depth(depth_image.sample(channel, x, y), decode);
            const DepthLine line = camera.depth_line(x + 0.5, y + 0.5);
            if (decode.range && std::isfinite(depth)) depth /= length(line.per_depth);
            if (!std::isfinite(depth)) {
                px[o] = py[o] = pz[o] = nan;
                continue;
            }
            const Vec3 p = line.at(depth);
            px[o] = float(p.x);
            py[o] = float(p.y);
            pz[o] = float(p.z);
        }
    return out;
}

}  // namespace gdof
