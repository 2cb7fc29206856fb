// The bokeh filter's point-spread function (spread_planes) against
// independent references: the analytic disc, the ray tracer's own polygon
// sampler (ApertureShape) for where a hexagon's corners point, an image
// kernel resampled here by plain bilinear look-ups, and conservation of the
// highlight's energy.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gdof/bokeh.h"
#include "gdof/lens_rays.h"

using namespace gdof;

namespace {

struct Psf {
    int size = 0;
    std::vector<float> planes;  // R, G, B, A
    float at(int c, int x, int y) const {
        return planes[std::size_t(c) * std::size_t(size) * std::size_t(size) + std::size_t(y) * std::size_t(size) + std::size_t(x)];
    }
};

// One point of value `v` (R, G, B) at the centre of an opaque black square,
// every pixel blurred by R.
Psf point_spread(const Aperture& ap, double R, int size, float v = 1000.0f, int nthreads = 0) {
    Psf p;
    p.size = size;
    const std::size_t n = std::size_t(size) * std::size_t(size);
    p.planes.assign(4 * n, 0.0f);
    const std::size_t centre = std::size_t(size / 2) * std::size_t(size) + std::size_t(size / 2);
    for (int c = 0; c < 3; ++c) p.planes[std::size_t(c) * n + centre] = v;
    std::fill(p.planes.begin() + std::ptrdiff_t(3 * n), p.planes.end(), 1.0f);
    std::vector<float> radius(n, float(R));
    auto f = BokehFilter::create(ap);
    EXPECT_TRUE(f) << f.message();
    const Roi win{0, 0, size, size};
    Exec e;
    e.nthreads = nthreads;
    Status st = spread_planes(ImageView::planar(p.planes.data(), 4, win), ConstImageView::planar(radius.data(), 1, win), *f,
                              win, e);
    EXPECT_TRUE(st) << st.message();
    return p;
}

double dist(const Psf& p, int x, int y) { return std::hypot(x + 0.5 - (p.size / 2 + 0.5), y + 0.5 - (p.size / 2 + 0.5)); }

}  // namespace

class bokeh_disc : public ::testing::TestWithParam<double> {};

TEST_P(bokeh_disc, IsTheDiscScaledToRAndKeepsTheEnergy) {
    const double R = GetParam();
    // Wide enough that the frame edge (which keeps the light in) is beyond
    // 2R: its normalisation would brighten what lies within R of it.
    const Psf p = point_spread(Aperture{}, R, int(4 * R) + 41);
    double total = 0, within = 0, lo = 1e30, hi = 0;
    for (int y = 0; y < p.size; ++y)
        for (int x = 0; x < p.size; ++x) {
            const double v = p.at(0, x, y), d = dist(p, x, y);
            total += v;
            if (d <= R + 1.5) within += v;
            if (d <= R - 1.5) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            // A constant image (the opaque black plane) stays constant.
            ASSERT_NEAR(p.at(3, x, y), 1.0, 1e-4) << x << "," << y;
        }
    EXPECT_NEAR(total, 1000.0, 1.0) << "energy conserved to 1e-3";
    EXPECT_GE(within / total, 0.98) << "support within R + 1.5 px";
    EXPECT_LE((hi - lo) / hi, 0.15) << "flat inside R - 1.5 px: " << lo << " .. " << hi;
    // Its level: the disc's area.
    EXPECT_NEAR(0.5 * (hi + lo), 1000.0 / (std::numbers::pi * R * R), 0.12 * 1000.0 / (std::numbers::pi * R * R));
}

INSTANTIATE_TEST_SUITE_P(bokeh, bokeh_disc, ::testing::Values(4.0, 12.0, 40.0));

