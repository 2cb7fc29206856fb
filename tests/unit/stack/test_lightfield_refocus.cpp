// Shift-and-add refocusing on generated light fields of textured planes.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "gdof/lightfield.h"
#include "lightfield_test_helpers.h"
#include "test_support.h"

using namespace gdof;
using gdof::test::Plane;

namespace {

// RMS error against a plane's ground-truth texture over a region.
double rms_vs_texture(const Image& img, const Plane& p, const Roi& r) {
    double e = 0;
    long n = 0;
    for (int c = 0; c < img.nchannels(); ++c)
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                const double d = img.at(c, x, y) - p.texture(x, y, c);
                e += d * d;
                ++n;
            }
    return std::sqrt(e / double(n));
}

// Mean squared horizontal + vertical gradient of channel 1 (sharpness).
double gradient_energy(const Image& img, const Roi& r) {
    double e = 0;
    long n = 0;
    for (int y = r.y0; y < r.y1 - 1; ++y)
        for (int x = r.x0; x < r.x1 - 1; ++x) {
            const double gx = img.at(1, x + 1, y) - img.at(1, x, y), gy = img.at(1, x, y + 1) - img.at(1, x, y);
            e += gx * gx + gy * gy;
            ++n;
        }
    return e / double(n);
}

// Plain shift-and-add for integer disparities, written out directly.
Image hand_shift_and_add(const LightField& lf, int d, double radius) {
    const Image& c0 = lf.central();
    Image out = Image::with_channels({"R", "G", "B"}, c0.data_window());
    const int w = c0.width(), h = c0.height();
    int n = 0;
    for (int r = 0; r < lf.rows; ++r)
        for (int c = 0; c < lf.cols; ++c) {
            const int du = c - lf.center_col, dv = r - lf.center_row;
            if (du * du + dv * dv > radius * radius) continue;
            ++n;
            for (int ch = 0; ch < 3; ++ch)
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const int sx = std::clamp(x - d * du, 0, w - 1), sy = std::clamp(y - d * dv, 0, h - 1);
                        out.at(ch, x, y) += lf.view(r, c).at(ch, sx, sy);
                    }
        }
    for (int ch = 0; ch < 3; ++ch)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) out.at(ch, x, y) /= float(n);
    return out;
}

}  // namespace

TEST(lightfield, refocus_at_a_plane_disparity_makes_it_as_sharp_as_the_central_view) {
    // A near square at disparity 1.3 over a background at -0.45 (non-integer: bicubic at work).
    Plane near{1.3, Roi{40, 30, 110, 90}, test::smooth_texture(1.0)};
    Plane far{-0.45, Roi{}, test::smooth_texture(2.0)};
    const LightField lf = test::make_planes_lightfield(5, 5, 160, 120, {near, far});
    // Inside the square, away from its edges by the largest parallax (2.83 views x 1.75 px).
    const Roi in_near{50, 40, 100, 80};
    // Background, away from the square and the image edges.
    const Roi in_far{120, 10, 150, 110};

    const double central_near = rms_vs_texture(lf.central(), near, in_near);
    const double central_far = rms_vs_texture(lf.central(), far, in_far);
    EXPECT_LT(central_near, 1e-6);
    EXPECT_LT(central_far, 1e-6);

    for (double r : {1.0, 2.0, 2.9}) {
        auto at_near = refocus(lf, {near.disparity, r});
        auto at_far = refocus(lf, {far.disparity, r});
        ASSERT_TRUE(at_near && at_far) << at_near.message() << at_far.message();
        const double e_near_ok = rms_vs_texture(*at_near, near, in_near);
        const double e_near_blur = rms_vs_texture(*at_far, near, in_near);
        const double e_far_ok = rms_vs_texture(*at_far, far, in_far);
        const double e_far_blur = rms_vs_texture(*at_near, far, in_far);
        SCOPED_TRACE("radius " + std::to_string(r));
        // In focus: only the interpolation error (bicubic on a smooth texture).
        EXPECT_LT(e_near_ok, 0.01) << "near plane refocused at its disparity";
        EXPECT_LT(e_far_ok, 0.01) << "far plane refocused at its disparity";
        // Out of focus: much worse.
        EXPECT_GT(e_near_blur, 8 * e_near_ok);
        EXPECT_GT(e_far_blur, 8 * e_far_ok);
        // As sharp as the central view (gradient energy within a few percent).
        const double g0 = gradient_energy(lf.central(), in_near);
        EXPECT_NEAR(gradient_energy(*at_near, in_near) / g0, 1.0, 0.05);
        EXPECT_LT(gradient_energy(*at_far, in_near) / g0, 0.8);
    }
}

