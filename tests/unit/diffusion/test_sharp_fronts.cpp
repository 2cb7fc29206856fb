// A front in focus over a blurred background (plate.h step 4, split_sharp_fronts):
// the front's anti-aliased edge pixels are part front, part background. The
// background's share must be blurred with the background, as a lens does,
// not kept as a sharp line of its colour along the front's edge. Reference:
// the same background defocused alone (no front), mixed with the front's
// colour by each edge pixel's coverage.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>

#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/plate.h"

using namespace gdof;

namespace {

constexpr int kW = 160, kH = 120;
constexpr int kBar0 = 70, kBar1 = 80;  // the front: columns [70, 80), edge pixels at 69 and 80
constexpr double kFront = 2.0, kBack = 6.0;
constexpr float kFrontGrey = 0.05f;

// Horizontal stripes, 6 rows bright and 6 dark: blurred by the background's
// 6 px they flatten, sharp they do not.
float back_grey(int y) { return (y / 6) % 2 ? 0.8f : 0.2f; }
// Each edge pixel's coverage by the front, varying down the edge.
double coverage(int x, int y) {
    if (x == kBar1) return 0.2 + 0.6 * y / double(kH - 1);
    if (x == kBar0 - 1) return 0.5;
    return x >= kBar0 && x < kBar1 ? 1.0 : 0.0;
}

Image plate(bool with_front, float edge_alpha = 1.0f) {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, Roi{0, 0, kW, kH});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double c = with_front ? coverage(x, y) : 0.0;
            const float a = c > 0.0 && c < 1.0 ? edge_alpha : 1.0f;  // premultiplied
            for (int ch = 0; ch < 3; ++ch) img.at(ch, x, y) = a * float(c * kFrontGrey + (1 - c) * back_grey(y));
            img.at(3, x, y) = a;
            img.at(4, x, y) = float(c * kFront + (1 - c) * kBack);  // a renderer's filtered Z
        }
    return img;
}

// A 50 mm thin lens on a 36 mm sensor focused at `focus`, its f-number
// blurring depth `blurred` by `radius` px; the camera of its flags.
std::pair<Camera, BlurField> thin_lens(double focus, double blurred, double radius) {
    ThinLens lens;
    lens.focal_length_mm = 50, lens.sensor_width_mm = 36, lens.focus_distance = focus, lens.image_width_px = kW;
    lens.f_number = 1.0;
    lens.f_number = lens.coc_radius_px(blurred) / radius;
    LensOverrides lo;
    lo.focal_length_mm = lens.focal_length_mm, lo.sensor_width_mm = lens.sensor_width_mm;
    lo.f_number = lens.f_number, lo.focus_distance = lens.focus_distance;
    return {resolve_camera(Metadata{}, Roi{0, 0, kW, kH}, lo).value(), BlurField::from_thin_lens(lens).value()};
}

}  // namespace

TEST(sharp_fronts, AFocusedFrontsEdgePixelsShowTheBlurredBackground) {
    // Focused on the front; the background blurred by 6 px.
    const auto [cam, field] = thin_lens(kFront, kBack, 6.0);

    ImageSet with, without;
    with.parts.emplace_back(plate(true));
    without.parts.emplace_back(plate(false));
    DefocusStats stats;
    auto out = defocus(with, field, cam, {}, &stats);
    ASSERT_TRUE(out) << out.message();
    auto back = defocus(without, field, cam, {});
    ASSERT_TRUE(back) << back.message();
    const Image& R = out->flat(0);
    const Image& B = back->flat(0);
    // Every edge pixel of the front is split (about 2 per row).
    EXPECT_GE(stats.depth.sharp_fronts, std::size_t(2 * kH - 8)) << stats.depth.report();

    // Rows away from the top and bottom (the frame's edge).
    double err = 0, sharp_err = 0;
    int n = 0;
    for (int y = 8; y < kH - 8; ++y)
        for (int x : {kBar0 - 1, kBar1}) {
            const double c = coverage(x, y);
            const double expected = c * kFrontGrey + (1 - c) * B.at(1, x, y);
            err += std::abs(R.at(1, x, y) - expected);
            // What the pixel kept whole at the front's depth shows: its
            // background's share sharp.
            sharp_err += std::abs(c * kFrontGrey + (1 - c) * back_grey(y) - expected);
            ++n;
        }
    err /= n;
    sharp_err /= n;
    std::printf("[ measured ] edge pixels: mean |error| %.4f against the blurred reference (kept whole: %.4f; "
                "stripes' contrast 0.6); %zu split\n",
                err, sharp_err, stats.depth.sharp_fronts);
    EXPECT_LT(err, 0.05 * 0.6) << "within 5% of the stripes' contrast";
    EXPECT_LT(err, sharp_err / 4);
    // The front itself stays sharp: its pixels keep their grey.
    for (int y = 8; y < kH - 8; ++y)
        for (int x = kBar0; x < kBar1; ++x) EXPECT_NEAR(R.at(1, x, y), kFrontGrey, 0.01) << x << "," << y;
}