// The polygon's corners: the angles where the PSF reaches farthest are where
// the ray tracer's ApertureShape::polygon(6, 15) puts its vertices (found by
// sampling it, u right and v up; image y runs down).
TEST(bokeh, HexagonCornersPointWhereTheRayTracersDo) {
    const double R = 30.0, rotation = 15.0;
    Aperture ap;
    ap.kind = Aperture::Kind::Polygon;
    ap.blades = 6;
    ap.rotation_deg = rotation;
    const Psf p = point_spread(ap, R, 101);

    auto shape = ApertureShape::polygon(6, rotation);
    ASSERT_TRUE(shape);
    // Vertex angles of the sampler: the farthest of many samples per sector.
    std::vector<double> vertex_angles;
    {
        std::vector<std::pair<double, double>> best(36, {0.0, 0.0});  // per 10-degree bin: radius, angle
        for (int i = 0; i < 200; ++i)
            for (int j = 0; j < 200; ++j) {
                const Vec2 s = shape->map({(i + 0.5) / 200.0, (j + 0.5) / 200.0});
                double a = std::atan2(s.y, s.x) * 180.0 / std::numbers::pi;
                if (a < 0) a += 360.0;
                auto& b = best[std::size_t(int(a / 10.0) % 36)];
                const double r = std::hypot(s.x, s.y);
                if (r > b.first) b = {r, a};
            }
        for (int k = 0; k < 36; ++k) {
            const auto& prev = best[std::size_t((k + 35) % 36)], &next = best[std::size_t((k + 1) % 36)];
            if (best[std::size_t(k)].first > prev.first && best[std::size_t(k)].first >= next.first && best[std::size_t(k)].first > 0.99)
                vertex_angles.push_back(best[std::size_t(k)].second);
        }
    }
    ASSERT_EQ(vertex_angles.size(), 6u);
    // The PSF's extent per direction (half of its plateau), 1-degree steps.
    const double level = 0.5 * p.at(0, 50, 50);
    auto extent = [&](double deg) {
        const double a = deg * std::numbers::pi / 180.0;
        double r = 0;
        for (double t = 0; t < 50; t += 0.05) {
            const double px = 50.5 + t * std::cos(a), py = 50.5 - t * std::sin(a);  // v up = -y
            if (p.at(0, int(px), int(py)) < level) break;
            r = t;
        }
        return r;
    };
    for (double va : vertex_angles) {
        // A corner is a local maximum of the extent within +-30 degrees.
        double best_deg = va, best_r = 0;
        for (double d = -25; d <= 25; d += 1) {
            const double r = extent(va + d);
            if (r > best_r) best_r = r, best_deg = va + d;
        }
        EXPECT_NEAR(best_deg, va, 4.0) << "corner at " << va << " degrees";
        EXPECT_NEAR(best_r, R, 1.5);
        // Between corners the edge is nearer: R cos(30 degrees).
        EXPECT_NEAR(extent(va + 30.0), R * std::cos(std::numbers::pi / 6), 1.5);
    }
}

// An image kernel: an asymmetric colour pattern is reproduced at R, channel
// by channel, against the kernel resampled to R (box-averaged over each pixel).
TEST(bokeh, ImageKernelIsReproducedAtR) {
    Aperture ap;
    ap.kind = Aperture::Kind::Image;
    ap.image = Image::with_channels({"R", "G", "B"}, Roi{0, 0, 24, 24});
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            // An "L" in red, a ring in green, a diagonal bar in blue.
            ap.image.at(0, x, y) = (x < 8 || y > 16) ? 1.0f : 0.0f;
            const double r = std::hypot(x - 11.5, y - 11.5);
            ap.image.at(1, x, y) = (r > 6 && r < 11) ? 1.0f : 0.0f;
            ap.image.at(2, x, y) = std::abs(x - y) < 4 ? 1.0f : 0.0f;
        }
    for (double R : {6.0, 12.0, 30.0}) {
        const int size = int(4 * R) + 21;
        const Psf p = point_spread(ap, R, size, 1000.0f);
        for (int c = 0; c < 3; ++c) {
            // Reference: the kernel at R, sampled at each pixel centre.
            double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0, total = 0;
            int n = 0;
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) {
                    // Its average over the pixel (4 x 4 nearest look-ups).
                    double ref = 0.0;
                    for (int sy = 0; sy < 4; ++sy)
                        for (int sx = 0; sx < 4; ++sx) {
                            const double u = (x + (sx + 0.5) / 4 - (size / 2 + 0.5)) / R;
                            const double v = -(y + (sy + 0.5) / 4 - (size / 2 + 0.5)) / R;
                            // Kernel pixel coordinates (fitted into [-1, 1]^2, rows down).
                            const double kx = u * 12.0 + 12.0, ky = -v * 12.0 + 12.0;
                            if (kx >= 0 && ky >= 0 && kx < 24 && ky < 24) ref += ap.image.at(c, int(kx), int(ky)) / 16.0;
                        }
                    const double got = p.at(c, x, y);
                    total += got;
                    sxy += ref * got, sx += ref, sy += got, sxx += ref * ref, syy += got * got;
                    ++n;
                }
            const double cov = sxy / n - sx / n * sy / n;
            const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
            EXPECT_GE(corr, 0.95) << "R " << R << " channel " << c;
            EXPECT_NEAR(total, 1000.0, 1.0) << "R " << R << " channel " << c;
        }
    }
}

