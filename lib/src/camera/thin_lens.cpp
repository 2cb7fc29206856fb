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
    // Each value may be fine on its own while their combination overflows
    // or underflows a double (f/N with N = 1e-310, s in mm = 1e301 * 1000):
    // then the CoC formula would give NaN (inf * 0, inf / inf). Every CoC is
    // finite-or-inf and never NaN when the focus distance in mm and the CoC
    // at infinity, in mm and in pixels, are positive finite numbers.
    const double s_mm = focus_distance * scene_unit_mm;
    const double c_inf = f_number > 0 ? focal_length_mm / f_number * focal_length_mm / (s_mm - focal_length_mm) : 0.0;
    if (!std::isfinite(s_mm) || !(c_inf > 0) || !std::isfinite(c_inf) || !(c_inf * pixels_per_mm() > 0) ||
        !std::isfinite(c_inf * pixels_per_mm()))
        return Status::error("thin lens focal_length_mm, f_number, focus_distance, scene_unit_mm, sensor_width_mm: "
                             "out of range together (focus distance " + std::to_string(s_mm) +
                             " mm, CoC at infinity " + std::to_string(c_inf) +
                             " mm must be positive and finite in mm and in pixels)");
    return {};
}

double ThinLens::coc_diameter_mm(double depth) const {
    if (std::isnan(depth)) return std::numeric_limits<double>::quiet_NaN();
    if (depth <= 0) return std::numeric_limits<double>::infinity();
    const double f = focal_length_mm;
    const double s = focus_distance * scene_unit_mm;
    const double aperture = f / f_number;  // aperture diameter, mm
    const double c_inf = aperture * f / (s - f);
    const double z = depth * scene_unit_mm;
    if (std::isinf(z)) return c_inf;  // also a finite depth whose mm overflow
    // c_inf * |z - s| / z, grouped so that huge depths do not overflow the
    // numerator and the denominator together (inf / inf = NaN); exactly 0 at
    // the focus distance (not c_inf * 0 = NaN for an infinite c_inf).
    const double rel = std::fabs(z - s) / z;
    return rel == 0 ? 0.0 : c_inf * rel;
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
    // s hp / (hp + (s - f)) written as s / (1 + (s - f) / hp): the same limits
    // without overflowing s * hp (a tiny acceptable CoC makes hp huge, even
    // +inf: then both limits are the focus distance).
    const double q = (s - f) / hp;
    DofLimits d;
    d.near = s / (1.0 + q) / scene_unit_mm;
    d.far = q < 1.0 ? s / (1.0 - q) / scene_unit_mm : std::numeric_limits<double>::infinity();
    return d;
}

}  // namespace gdof
