// Camera: projection between world points and (pixel, depth), central rays.
// Internally every camera works in a camera space with +z forward ("internal"
// space); a NegZ camera only differs in the worldToCamera matrix it reports.
#include "gdof/camera.h"

#include <cmath>
#include <numbers>
#include <limits>
#include <string>

namespace gdof {

namespace {

// diag(1, 1, -1, 1): flips the camera z axis (self-inverse).
Mat44 flip_z() {
    Mat44 f;
    f.m[2][2] = -1.0;
    return f;
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const Mat44& m) {
    for (const auto& r : m.m)
        for (double v : r)
            if (!std::isfinite(v)) return false;
    return true;
}

// Homogeneous NDC x, y numerators and w of an internal camera point.
struct Hom {
    double x, y, w;
};
inline Hom hom(const Mat44& m, double x, double y, double z) {
    return {x * m.m[0][0] + y * m.m[1][0] + z * m.m[2][0] + m.m[3][0],
            x * m.m[0][1] + y * m.m[1][1] + z * m.m[2][1] + m.m[3][1],
            x * m.m[0][3] + y * m.m[1][3] + z * m.m[2][3] + m.m[3][3]};
}

}  // namespace

const char* to_string(ForwardAxis a) {
    switch (a) {
        case ForwardAxis::Auto: return "auto";
        case ForwardAxis::PosZ: return "+z";
        case ForwardAxis::NegZ: return "-z";
    }
    return "?";
}

const char* to_string(Projection p) { return p == Projection::Perspective ? "perspective" : "orthographic"; }

Status Camera::init(const Mat44& w2c_file, const Mat44& w2ndc, const Roi& display, ForwardAxis axis) {
    if (display.empty()) return Status::error("camera: display window " + to_string(display) + " is empty");
    if (!finite(w2c_file)) return Status::error("camera: worldToCamera has NaN or infinite entries");
    if (!finite(w2ndc)) return Status::error("camera: worldToNDC has NaN or infinite entries");
    auto c2w = inverse(w2c_file);
    if (!c2w) return Status::error("camera: worldToCamera is singular");
    const Mat44 cam_to_ndc = *c2w * w2ndc;  // file camera space -> NDC

    const double wscale = std::fabs(cam_to_ndc.m[0][3]) + std::fabs(cam_to_ndc.m[1][3]) +
                          std::fabs(cam_to_ndc.m[2][3]) + std::fabs(cam_to_ndc.m[3][3]);
    if (!(wscale > 0)) return Status::error("camera: worldToNDC has a zero w column");
    const bool ortho = std::fabs(cam_to_ndc.m[0][3]) + std::fabs(cam_to_ndc.m[1][3]) +
                           std::fabs(cam_to_ndc.m[2][3]) <=
                       1e-12 * wscale;

    if (axis == ForwardAxis::Auto) {
        axis = ForwardAxis::PosZ;
        if (!ortho) {
            // A point up and to the right projects right of the centre only
            // when it lies in front of the camera (x right, y up in both conventions).
            Hom c = hom(cam_to_ndc, 0, 0, 1), p = hom(cam_to_ndc, 1, 1, 1);
            const double ncx = c.x / c.w, npx = p.x / p.w;
            if (std::isfinite(ncx) && std::isfinite(npx) && npx < ncx) axis = ForwardAxis::NegZ;
        }
    }
    const Mat44 flip = axis == ForwardAxis::NegZ ? flip_z() : Mat44::identity();

    w2c_ = w2c_file;
    w2ndc_ = w2ndc;
    c2w_ = *c2w;
    w2ci_ = w2c_file * flip;
    ci2w_ = flip * *c2w;
    ci2ndc_ = flip * cam_to_ndc;
    display_ = display;
    axis_ = axis;
    proj_ = ortho ? Projection::Orthographic : Projection::Perspective;

    position_ = ci2w_.transform_point({0, 0, 0});
    fwd_ = normalize(ci2w_.transform_dir({0, 0, 1}));
    right_ = normalize(ci2w_.transform_dir({1, 0, 0}));
    up_ = normalize(ci2w_.transform_dir({0, 1, 0}));

    // d(pixel x)/d(x/z) on the axis at depth 1.
    const Mat44& m = ci2ndc_;
    const Hom c = hom(m, 0, 0, 1);
    fx_ = display_.width() * (m.m[0][0] * c.w - c.x * m.m[0][3]) / (c.w * c.w);
    if (!std::isfinite(fx_) || fx_ == 0) return Status::error("camera: worldToNDC is degenerate (zero horizontal scale)");
    // The 2x2 system used by unproject must be solvable.
    const double det = (m.m[0][0] - 0.5 * m.m[0][3]) * (m.m[1][1] - 0.5 * m.m[1][3]) -
                       (m.m[1][0] - 0.5 * m.m[1][3]) * (m.m[0][1] - 0.5 * m.m[0][3]);
    if (!(std::fabs(det) > 0)) return Status::error("camera: worldToNDC is degenerate (cannot invert the projection)");
    return {};
}

const char* to_string(Handedness h) { return h == Handedness::Left ? "left" : "right"; }

Result<Camera> Camera::create(const CameraDesc& d) {
    if (!finite(d.position)) return Status::error("camera position: must be finite");
    if (!finite(d.look_at)) return Status::error("camera look_at: must be finite");
    if (!finite(d.up)) return Status::error("camera up: must be finite");
    const Vec3 dir = d.look_at - d.position;
    if (!(length(dir) > 0)) return Status::error("camera look_at: must differ from the position");
    const Vec3 f = normalize(dir);
    // Image right: forward x up in a right-handed world, up x forward in a left-handed one.
    const bool left = d.handedness == Handedness::Left;
    const Vec3 rc = left ? cross(d.up, f) : cross(f, d.up);
    if (!(length(rc) > 1e-12 * length(d.up)) || !(length(d.up) > 0))
        return Status::error("camera up: must not be zero or parallel to the viewing direction");
    const Vec3 r = normalize(rc);
    const Vec3 u = left ? cross(f, r) : cross(r, f);
    if (d.display_window.empty())
        return Status::error("camera display_window: " + to_string(d.display_window) + " is empty");
    if (d.forward_axis == ForwardAxis::Auto)
        return Status::error("camera forward_axis: must be +z or -z for an explicit camera");

    Mat44 w2ci;
    w2ci.m[0][0] = r.x, w2ci.m[1][0] = r.y, w2ci.m[2][0] = r.z, w2ci.m[3][0] = -dot(d.position, r);
    w2ci.m[0][1] = u.x, w2ci.m[1][1] = u.y, w2ci.m[2][1] = u.z, w2ci.m[3][1] = -dot(d.position, u);
    w2ci.m[0][2] = f.x, w2ci.m[1][2] = f.y, w2ci.m[2][2] = f.z, w2ci.m[3][2] = -dot(d.position, f);

    const double W = d.display_window.width(), H = d.display_window.height();
    Mat44 p;  // internal camera -> NDC
    LensInfo lens;
    lens.scene_unit_mm = d.scene_unit_mm;
    lens.f_number = d.f_number;
    lens.focus_distance = d.focus_distance;
    if (!(d.scene_unit_mm > 0) || !std::isfinite(d.scene_unit_mm))
        return Status::error("camera scene_unit_mm: must be > 0, got " + std::to_string(d.scene_unit_mm));
    if (d.projection == Projection::Perspective) {
        double a;  // focal length / sensor width
        if (d.hfov_deg != 0) {
            if (!(d.hfov_deg > 0 && d.hfov_deg < 180))
                return Status::error("camera hfov_deg: must be in (0, 180), got " + std::to_string(d.hfov_deg));
            if (!(d.sensor_width_mm > 0) || !std::isfinite(d.sensor_width_mm))
                return Status::error("camera sensor_width_mm: must be > 0, got " + std::to_string(d.sensor_width_mm));
            a = 0.5 / std::tan(0.5 * d.hfov_deg * std::numbers::pi / 180.0);
            lens.sensor_width_mm = d.sensor_width_mm;
            lens.focal_length_mm = a * d.sensor_width_mm;
        } else {
            if (!(d.focal_length_mm > 0) || !std::isfinite(d.focal_length_mm))
                return Status::error("camera focal_length_mm: must be > 0, got " + std::to_string(d.focal_length_mm));
            if (!(d.sensor_width_mm > 0) || !std::isfinite(d.sensor_width_mm))
                return Status::error("camera sensor_width_mm: must be > 0, got " + std::to_string(d.sensor_width_mm));
            a = d.focal_length_mm / d.sensor_width_mm;
            lens.sensor_width_mm = d.sensor_width_mm;
            lens.focal_length_mm = d.focal_length_mm;
        }
        p.m[0][0] = a;
        p.m[2][0] = 0.5;
        p.m[1][1] = -a * W / H;
        p.m[2][1] = 0.5;
        p.m[2][2] = 0.0;  // NDC z = 1 / depth
        p.m[3][2] = 1.0;
        p.m[2][3] = 1.0;  // w = depth
        p.m[3][3] = 0.0;
    } else {
        if (!(d.ortho_width > 0) || !std::isfinite(d.ortho_width))
            return Status::error("camera ortho_width: must be > 0 for an orthographic camera, got " +
                                 std::to_string(d.ortho_width));
        p.m[0][0] = 1.0 / d.ortho_width;
        p.m[3][0] = 0.5;
        p.m[1][1] = -(W / H) / d.ortho_width;
        p.m[3][1] = 0.5;
    }
    const Mat44 w2ndc = w2ci * p;
    const Mat44 w2c_file = d.forward_axis == ForwardAxis::NegZ ? w2ci * flip_z() : w2ci;
    Camera cam;
    if (auto s = cam.init(w2c_file, w2ndc, d.display_window, d.forward_axis); !s) return s;
    cam.lens_ = lens;
    return cam;
}

Result<Camera> Camera::from_matrices(const Mat44& world_to_camera, const Mat44& world_to_ndc, const Roi& display,
                                     ForwardAxis axis, const LensInfo& lens) {
    Camera cam;
    if (auto s = cam.init(world_to_camera, world_to_ndc, display, axis); !s) return s;
    cam.lens_ = lens;
    return cam;
}

PixelDepth Camera::project(const Vec3& p) const {
    const Mat44& a = w2ci_;
    const double depth = p.x * a.m[0][2] + p.y * a.m[1][2] + p.z * a.m[2][2] + a.m[3][2];
    const double cx = p.x * a.m[0][0] + p.y * a.m[1][0] + p.z * a.m[2][0] + a.m[3][0];
    const double cy = p.x * a.m[0][1] + p.y * a.m[1][1] + p.z * a.m[2][1] + a.m[3][1];
    const Hom h = hom(ci2ndc_, cx, cy, depth);
    return {display_.x0 + (h.x / h.w) * display_.width(), display_.y0 + (h.y / h.w) * display_.height(), depth};
}

void Camera::project(std::span<const Vec3> world, std::span<PixelDepth> out) const {
    if (world.size() != out.size()) return;
    for (std::size_t i = 0; i < world.size(); ++i) out[i] = project(world[i]);
}

Vec3 Camera::unproject(double px, double py, double depth) const {
    const double nx = (px - display_.x0) / display_.width();
    const double ny = (py - display_.y0) / display_.height();
    const Mat44& m = ci2ndc_;
    const double z = depth;
    // nx * w = num_x, ny * w = num_y, linear in the camera x, y for a given z.
    const double a11 = m.m[0][0] - nx * m.m[0][3], a12 = m.m[1][0] - nx * m.m[1][3];
    const double a21 = m.m[0][1] - ny * m.m[0][3], a22 = m.m[1][1] - ny * m.m[1][3];
    const double b1 = nx * (z * m.m[2][3] + m.m[3][3]) - (z * m.m[2][0] + m.m[3][0]);
    const double b2 = ny * (z * m.m[2][3] + m.m[3][3]) - (z * m.m[2][1] + m.m[3][1]);
    const double det = a11 * a22 - a12 * a21;
    const double x = (b1 * a22 - a12 * b2) / det;
    const double y = (a11 * b2 - a21 * b1) / det;
    const Mat44& c = ci2w_;
    return {x * c.m[0][0] + y * c.m[1][0] + z * c.m[2][0] + c.m[3][0],
            x * c.m[0][1] + y * c.m[1][1] + z * c.m[2][1] + c.m[3][1],
            x * c.m[0][2] + y * c.m[1][2] + z * c.m[2][2] + c.m[3][2]};
}

DepthLine Camera::depth_line(double px, double py) const {
    const Vec3 o = unproject(px, py, 0.0);
    const Vec3 one = unproject(px, py, 1.0);
    return {o, one - o};
}

CameraRay Camera::central_ray(double px, double py) const {
    const DepthLine l = depth_line(px, py);
    const double len = length(l.per_depth);
    return {l.origin, l.per_depth / len, 1.0 / len};
}

double Camera::pixel_footprint(double depth) const {
    const double cx = display_.x0 + 0.5 * display_.width(), cy = display_.y0 + 0.5 * display_.height();
    return length(unproject(cx + 0.5, cy, depth) - unproject(cx - 0.5, cy, depth));
}

double Camera::hfov_deg() const {
    return 2.0 * std::atan(0.5 * display_.width() / std::fabs(fx_)) * 180.0 / std::numbers::pi;
}

Result<ThinLens> Camera::thin_lens() const {
    ThinLens t;
    if (std::isnan(lens_.focal_length_mm)) return Status::error("camera lens: focal length unknown (focalLength)");
    if (std::isnan(lens_.f_number)) return Status::error("camera lens: f-number unknown (fNumber / aperture)");
    if (std::isnan(lens_.focus_distance))
        return Status::error("camera lens: focus distance unknown (focusDistance / focus)");
    if (std::isnan(lens_.sensor_width_mm)) return Status::error("camera lens: sensor width unknown (sensorWidth)");
    t.focal_length_mm = lens_.focal_length_mm;
    t.f_number = lens_.f_number;
    t.focus_distance = lens_.focus_distance;
    t.sensor_width_mm = lens_.sensor_width_mm;
    t.scene_unit_mm = lens_.scene_unit_mm;
    t.image_width_px = image_width();
    if (auto s = t.validate(); !s) return s;
    return t;
}

}  // namespace gdof
