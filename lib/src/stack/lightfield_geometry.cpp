// Light-field geometry: disparity <-> depth, depth of field of a refocused
// image, and the checks on a grid of views.
#include <cmath>
#include <limits>
#include <string>

#include "gdof/lightfield.h"

namespace gdof {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double LightFieldGeometry::disparity_of_depth(double z) const {
    if (std::isnan(z)) return kNaN;
    if (std::isinf(z) && z > 0) return disparity_at_infinity;
    return focal_baseline / z + disparity_at_infinity;
}

double LightFieldGeometry::depth_of_disparity(double d) const {
    if (std::isnan(d) || focal_baseline == 0) return kNaN;
    const double u = (d - disparity_at_infinity) / focal_baseline;  // 1 / z
    if (u < 0) return kNaN;
    if (u == 0) return kInf;
    return 1.0 / u;
}

DepthRange depth_interval(const LightFieldGeometry& g, double d_lo, double d_hi) {
    DepthRange out;
    if (std::isnan(d_lo) || std::isnan(d_hi) || d_lo > d_hi || g.focal_baseline == 0 ||
        !std::isfinite(g.focal_baseline) || !std::isfinite(g.disparity_at_infinity))
        return out;
    // Inverse depth u = 1/z = (d - d_inf) / fb is monotonic in d.
    double u0 = (d_lo - g.disparity_at_infinity) / g.focal_baseline;
    double u1 = (d_hi - g.disparity_at_infinity) / g.focal_baseline;
    if (u0 > u1) std::swap(u0, u1);
    if (u1 < 0) return out;  // every disparity lies beyond infinity
    out.near = std::isinf(u1) ? 0.0 : (u1 == 0 ? kInf : 1.0 / u1);
    out.far = u0 <= 0 ? kInf : 1.0 / u0;
    return out;
}

DepthRange refocus_depth_of_field(const LightFieldGeometry& g, double focus_disparity, double aperture_radius,
                                     double coc_px) {
    if (!(aperture_radius >= 0) || !(coc_px > 0) || std::isnan(focus_disparity)) return {};
    const double half = aperture_radius == 0 ? kInf : coc_px / aperture_radius;  // disparity half-width
    return depth_interval(g, focus_disparity - half, focus_disparity + half);
}

Status LightField::validate() const {
    auto name = [&](std::size_t i) {
        if (i < sources.size() && !sources[i].empty()) return "'" + sources[i] + "'";
        return "view (" + std::to_string(i / std::size_t(cols > 0 ? cols : 1)) + ", " +
               std::to_string(i % std::size_t(cols > 0 ? cols : 1)) + ")";
    };
    if (rows <= 0 || cols <= 0) return Status::error("light field: empty view grid");
    if (views.size() != std::size_t(rows) * std::size_t(cols))
        return Status::error("light field: " + std::to_string(views.size()) + " views for a " + std::to_string(rows) +
                             " x " + std::to_string(cols) + " grid");
    if (center_row < 0 || center_row >= rows || center_col < 0 || center_col >= cols)
        return Status::error("light field: central view (" + std::to_string(center_row) + ", " +
                             std::to_string(center_col) + ") is outside the " + std::to_string(rows) + " x " +
                             std::to_string(cols) + " grid");
    if (!std::isfinite(geometry.disparity_at_infinity))
        return Status::error("light field: disparity_at_infinity must be finite");
    if (!std::isfinite(geometry.focal_baseline) || geometry.focal_baseline == 0)
        return Status::error("light field: focal_baseline must be finite and non-zero");
    const Image& ref = views.front();
    if (ref.data_window().empty()) return Status::error("light field: " + name(0) + " has no pixels");
    for (std::size_t i = 0; i < views.size(); ++i) {
        const Image& v = views[i];
        if (v.width() != ref.width() || v.height() != ref.height())
            return Status::error("light field: " + name(i) + " is " + std::to_string(v.width()) + "x" +
                                 std::to_string(v.height()) + ", the other views are " + std::to_string(ref.width()) +
                                 "x" + std::to_string(ref.height()));
        if (!(v.data_window() == ref.data_window()))
            return Status::error("light field: " + name(i) + " has data window " + to_string(v.data_window()) +
                                 ", " + name(0) + " has " + to_string(ref.data_window()));
        if (v.nchannels() != ref.nchannels())
            return Status::error("light field: " + name(i) + " has " + std::to_string(v.nchannels()) +
                                 " channels, " + name(0) + " has " + std::to_string(ref.nchannels()));
        for (int c = 0; c < v.nchannels(); ++c) {
            if (v.channel(c).name != ref.channel(c).name)
                return Status::error("light field: " + name(i) + " channel " + std::to_string(c) + " is '" +
                                     v.channel(c).name + "', " + name(0) + " has '" + ref.channel(c).name + "'");
            if (!v.plane(c))
                return Status::error("light field: " + name(i) + " channel '" + v.channel(c).name +
                                     "' is an integer channel; views must be float");
        }
    }
    return {};
}

int LightField::aperture_views(double r) const {
    int n = 0;
    for (int row = 0; row < rows; ++row)
        for (int col = 0; col < cols; ++col) {
            const double du = col - center_col, dv = row - center_row;
            if (du * du + dv * dv <= r * r + 1e-9) ++n;
        }
    return n;
}

const char* to_string(LightFieldFilter f) { return f == LightFieldFilter::Bilinear ? "bilinear" : "bicubic"; }

Result<LightFieldFilter> parse_lightfield_filter(const std::string& name) {
    if (name == "bicubic" || name == "catmull-rom") return LightFieldFilter::Bicubic;
    if (name == "bilinear") return LightFieldFilter::Bilinear;
    return Status::error("unknown filter '" + name + "' (expected bicubic or bilinear)");
}

}  // namespace gdof