// Radii that vary: the energy of every channel is kept (a constant image
// stays constant), and the result is the same bit for bit on 1 and 2 threads.
TEST(bokeh, VaryingBlurKeepsEnergyAndIsThreadCountIndependent) {
    const int w = 300, h = 260;
    const Roi win{0, 0, w, h};
    const std::size_t n = win.npixels();
    std::vector<float> planes(4 * n), radius(n);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + std::size_t(x);
            radius[i] = float(0.3 * x);  // 0 .. 90 px: every pyramid level
            planes[i] = ((x / 7 + y / 5) % 5 == 0) ? 50.0f : 0.0f;
            planes[n + i] = float((x * 13 + y * 7) % 11) / 11.0f;
            planes[2 * n + i] = 0.25f;
            planes[3 * n + i] = 1.0f;
        }
    Aperture polygon;
    polygon.kind = Aperture::Kind::Polygon;
    polygon.blades = 5;
    polygon.roundness = 0.3;
    for (const Aperture& ap : {Aperture{}, polygon}) {
        auto f = BokehFilter::create(ap);
        ASSERT_TRUE(f);
        std::vector<float> one = planes, two = planes;
        Exec e1, e2;
        e1.nthreads = 1;
        e2.nthreads = 2;
        ASSERT_TRUE(spread_planes(ImageView::planar(one.data(), 4, win), ConstImageView::planar(radius.data(), 1, win), *f, win, e1));
        ASSERT_TRUE(spread_planes(ImageView::planar(two.data(), 4, win), ConstImageView::planar(radius.data(), 1, win), *f, win, e2));
        EXPECT_EQ(one, two) << "thread count changed the bits";
        double a_min = 1e9, a_max = -1e9, b_min = 1e9, b_max = -1e9;
        for (std::size_t i = 0; i < n; ++i) {
            a_min = std::min(a_min, double(one[3 * n + i])), a_max = std::max(a_max, double(one[3 * n + i]));
            b_min = std::min(b_min, double(one[2 * n + i])), b_max = std::max(b_max, double(one[2 * n + i]));
        }
        EXPECT_NEAR(a_min, 1.0, 1e-4);
        EXPECT_NEAR(a_max, 1.0, 1e-4);
        EXPECT_NEAR(b_min, 0.25, 1e-4);
        EXPECT_NEAR(b_max, 0.25, 1e-4);
        // The sharp end (R < 0.5) is untouched: a point stays a point.
        EXPECT_NEAR(one[std::size_t(0) * w + 0], planes[0], 1e-3);
    }
}

