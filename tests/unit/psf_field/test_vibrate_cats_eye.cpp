// The cat's eye with --vibrate (method 4): a point towards a corner spreads
// into the lens where the aperture and the displaced vignetting disc overlap,
// as --bokeh draws it, with its light kept; at the frame's centre the shape
// stays the disc.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/psf_field.h"

using namespace gdof;
using namespace gdof::test;

namespace {

constexpr double kBlur = 12.0;

// Second moments of a spread (channel 0) about its centroid, along the
// outward axis (ex, ey) and across it.
struct Moments {
    double total = 0, cx = 0, cy = 0, along = 0, across = 0;
};
Moments moments(const Image& img, double ex, double ey) {
    Moments m;
    const Roi w = img.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            const double v = value_at(img, 0, x, y);
            m.total += v;
            m.cx += v * (x + 0.5);
            m.cy += v * (y + 0.5);
        }
    m.cx /= m.total;
    m.cy /= m.total;
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            const double v = value_at(img, 0, x, y), dx = x + 0.5 - m.cx, dy = y + 0.5 - m.cy;
            const double a = dx * ex + dy * ey, b = -dx * ey + dy * ex;
            m.along += v * a * a;
            m.across += v * b * b;
        }
    m.along /= m.total;
    m.across /= m.total;
    return m;
}

// The same moments of the lens itself (unit disc cut by the unit disc at
// distance d), by Monte Carlo, in units of the aperture radius.
void lens_moments(double d, double& along, double& across) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    double n = 0, ma = 0, mb = 0, saa = 0, sbb = 0;
    for (int k = 0; k < 400000; ++k) {
        const double a = U(rng), b = U(rng);
        if (a * a + b * b > 1.0 || (a - d) * (a - d) + b * b > 1.0) continue;
        n += 1, ma += a, mb += b, saa += a * a, sbb += b * b;
    }
    ma /= n, mb /= n;
    along = saa / n - ma * ma;
    across = sbb / n - mb * mb;
}

Image spread(const Roi& display, int px, int py, DefocusFilter filter, double cats_eye) {
    Layer l = make_layer(display, display, [&](int x, int y) {
        return x == px && y == py ? Rgba{1000.0f, 1000.0f, 1000.0f, 1.0f} : Rgba{0, 0, 0, 0};
    });
    DefocusOptions o;
    o.filter = filter;
    o.aperture.cats_eye = cats_eye;
    o.vibrate.samples = 1024;
    auto out = defocus_layers({l}, constant_field(display, kBlur), test_camera(display), o);
    EXPECT_TRUE(out) << out.message();
    return out ? std::move(out).value() : Image{};
}

}  // namespace

TEST(vibrate_cats_eye, PointTowardsACornerSpreadsIntoTheLens) {
    const Roi display{0, 0, 160, 120};
    const double amount = 0.9;
    // A point at (30, 25): outward (away from the centre 80, 60) in image axes.
    const int px = 30, py = 25;
    const double dx = px + 0.5 - 80.0, dy = py + 0.5 - 60.0, rho = std::hypot(dx, dy);
    const double ex = dx / rho, ey = dy / rho;
    const double d = amount * rho / (0.5 * std::hypot(160.0, 120.0));
    double la = 0, lb = 0;
    lens_moments(d, la, lb);
    const Image vib = spread(display, px, py, DefocusFilter::Vibrate, amount);
    const Image bok = spread(display, px, py, DefocusFilter::Bokeh, amount);
    const Image disc = spread(display, px, py, DefocusFilter::Vibrate, 0.0);
    const Moments mv = moments(vib, ex, ey), mb = moments(bok, ex, ey), md = moments(disc, ex, ey);
    // The prefilter and the pixel add a little to each variance (as for the
    // disc, where the lens has R^2 / 4).
    const double extra = md.along - kBlur * kBlur / 4.0;
    std::printf("cats eye d = %.3f: along / across variance: vibrate %.2f / %.2f, bokeh %.2f / %.2f, "
                "lens %.2f / %.2f (+%.2f), disc %.2f / %.2f; energy %.2f\n",
                d, mv.along, mv.across, mb.along, mb.across, la * kBlur * kBlur + extra, lb * kBlur * kBlur + extra,
                extra, md.along, md.across, mv.total);
    EXPECT_NEAR(mv.total, 1000.0, 1.0) << "every source keeps all its samples";
    EXPECT_NEAR(mv.along, la * kBlur * kBlur + extra, 0.12 * la * kBlur * kBlur);
    EXPECT_NEAR(mv.across, lb * kBlur * kBlur + extra, 0.12 * lb * kBlur * kBlur);
    // The cut narrows the shape along the outward axis only.
    EXPECT_LT(mv.along, 0.75 * md.along);
    EXPECT_GT(mv.across, 0.8 * md.across);
    // Centred on its source, as --bokeh draws it.
    EXPECT_NEAR(mv.cx, mb.cx, 0.5);
    EXPECT_NEAR(mv.cy, mb.cy, 0.5);
    EXPECT_NEAR(mv.along, mb.along, 0.15 * mb.along);
    EXPECT_NEAR(mv.across, mb.across, 0.15 * mb.across);
}

TEST(vibrate_cats_eye, AtTheCentreTheShapeIsTheDisc) {
    const Roi display{0, 0, 160, 120};
    const Image cut = spread(display, 79, 59, DefocusFilter::Vibrate, 0.9);
    const Image disc = spread(display, 79, 59, DefocusFilter::Vibrate, 0.0);
    // The centre pixel's centre is 0.7 px from the frame's: d is 0.009.
    const Moments a = moments(cut, 1, 0), b = moments(disc, 1, 0);
    EXPECT_NEAR(a.along, b.along, 0.02 * b.along);
    EXPECT_NEAR(a.across, b.across, 0.02 * b.across);
}
