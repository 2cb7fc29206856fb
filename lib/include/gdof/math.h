// Minimal double-precision vector/matrix types for camera maths.
// Matrices follow the OpenEXR/Imath convention: row vectors, p' = p * M,
// translation in the last row (m[3][0..2]). This is how EXR stores
// worldToCamera / worldToNDC, so attributes map over without transposes.
#pragma once

#include <array>
#include <cmath>
#include <optional>

#include "gdof/export.h"

namespace gdof {

struct Vec3 {
    double x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr bool operator==(const Vec3&) const = default;
};
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return a / length(a); }

struct Mat44 {
    std::array<std::array<double, 4>, 4> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};

    static Mat44 identity() { return {}; }
    static Mat44 from_row_major(const double* v16) {
        Mat44 r;
        for (int i = 0; i < 16; ++i) r.m[i / 4][i % 4] = v16[i];
        return r;
    }
    // Row-vector product: (p, 1) * M, then divided by w.
    Vec3 transform_point(const Vec3& p) const {
        double x = p.x * m[0][0] + p.y * m[1][0] + p.z * m[2][0] + m[3][0];
        double y = p.x * m[0][1] + p.y * m[1][1] + p.z * m[2][1] + m[3][1];
        double z = p.x * m[0][2] + p.y * m[1][2] + p.z * m[2][2] + m[3][2];
        double w = p.x * m[0][3] + p.y * m[1][3] + p.z * m[2][3] + m[3][3];
        return {x / w, y / w, z / w};
    }
    Vec3 transform_dir(const Vec3& d) const {
        return {d.x * m[0][0] + d.y * m[1][0] + d.z * m[2][0],
                d.x * m[0][1] + d.y * m[1][1] + d.z * m[2][1],
                d.x * m[0][2] + d.y * m[1][2] + d.z * m[2][2]};
    }
    Mat44 operator*(const Mat44& o) const {  // this then o (row vectors)
        Mat44 r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
                r.m[i][j] = s;
            }
        return r;
    }
    bool operator==(const Mat44&) const = default;
};

// General 4x4 inverse (Gauss-Jordan with partial pivoting); nullopt if singular.
GDOF_API std::optional<Mat44> inverse(const Mat44& a);

}  // namespace gdof
