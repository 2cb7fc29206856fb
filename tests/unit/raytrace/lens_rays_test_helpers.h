// Cameras, fields and polyline helpers shared by the lens-ray tests.
#pragma once

#include <gtest/gtest.h>

#include "gdof/lens_rays.h"

namespace gdof::test {

inline Camera make_camera(double focal_mm = 50.0, int w = 320, int h = 240, Vec3 pos = {0, 0, 0}, Vec3 at = {0, 0, 1}) {
    CameraDesc d;
    d.position = pos;
    d.look_at = at;
    d.up = {0, 1, 0};
    d.focal_length_mm = focal_mm;
    d.sensor_width_mm = 36.0;
    d.display_window = Roi{0, 0, w, h};
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return *c;
}

inline ThinLens make_lens(const Camera& cam, double f = 50.0, double n = 2.8, double s = 2.0) {
    ThinLens l;
    l.focal_length_mm = f;
    l.f_number = n;
    l.focus_distance = s;
    l.sensor_width_mm = 36.0;
    l.image_width_px = cam.image_width();
    return l;
}

inline BlurField parse_ok(const char* text) {
    auto r = BlurField::parse(text);
    EXPECT_TRUE(r) << r.message();
    return r ? *r : BlurField();
}

inline NonlinearCamera make_nl(const Camera& cam, const BlurField& f, NonlinearCameraOptions o = {}) {
    o.depth_min = 0.01;
    o.depth_max = 1000.0;
    auto r = NonlinearCamera::create(cam, f, o);
    EXPECT_TRUE(r) << r.message();
    return *r;
}

inline double depth_of(const Camera& cam, const Vec3& p) { return dot(p - cam.position(), cam.forward()); }

// The polyline's point at a depth.
inline Vec3 polyline_at(const Camera& cam, const PolylineRay& r, double z) {
    const std::size_t n = r.points.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
        if (z <= r.depth[i + 1]) {
            const double t = (z - r.depth[i]) / (r.depth[i + 1] - r.depth[i]);
            return r.points[i] + (r.points[i + 1] - r.points[i]) * t;
        }
    const double per_t = dot(r.far_direction, cam.forward());
    return r.points[n - 1] + r.far_direction * ((z - r.depth[n - 1]) / per_t);
}

inline double dist(const Vec3& a, const Vec3& b) { return length(a - b); }

}  // namespace gdof::test
