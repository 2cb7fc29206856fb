// Camera <-> EXR attributes (worldToCamera, worldToNDC, lens attributes).
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

#include "gdof/camera.h"

namespace gdof {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// First attribute of the list present as a number; NaN if none.
double first_float(const Metadata& md, std::initializer_list<const char*> names, std::string* found = nullptr) {
    for (const char* n : names)
        if (auto v = md.get_float(n)) {
            if (found) *found = n;
            return *v;
        }
    return kNaN;
}

}  // namespace

Result<Camera> Camera::from_metadata(const Metadata& md, const Roi& display, const CameraReadOptions& opts) {
    // Units first: focus (OpenEXR standard) is in metres.
    double unit = opts.scene_unit_mm;
    if (std::isnan(unit)) unit = first_float(md, {"gdof:sceneUnitMm"});
    if (std::isnan(unit)) unit = 1000.0;
    if (!(unit > 0) || !std::isfinite(unit))
        return Status::error("camera: scene_unit_mm must be > 0, got " + std::to_string(unit));

    LensInfo lens;
    lens.scene_unit_mm = unit;
    lens.focal_length_mm = first_float(md, {"focalLength", "gdof:focalLength"});
    lens.sensor_width_mm = first_float(md, {"sensorWidth", "gdof:sensorWidth"});
    lens.f_number = first_float(md, {"fNumber", "aperture"});
    lens.focus_distance = first_float(md, {"focusDistance"});
    if (std::isnan(lens.focus_distance)) {
        const double metres = first_float(md, {"focus"});
        if (!std::isnan(metres)) lens.focus_distance = metres * 1000.0 / unit;
    }

    ForwardAxis axis = opts.forward_axis;
    if (axis == ForwardAxis::Auto) {
        if (auto s = md.get_string("gdof:forwardAxis")) {
            if (*s == "+z") axis = ForwardAxis::PosZ;
            else if (*s == "-z") axis = ForwardAxis::NegZ;
            else return Status::error("camera attribute gdof:forwardAxis: must be \"+z\" or \"-z\", got \"" + *s + "\"");
        }
    }

    auto w2c = md.get_matrix("worldToCamera");
    auto w2ndc = md.get_matrix("worldToNDC");
    if (!w2c && !w2ndc) return Status::error("camera: no worldToCamera / worldToNDC attributes");
    if (!w2c) return Status::error("camera: worldToNDC present but worldToCamera missing (needed for depth)");

    if (!w2ndc) {
        // Perspective, centred, square pixels, from the lens attributes.
        if (std::isnan(lens.focal_length_mm))
            return Status::error("camera: worldToNDC missing and no focalLength attribute to build the projection");
        double sw = std::isnan(lens.sensor_width_mm) ? opts.default_sensor_width_mm : lens.sensor_width_mm;
        if (!(sw > 0) || !(lens.focal_length_mm > 0))
            return Status::error("camera: focalLength and sensor width must be > 0");
        lens.sensor_width_mm = sw;
        if (axis == ForwardAxis::Auto) axis = ForwardAxis::PosZ;
        const Mat44 flip = [&] {
            Mat44 f;
            if (axis == ForwardAxis::NegZ) f.m[2][2] = -1.0;
            return f;
        }();
        const double a = lens.focal_length_mm / sw;
        const double W = display.width(), H = display.height();
        if (display.empty()) return Status::error("camera: display window " + to_string(display) + " is empty");
        Mat44 p;
        p.m[0][0] = a;
        p.m[2][0] = 0.5;
        p.m[1][1] = -a * W / H;
        p.m[2][1] = 0.5;
        p.m[2][2] = 0.0;
        p.m[3][2] = 1.0;
        p.m[2][3] = 1.0;
        p.m[3][3] = 0.0;
        // file camera -> internal (flip) -> NDC
        w2ndc = *w2c * flip * p;
    }
    auto cam = from_matrices(*w2c, *w2ndc, display, axis, lens);
    if (!cam) return cam.status().prefix("reading camera attributes");
    return cam;
}

void Camera::to_metadata(Metadata& md) const {
    md.set_matrix("worldToCamera", w2c_);
    md.set_matrix("worldToNDC", w2ndc_);
    md.set_string("gdof:forwardAxis", to_string(axis_));
    md.set_float("gdof:sceneUnitMm", lens_.scene_unit_mm);
    if (std::isfinite(lens_.focal_length_mm)) md.set_float("focalLength", lens_.focal_length_mm);
    if (std::isfinite(lens_.sensor_width_mm)) md.set_float("sensorWidth", lens_.sensor_width_mm);
    if (std::isfinite(lens_.f_number)) {
        md.set_float("fNumber", lens_.f_number);
        md.set_float("aperture", lens_.f_number);
    }
    if (std::isfinite(lens_.focus_distance)) {
        md.set_float("focusDistance", lens_.focus_distance);
        md.set_float("focus", lens_.focus_distance * lens_.scene_unit_mm / 1000.0);
    }
}

}  // namespace gdof