TEST(sharp_fronts, ABlurredFrontsEdgePixelsAreNotSplit) {
    // Focused on the background: the front blurs more, and its edge pixels
    // stay whole at its depth (plate.h step 4).
    const auto [cam, field] = thin_lens(kBack, kFront, 6.0);
    ImageSet with;
    with.parts.emplace_back(plate(true));
    DefocusStats stats;
    auto out = defocus(with, field, cam, {}, &stats);
    ASSERT_TRUE(out) << out.message();
    EXPECT_GE(stats.depth.mixed, std::size_t(2 * kH - 8));
    EXPECT_EQ(stats.depth.sharp_fronts, 0u);
}

TEST(sharp_fronts, EdgePixelsThatAreNotOpaqueAreNotSplit) {
    // The same plate whose edge pixels are partly transparent (a matted
    // element's edge): their alpha is the element's coverage already, and a
    // split would count it twice. They stay whole, and keep their alpha.
    const auto [cam, field] = thin_lens(kFront, kBack, 6.0);
    ImageSet with;
    with.parts.emplace_back(plate(true, 0.7f));
    DefocusStats stats;
    auto out = defocus(with, field, cam, {}, &stats);
    ASSERT_TRUE(out) << out.message();
    EXPECT_GE(stats.depth.mixed, std::size_t(2 * kH - 8));
    EXPECT_EQ(stats.depth.sharp_fronts, 0u);
    const Image& R = out->flat(0);
    const int a = R.channel_index("A");
    ASSERT_GE(a, 0);
    for (int y = 8; y < kH - 8; y += 9) EXPECT_NEAR(R.at(a, kBar0 + 4, y), 1.0f, 1e-4) << "the front is opaque";
}

TEST(sharp_fronts, AProbeShowsThePixelsTheDefocusSplits) {
    // --probe on a front's edge: where the defocus splits (focused on the
    // front), the probe says so with the pixel's coverage and each part's
    // depth and blur, on the same pixels as the defocus counts; focused on
    // the background, or with no lens to know the blur, it does not.
    const auto [cam, field] = thin_lens(kFront, kBack, 6.0);
    ImageSet with;
    with.parts.emplace_back(plate(true));
    DefocusStats stats;
    ASSERT_TRUE(defocus(with, field, cam, {}, &stats));
    auto pd = prepare_plate_depth(with.flat(0), 4, DepthDecode{}, cam);
    ASSERT_TRUE(pd) << pd.message();
    std::size_t split = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            auto p = probe_pixel(*pd, cam, field, x, y);
            ASSERT_TRUE(p) << p.message();
            if (!p->mixed) continue;
            ++split;
            EXPECT_TRUE(x == kBar0 - 1 || x == kBar1) << x << "," << y << ": only the front's edge";
            EXPECT_NEAR(p->fg_share, coverage(x, y), 0.05) << x << "," << y;
            EXPECT_FLOAT_EQ(p->fg_depth, kFront) << x << "," << y;
            EXPECT_FLOAT_EQ(p->bg_depth, kBack) << x << "," << y;
            EXPECT_NEAR(p->fg_blur_px, 0.0, 1e-3) << x << "," << y;
            EXPECT_NEAR(p->bg_blur_px, 6.0, 1e-3) << x << "," << y;
        }
    EXPECT_EQ(split, stats.depth.sharp_fronts) << "the probe and the defocus split the same pixels";

    const auto [cam_back, field_back] = thin_lens(kBack, kFront, 6.0);
    auto on_back = prepare_plate_depth(with.flat(0), 4, DepthDecode{}, cam_back);
    ASSERT_TRUE(on_back) << on_back.message();
    for (int y = 8; y < kH - 8; y += 7) {
        auto p = probe_pixel(*on_back, cam_back, field_back, kBar1, y);
        ASSERT_TRUE(p) << p.message();
        EXPECT_FALSE(p->mixed) << y << ": the front blurs more; the pixel stays whole";
        EXPECT_TRUE(std::isnan(p->fg_share)) << y;
        auto bare = probe_pixel(*pd, nullptr, nullptr, kBar1, y);
        ASSERT_TRUE(bare) << bare.message();
        EXPECT_FALSE(bare->mixed) << y << ": without a blur, a step-4 pixel is not known to split";
    }
}