TEST(lightfield, bicubic_beats_bilinear_on_sub_pixel_shifts) {
    Plane p{0.5, Roi{}, test::smooth_texture(3.0)};
    const LightField lf = test::make_planes_lightfield(5, 5, 96, 80, {p});
    const Roi in{12, 12, 84, 68};
    RefocusOptions cubic{0.5, 2.0, LightFieldFilter::Bicubic};
    RefocusOptions linear{0.5, 2.0, LightFieldFilter::Bilinear};
    const double e_cubic = rms_vs_texture(refocus(lf, cubic).value(), p, in);
    const double e_linear = rms_vs_texture(refocus(lf, linear).value(), p, in);
    EXPECT_LT(e_cubic, 0.5 * e_linear) << "cubic " << e_cubic << ", linear " << e_linear;
}

TEST(lightfield, aperture_radius_zero_returns_the_central_view_exactly) {
    Plane near{0.8, Roi{10, 10, 30, 30}, test::smooth_texture(1.0)};
    Plane far{0.0, Roi{}, test::smooth_texture(2.0)};
    const LightField lf = test::make_planes_lightfield(3, 5, 48, 40, {near, far}, 4);
    for (double d : {0.0, 0.37, -2.6, 11.0}) {
        for (LightFieldFilter f : {LightFieldFilter::Bicubic, LightFieldFilter::Bilinear}) {
            auto img = refocus(lf, {d, 0.0, f});
            ASSERT_TRUE(img) << img.message();
            ASSERT_EQ(img->nchannels(), 4);
            for (int c = 0; c < 4; ++c)
                for (int y = 0; y < 40; ++y)
                    for (int x = 0; x < 48; ++x)
                        ASSERT_EQ(img->at(c, x, y), lf.central().at(c, x, y)) << "d " << d << " at " << x << "," << y;
        }
    }
    // Radius below one view step is still the central view alone.
    EXPECT_EQ(lf.aperture_views(0.99), 1);
}

TEST(lightfield, integer_disparity_matches_a_hand_written_shift_and_add_exactly) {
    // Values k/64: every sum is exact, so equality does not depend on the order of addition.
    auto quantised = [](double seed) {
        auto t = test::smooth_texture(seed);
        return [t](double x, double y, int c) { return std::round(t(x, y, c) * 64.0f) / 64.0f; };
    };
    Plane near{2.0, Roi{12, 10, 40, 36}, quantised(1.0)};
    Plane far{-1.0, Roi{}, quantised(2.0)};
    const LightField lf = test::make_planes_lightfield(5, 5, 56, 48, {near, far});
    for (int d : {2, -1, 0, 3}) {
        for (double r : {1.0, 1.5, 2.0, 3.0}) {
            const Image want = hand_shift_and_add(lf, d, r);
            for (LightFieldFilter f : {LightFieldFilter::Bicubic, LightFieldFilter::Bilinear}) {
                auto got = refocus(lf, {double(d), r, f});
                ASSERT_TRUE(got) << got.message();
                for (int c = 0; c < 3; ++c)
                    for (int y = 0; y < 48; ++y)
                        for (int x = 0; x < 56; ++x)
                            ASSERT_EQ(got->at(c, x, y), want.at(c, x, y))
                                << "d " << d << " r " << r << " " << to_string(f) << " at " << x << "," << y;
            }
        }
    }
}