// Position-dependent and anamorphic shapes: squeeze 2 halves the width; the
// cat's eye leaves the centre of the frame a disc and, towards a corner,
// narrows the shape along the direction to the centre (radially) while
// keeping it tangentially; energy is kept in both.
TEST(bokeh, SqueezeAndCatsEye) {
    const double R = 12.0;
    auto widths = [&](const Psf& p, int cx, int cy, double dir_deg) {
        // Extent (half of the plateau) along a direction and across it.
        double peak = 0;
        for (int y = cy - 2; y <= cy + 2; ++y)
            for (int x = cx - 2; x <= cx + 2; ++x) peak = std::max(peak, double(p.at(0, x, y)));
        auto extent = [&](double deg) {
            const double a = deg * std::numbers::pi / 180.0;
            double r = 0;
            for (double t = -30; t <= 30; t += 0.1) {
                const double px = cx + 0.5 + t * std::cos(a), py = cy + 0.5 - t * std::sin(a);
                if (px < 0 || py < 0 || px >= p.size || py >= p.size) continue;
                if (p.at(0, int(px), int(py)) >= 0.5 * peak) r = std::max(r, std::abs(t));
            }
            return r;
        };
        return std::pair{extent(dir_deg), extent(dir_deg + 90.0)};
    };
    Aperture squeezed;
    squeezed.squeeze = 2.0;
    const Psf sq = point_spread(squeezed, R, 81);
    // Second moments of an ellipse: var_x / var_y = (1 / squeeze)^2.
    double sxx = 0, syy = 0;
    for (int y = 0; y < sq.size; ++y)
        for (int x = 0; x < sq.size; ++x) {
            const double v = sq.at(0, x, y);
            sxx += v * (x - 40) * (x - 40);
            syy += v * (y - 40) * (y - 40);
        }
    EXPECT_NEAR(sxx / syy, 0.25, 0.02);

    // A point near the top-left corner of a 201 x 201 frame.
    Aperture cats;
    cats.cats_eye = 0.8;
    auto f = BokehFilter::create(cats);
    ASSERT_TRUE(f);
    const int size = 201;
    const std::size_t n = std::size_t(size) * size;
    for (const auto& [px, py] : {std::pair{100, 100}, std::pair{25, 25}}) {
        Psf p;
        p.size = size;
        p.planes.assign(4 * n, 0.0f);
        p.planes[std::size_t(py) * size + std::size_t(px)] = 1000.0f;
        std::fill(p.planes.begin() + std::ptrdiff_t(3 * n), p.planes.end(), 1.0f);
        std::vector<float> radius(n, float(R));
        const Roi win{0, 0, size, size};
        ASSERT_TRUE(spread_planes(ImageView::planar(p.planes.data(), 4, win), ConstImageView::planar(radius.data(), 1, win), *f, win));
        double total = 0;
        for (std::size_t i = 0; i < n; ++i) total += p.planes[i];
        // Neighbours' shapes differ, so the spread weight is not exactly 1:
        // a few percent (docs/bokeh.md); a constant image stays constant.
        EXPECT_NEAR(total, 1000.0, 50.0);
        double amin = 2, amax = 0;
        for (std::size_t i = 0; i < n; ++i) amin = std::min(amin, double(p.planes[3 * n + i])), amax = std::max(amax, double(p.planes[3 * n + i]));
        EXPECT_NEAR(amin, 1.0, 1e-4);
        EXPECT_NEAR(amax, 1.0, 1e-4);
        const auto [radial, tangential] = widths(p, px, py, 135.0);  // towards the centre from the top-left
        if (px == 100) {
            EXPECT_NEAR(radial / tangential, 1.0, 0.05) << "the centre keeps the disc";
        } else {
            // rho = 0.75 * sqrt(2) / sqrt(2) of the half diagonal: offset 0.8 * 0.75 = 0.6 of R.
            EXPECT_LT(radial / tangential, 0.85) << radial << " x " << tangential;
            EXPECT_NEAR(tangential, R, 1.5);
        }
    }
}

TEST(bokeh, BadRadiiAndShapesAreErrors) {
    const Roi win{0, 0, 8, 8};
    std::vector<float> planes(4 * 64, 0.0f), radius(64, 1.0f);
    auto f = BokehFilter::create(Aperture{});
    ASSERT_TRUE(f);
    radius[9] = std::nanf("");
    Status st = spread_planes(ImageView::planar(planes.data(), 4, win), ConstImageView::planar(radius.data(), 1, win), *f, win);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("(1, 1)"), std::string::npos) << st.message();
    std::vector<float> small(16);
    st = spread_planes(ImageView::planar(planes.data(), 4, win), ConstImageView::planar(small.data(), 1, Roi{0, 0, 4, 4}), *f, win);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("does not match"), std::string::npos) << st.message();
    Aperture bad;
    bad.kind = Aperture::Kind::Polygon;
    bad.blades = 2;
    EXPECT_FALSE(BokehFilter::create(bad));
    Aperture empty;
    empty.kind = Aperture::Kind::Image;
    empty.image = Image::with_channels({"Y"}, Roi{0, 0, 4, 4});  // all zero
    auto e = BokehFilter::create(empty);
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("all zero"), std::string::npos) << e.message();
}
