// Past a plate layer's silhouette (radius_past_coverage.cpp): a blurred bar
// over a sharp wall, whose blur falls from 8 px inside to 2 px at its edges
// (a rounded object's limb lies nearer the focus than its middle). Through a
// lens each point of the bar spreads over its own circle of confusion, so
// the light the bar throws past its silhouette comes mostly from its inner,
// more blurred points. The reference is that scatter model with disc
// kernels, as a ratio against the same bar blurred 8 px throughout (which
// calibrates away the kernel's shape: diffusion spreads as a Gaussian).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "defocus_test_helpers.h"
#include "gdof/image_set.h"

using namespace gdof;
using namespace gdof::test;

namespace {

constexpr int kW = 128, kH = 40;
constexpr int kBar0 = 40, kBar1 = 72;  // columns [kBar0, kBar1)
constexpr float kInner = 8.0f, kLimb = 2.0f, kWall = 0.5f;

bool in_bar(int x) { return x >= kBar0 && x < kBar1; }
// Pixels from the bar's nearer edge (0: its edge pixels).
int inside(int x) { return std::min(x - kBar0, kBar1 - 1 - x); }
float limb_radius(int x) { return kLimb + (kInner - kLimb) * std::min(1.0f, float(inside(x)) / 4.0f); }

// The share of a disc of radius r centred d px inside a straight edge that
// lies past it.
double disc_share_past(double d, double r) {
    if (d >= r) return 0.0;
    return (r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d)) / (std::numbers::pi * r * r);
}

// Scatter reference: a row's light past both silhouettes, per unit of the
// bar's colour.
double scatter_past(bool limb) {
    double s = 0.0;
    for (int x = kBar0; x < kBar1; ++x) {
        const double r = limb ? limb_radius(x) : kInner;
        s += disc_share_past(x + 0.5 - kBar0, r) + disc_share_past(kBar1 - (x + 0.5), r);
    }
    return s;
}

// gdof's defocus of the plate: the bar's red past its silhouettes on the
// middle row (the wall is blue).
double defocus_past(bool limb) {
    const Roi win{0, 0, kW, kH};
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, win);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            img.at(0, x, y) = in_bar(x) ? 1.0f : 0.0f;
            img.at(1, x, y) = 0.0f;
            img.at(2, x, y) = in_bar(x) ? 0.0f : 1.0f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = in_bar(x) ? 2.0f : 10.0f;
        }
    ImageSet input;
    input.parts.emplace_back(std::move(img));
    const BlurField field = map_field(win, [limb](int x, int) {
        return in_bar(x) ? (limb ? limb_radius(x) : kInner) : kWall;
    });
    DefocusStats stats;
    auto out = defocus(input, field, test_camera(win), DefocusOptions{}, &stats);
    EXPECT_TRUE(out) << out.message();
    if (!out) return 0.0;
    EXPECT_GE(stats.layers, 2) << "the bar's silhouette needs a bound";
    double s = 0.0;
    for (int x = 0; x < kW; ++x)
        if (!in_bar(x)) s += value_at(out->flat(0), 0, x, kH / 2);
    return s;
}

}  // namespace

TEST(radius_past_coverage, ABlurredObjectSpreadsPastItsLimbWithItsInnerBlur) {
    const double ref = scatter_past(true) / scatter_past(false);
    const double ours = defocus_past(true) / defocus_past(false);
    std::printf("light past the silhouette, limb 2 px / uniform 8 px: scatter %.3f, gdof %.3f\n", ref, ours);
    // With the layer's radii averaged past it (push-pull), the limb's 2 px
    // held the bar's light in: 0.215 where the scatter ratio is 0.747; with
    // the radius of the point that reaches, 0.598. What is left is the limb
    // inside the layer, which diffusion (a gather: each pixel blurs with its
    // own radius) keeps sharper than a lens would.
    EXPECT_NEAR(ours, ref, 0.25 * ref);
}
