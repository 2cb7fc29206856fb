// Thin-lens circle of confusion, depth-of-field limits and hyperfocal distance.
#include <cmath>
#include <limits>
#include <string>

#include "gdof/camera.h"

namespace gdof {

namespace {

Status positive_finite(const char* name, double v, const char* unit) {
    if (std::isnan(v)) return Status::error(std::string("thin lens ") + name + ": is NaN");
    if (!std::isfinite(v)) return Status::error(std::string("thin lens ") + name + ": must be finite, got " + std::to_string(v));
    if (v <= 0)
        return Status::error(std::string("thin lens ") + name + ": must be > 0" + unit + ", got " + std::to_string(v));
    return {};
}

}  // namespace

Status ThinLens::validate() const {
    if (auto s = positive_finite("focal_length_mm", focal_length_mm, " mm"); !s) return s;
    if (auto s = positive_finite("f_number", f_number, ""); !s) return s;
    if (auto s = positive_finite("focus_distance", focus_distance, " scene units"); !s) return s;
    if (auto s = positive_finite("sensor_width_mm", sensor_width_mm, " mm"); !s) return s;
    if (auto s = positive_finite("image_width_px", image_width_px, " px"); !s) return s;
    if (auto s = positive_finite("scene_unit_mm", scene_unit_mm, " mm per scene unit"); !s) return s;
    if (!(focus_distance * scene_unit_mm > focal_length_mm))
        return Status::error("thin lens focus_distance: must be beyond the focal length (" +
                             std::to_string(focal_length_mm) + " mm = " +
                             std::to_string(focal_length_mm / scene_unit_mm) + " scene units), got " +
                             std::to_string(focus_distance));
    return {};
}

double ThinLens::coc_diameter_mm(double depth) const {
    if (std::isnan(depth)) return std::numeric_limits<double>::quiet_NaN();
    if (depth <= 0) return std::numeric_limits<double>::infinity();
    const double f = focal_length_mm;
    const double s = focus_distance * scene_unit_mm;
    const double aperture = f / f_number;  // aperture diameter, mm
    if (std::isinf(depth)) return aperture * f / (s - f);
    const double z = depth * scene_unit_mm;
    return aperture * f * std::fabs(z - s) / (z * (s - f));
}

double ThinLens::coc_radius_px(double depth) const { return 0.5 * coc_diameter_mm(depth) * pixels_per_mm(); }

double ThinLens::coc_radius_px_at_infinity() const {
    return coc_radius_px(std::numeric_limits<double>::infinity());
}

double ThinLens::hyperfocal_distance(double coc_radius_px) const {
    const double c = acceptable_coc_mm(coc_radius_px);
    if (!(c > 0)) return std::numeric_limits<double>::infinity();
    const double f = focal_length_mm;
    return (f * f / (f_number * c) + f) / scene_unit_mm;
}

ThinLens::DofLimits ThinLens::dof_limits(double coc_radius_px) const {
    const double c = acceptable_coc_mm(coc_radius_px);
    if (!(c > 0)) return {focus_distance, focus_distance};
    const double f = focal_length_mm;
    const double s = focus_distance * scene_unit_mm;
    const double hp = f * f / (f_number * c);  // H - f, mm
    DofLimits d;
    d.near = s * hp / (hp + (s - f)) / scene_unit_mm;
    d.far = (s - f) < hp ? s * hp / (hp - (s - f)) / scene_unit_mm : std::numeric_limits<double>::infinity();
    return d;
}

}  // namespace gdof