TEST(lightfield, half_pixel_bilinear_shift_averages_neighbours) {
    // One row of views (1 x 3): the right view sampled half a pixel away.
    LightField lf;
    lf.rows = 1, lf.cols = 3, lf.center_row = 0, lf.center_col = 1;
    for (int i = 0; i < 3; ++i) {
        Image v = Image::with_channels({"Y"}, Roi{0, 0, 8, 1});
        for (int x = 0; x < 8; ++x) v.at(0, x, 0) = float(x * x);
        lf.views.push_back(v);
    }
    auto img = refocus(lf, {0.5, 1.0, LightFieldFilter::Bilinear});
    ASSERT_TRUE(img) << img.message();
    // Views du = -1, 0, +1 sampled at x + 0.5, x, x - 0.5.
    for (int x = 1; x < 7; ++x) {
        const double a = 0.5 * ((x) * (x) + (x + 1) * (x + 1)), b = x * x, c = 0.5 * ((x - 1) * (x - 1) + x * x);
        EXPECT_NEAR(img->at(0, x, 0), (a + b + c) / 3.0, 1e-5) << x;
    }
}

TEST(lightfield, refocus_output_keeps_the_central_windows_and_records_the_focus) {
    Plane p{0.0, Roi{}, test::smooth_texture(1.0)};
    LightField lf = test::make_planes_lightfield(3, 3, 20, 10, {p});
    auto img = refocus(lf, {0.25, 1.0});
    ASSERT_TRUE(img);
    EXPECT_EQ(img->data_window(), (Roi{0, 0, 20, 10}));
    EXPECT_EQ(img->metadata.get_float("gdof:focusDisparity").value_or(-1), 0.25);
    EXPECT_EQ(img->metadata.get_float("gdof:apertureViews").value_or(-1), 5);
}

TEST(lightfield, bad_settings_and_grids_are_errors) {
    Plane p{0.0, Roi{}, test::smooth_texture(1.0)};
    LightField lf = test::make_planes_lightfield(3, 3, 20, 10, {p});
    auto neg = refocus(lf, {0.0, -1.0});
    EXPECT_FALSE(neg);
    EXPECT_NE(neg.message().find("aperture_radius"), std::string::npos) << neg.message();
    EXPECT_FALSE(refocus(lf, {std::nan(""), 1.0}));

    LightField bad = lf;
    bad.views[4] = Image::with_channels({"R", "G", "B"}, Roi{0, 0, 21, 10});
    auto r = refocus(bad, {0.0, 1.0});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("view_1_1"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("21x10"), std::string::npos) << r.message();

    LightField chans = lf;
    chans.views[2].rename_channel(1, "Y");
    auto rc = refocus(chans, {0.0, 1.0});
    ASSERT_FALSE(rc);
    EXPECT_NE(rc.message().find("'Y'"), std::string::npos) << rc.message();

    LightField centre = lf;
    centre.center_col = 5;
    EXPECT_FALSE(refocus(centre, {0.0, 1.0}));
}

TEST(lightfield, cancellation_stops_refocus) {
    Plane p{0.0, Roi{}, test::smooth_texture(1.0)};
    LightField lf = test::make_planes_lightfield(3, 3, 64, 64, {p});
    Exec exec;
    exec.cancelled = [] { return true; };
    auto r = refocus(lf, {0.5, 1.0}, exec);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("cancelled"), std::string::npos);
}

TEST(lightfield, results_do_not_depend_on_the_thread_count) {
    Plane near{1.3, Roi{10, 10, 40, 30}, test::smooth_texture(1.0)};
    Plane far{-0.4, Roi{}, test::smooth_texture(2.0)};
    const LightField lf = test::make_planes_lightfield(5, 5, 64, 48, {near, far});
    Exec one;
    one.nthreads = 1;
    auto a = refocus(lf, {0.7, 2.0}, one);
    auto b = refocus(lf, {0.7, 2.0});
    ASSERT_TRUE(a && b);
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x) ASSERT_EQ(a->at(c, x, y), b->at(c, x, y));
}
