// ApertureProfile: the shape's left and right edges row by row over
// v in [-1, 1], and their running integrals, so a filter spreading one span
// per image row gets each strip's average edges (exact area, anti-aliased
// top and bottom) from two look-ups instead of an inside test per pixel.
#include <algorithm>
#include <cmath>
#include <limits>

#include "aperture/aperture_internal.h"

namespace gdof {

namespace {

constexpr int kRows = 2048;     // table rows over v in [-1, 1]
constexpr int kScan = 64;       // samples per row to find the edges (the shapes are convex)
constexpr int kFineScan = 4096; // for a row thinner than that (near a vertex)
constexpr int kRefine = 24;     // bisection steps per edge

bool inside(const Aperture& a, double u, double v) { return aperture_detail::density(a, u, v, -1) > 0.0; }

// Between an outside point `out` and an inside point `in` on one row.
double edge(const Aperture& a, double v, double out, double in) {
    for (int k = 0; k < kRefine; ++k) {
        const double mid = 0.5 * (out + in);
        (inside(a, mid, v) ? in : out) = mid;
    }
    return 0.5 * (out + in);
}

}  // namespace

Result<ApertureProfile> ApertureProfile::create(const Aperture& a) {
    if (Status st = validate(a); !st) return st;
    if (a.kind == Aperture::Kind::Image)
        return Status::error("aperture profile: an image kernel has no span per row", StatusCode::InvalidArgument);
    ApertureProfile p;
    p.n_ = kRows;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    p.left_.assign(kRows, float(nan));
    p.right_.assign(kRows, float(nan));
    p.c_height_.assign(kRows + 1, 0.0);
    p.c_left_.assign(kRows + 1, 0.0);
    p.c_right_.assign(kRows + 1, 0.0);
    const double h = 2.0 / kRows, du = 2.0 / kScan;
    for (int i = 0; i < kRows; ++i) {
        const double v = -1.0 + (i + 0.5) * h;
        int first = -1, last = -1;
        for (int k = 0; k <= kScan; ++k)
            if (inside(a, -1.0 + k * du, v)) {
                if (first < 0) first = k;
                last = k;
            }
        double l = 0.0, r = 0.0;
        bool any = first >= 0;
        if (any) {
            l = first == 0 ? -1.0 : edge(a, v, -1.0 + (first - 1) * du, -1.0 + first * du);
            r = last == kScan ? 1.0 : edge(a, v, -1.0 + (last + 1) * du, -1.0 + last * du);
        } else {
            // A row thinner than the scan step (a polygon's vertex): once
            // more at a finer step.
            const double fine = 2.0 / kFineScan;
            for (int k = 0; k <= kFineScan && !any; ++k) {
                const double u = -1.0 + k * fine;
                if (inside(a, u, v)) {
                    any = true;
                    l = k == 0 ? -1.0 : edge(a, v, u - fine, u);
                    double end = u;  // the last inside point of the fine scan
                    while (end + fine <= 1.0 && inside(a, end + fine, v)) end += fine;
                    r = end + fine > 1.0 ? 1.0 : edge(a, v, end + fine, end);
                }
            }
        }
        p.c_height_[std::size_t(i) + 1] = p.c_height_[std::size_t(i)] + (any ? h : 0.0);
        p.c_left_[std::size_t(i) + 1] = p.c_left_[std::size_t(i)] + (any ? h * l : 0.0);
        p.c_right_[std::size_t(i) + 1] = p.c_right_[std::size_t(i)] + (any ? h * r : 0.0);
        if (any) {
            p.left_[std::size_t(i)] = float(l);
            p.right_[std::size_t(i)] = float(r);
            p.area_ += h * (r - l);
        }
    }
    return p;
}

double ApertureProfile::integral(const std::vector<double>& c, double v) const {
    const double t = (v + 1.0) * 0.5 * n_;
    if (!(t > 0.0)) return 0.0;
    if (t >= n_) return c[std::size_t(n_)];
    const int i = int(t);
    return c[std::size_t(i)] + (t - i) * (c[std::size_t(i) + 1] - c[std::size_t(i)]);
}

bool ApertureProfile::strip(double v0, double v1, double& height, double& left, double& right) const {
    height = integral(c_height_, v1) - integral(c_height_, v0);
    if (!(height > 1e-12)) return false;
    left = (integral(c_left_, v1) - integral(c_left_, v0)) / height;
    right = (integral(c_right_, v1) - integral(c_right_, v0)) / height;
    return right > left;
}

bool ApertureProfile::row(double v, double& left, double& right) const {
    const double t = (v + 1.0) * 0.5 * n_ - 0.5;
    if (!(t > -0.5 && t < n_ - 0.5)) return false;
    const int i = std::clamp(int(std::floor(t)), 0, n_ - 1), j = std::min(i + 1, n_ - 1);
    const double f = std::clamp(t - i, 0.0, 1.0);
    const float li = left_[std::size_t(i)], lj = left_[std::size_t(j)];
    const float ri = right_[std::size_t(i)], rj = right_[std::size_t(j)];
    const bool hi = std::isfinite(li), hj = std::isfinite(lj);
    if (!hi && !hj) return false;
    if (hi && hj) {
        left = (1 - f) * li + f * lj;
        right = (1 - f) * ri + f * rj;
    } else if (hi ? f < 0.5 : f >= 0.5) {
        left = hi ? li : lj;
        right = hi ? ri : rj;
    } else {
        return false;
    }
    return right > left;
}

}  // namespace gdof
