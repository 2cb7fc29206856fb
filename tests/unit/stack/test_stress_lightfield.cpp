// Numerical stress: light-field refocusing (shift-and-add) and stack
// extraction (issue 7, item 4): a light field of one view, grids up to
// 9 x 9, 1x1, 1x10000 and 10000x1 views, focus disparities from 0 to
// 1e300, apertures 0..1000 view steps, HDR (1e6) and denormal values, NaN
// pixels, NaN / Inf settings; the disparity <-> depth geometry at the
// extremes. Properties: a single view is returned bit for bit; constant
// views refocus to the same constant; 1x1 views average exactly the views
// in the aperture; a NaN pixel stays local; invalid settings are errors
// naming the setting.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "gdof/lightfield.h"
#include "stress_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

// A focus disparity: small, sub-pixel, huge (up to 1e300), or exactly 0.
double random_disparity(StressRng& rng) {
    const double sign = rng.chance(0.5) ? 1.0 : -1.0;
    switch (rng.integer(0, 5)) {
        case 0: return 0.0;
        case 1: return sign * rng.log_uniform(1e3, 1e300);
        case 2: return sign * double(kDenormF);
        default: return sign * rng.uniform(0.0, 20.0);
    }
}

double random_aperture(StressRng& rng) {
    switch (rng.integer(0, 4)) {
        case 0: return 0.0;
        case 1: return rng.log_uniform(10.0, 1000.0);
        default: return rng.uniform(0.0, 5.0);
    }
}

// rows x cols views of the given size, each channel filled by fill(view, channel, index).
LightField make_lightfield(int rows, int cols, const Size& sz, int nch,
                           const std::function<float(int, int, std::size_t)>& fill) {
    LightField lf;
    lf.rows = rows, lf.cols = cols;
    lf.center_row = (rows - 1) / 2, lf.center_col = (cols - 1) / 2;
    const std::vector<std::string> names = {"R", "G", "B", "A"};
    for (int v = 0; v < rows * cols; ++v) {
        Image img = Image::with_channels(std::vector<std::string>(names.begin(), names.begin() + nch), {0, 0, sz.w, sz.h});
        for (int c = 0; c < nch; ++c)
            for (std::size_t i = 0; i < img.npixels(); ++i) img.plane(c)[i] = fill(v, c, i);
        lf.views.push_back(std::move(img));
        lf.sources.push_back("view_" + std::to_string(v));
    }
    return lf;
}

}  // namespace

// A light field of one view: every focus (to 1e300) and aperture gives the
// view back bit for bit (HDR, denormal, NaN pixels included); a stack
// extracted from it is that view per reference, with valid near/far.
TEST(stress_lightfield, a_light_field_of_one_view_refocuses_to_the_view) {
    GDOF_STRESS_RNG(rng, 4001);
    for (int iter = 0; iter < 40; ++iter) {
        const Size sz = random_size(rng, 40);
        const LightField lf = make_lightfield(1, 1, sz, rng.integer(1, 4), [&](int, int, std::size_t) {
            return rng.chance(0.01) ? float(kStressNaN) : rng.pixel();
        });
        RefocusOptions rs;
        rs.focus_disparity = random_disparity(rng);
        rs.aperture_radius = random_aperture(rng);
        rs.filter = rng.chance(0.5) ? LightFieldFilter::Bicubic : LightFieldFilter::Bilinear;
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", disparity " << num(rs.focus_disparity) << ", aperture "
                                          << rs.aperture_radius << ", " << to_string(rs.filter));
        auto out = refocus(lf, rs);
        ASSERT_TRUE(out) << out.message();
        const Image& v = lf.views[0];
        ASSERT_EQ(out->data_window(), v.data_window());
        for (int c = 0; c < v.nchannels(); ++c)
            EXPECT_EQ(std::memcmp(out->plane(c), v.plane(c), v.npixels() * sizeof(float)), 0) << "channel " << c;
    }
    // Stack extraction from one view.
    const LightField lf = make_lightfield(1, 1, {7, 5}, 3, [](int, int c, std::size_t i) { return float(i * 3 + std::size_t(c)); });
    ExtractStackOptions spec;
    spec.references = {{0.0, kStressNaN, 0.0}, {1e300, kStressNaN, 3.0}, {kStressNaN, kStressInf, 1000.0}, {kStressNaN, 1e-4, 1.0}};
    auto st = extract_stack(lf, spec);
    ASSERT_TRUE(st) << st.message();
    ASSERT_EQ(st->images.size(), spec.references.size());
    for (std::size_t i = 0; i < st->images.size(); ++i) {
        const StackReference& r = st->stack.references[i];
        EXPECT_FALSE(std::isnan(r.near) || std::isnan(r.far)) << "reference " << i;
        EXPECT_LE(r.near, r.far) << "reference " << i;
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(std::memcmp(st->images[i].plane(c), lf.views[0].plane(c), 35 * sizeof(float)), 0) << "reference " << i;
    }
}

// Constant views (the same value in every view, HDR to 1e6, denormal, 0)
// refocus to that constant for any grid, focus and aperture: the filter
// weights sum to 1 and edges clamp.
TEST(stress_lightfield, constant_views_refocus_to_the_constant) {
    GDOF_STRESS_RNG(rng, 4002);
    for (int iter = 0; iter < 60; ++iter) {
        const Size sz = random_size(rng, 40);
        const int rows = rng.integer(1, 9), cols = rng.integer(1, 9);
        const int nch = rng.integer(1, 4);
        std::vector<float> value(static_cast<std::size_t>(nch));
        for (float& v : value) v = rng.pixel();
        const LightField lf = make_lightfield(rows, cols, sz, nch, [&](int, int c, std::size_t) { return value[std::size_t(c)]; });
        RefocusOptions rs;
        rs.focus_disparity = random_disparity(rng);
        rs.aperture_radius = random_aperture(rng);
        rs.filter = rng.chance(0.5) ? LightFieldFilter::Bicubic : LightFieldFilter::Bilinear;
        SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " views of " << sz.w << "x" << sz.h << ", disparity "
                                          << num(rs.focus_disparity) << ", aperture " << rs.aperture_radius << ", "
                                          << to_string(rs.filter));
        auto out = refocus(lf, rs);
        ASSERT_TRUE(out) << out.message();
        for (int c = 0; c < nch; ++c) {
            const float want = value[std::size_t(c)];
            // Float accumulation over the views in the aperture (n ulps for n
            // views, documented), filter weights summing to 1 within a few
            // ulps; denormals carry a few absolute ulps of their own.
            const float n_views = float(lf.aperture_views(rs.aperture_radius));
            const float tol = 1.2e-7f * (n_views + 4.0f) * want + 1e-43f;
            for (std::size_t i = 0; i < out->npixels(); ++i)
                if (!(std::fabs(out->plane(c)[i] - want) <= tol)) {
                    ADD_FAILURE() << "channel " << c << " pixel index " << i << ": " << num(out->plane(c)[i]) << " instead of "
                                  << num(want);
                    break;
                }
        }
    }
}

// 1x1 views: every sample clamps to the one pixel, so the refocused value is
// exactly the mean of the views inside the aperture (in row-major order).
TEST(stress_lightfield, one_pixel_views_average_the_aperture) {
    GDOF_STRESS_RNG(rng, 4003);
    for (int iter = 0; iter < 60; ++iter) {
        const int rows = rng.integer(1, 9), cols = rng.integer(1, 9);
        std::vector<float> value(static_cast<std::size_t>(rows * cols));
        for (float& v : value) v = rng.pixel();
        LightField lf = make_lightfield(rows, cols, {1, 1}, 1, [&](int v, int, std::size_t) { return value[std::size_t(v)]; });
        lf.center_row = rng.integer(0, rows - 1), lf.center_col = rng.integer(0, cols - 1);
        RefocusOptions rs;
        rs.focus_disparity = random_disparity(rng);
        rs.aperture_radius = random_aperture(rng);
        rs.filter = LightFieldFilter::Bilinear;  // bicubic weights sum to 1 only up to rounding
        double sum = 0;
        int n = 0;
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) {
                const double du = c - lf.center_col, dv = r - lf.center_row;
                if (du * du + dv * dv <= rs.aperture_radius * rs.aperture_radius + 1e-9) sum += value[std::size_t(r * cols + c)], ++n;
            }
        SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " views, centre (" << lf.center_row << ", " << lf.center_col
                                          << "), disparity " << num(rs.focus_disparity) << ", aperture " << rs.aperture_radius);
        ASSERT_EQ(n, lf.aperture_views(rs.aperture_radius));
        auto out = refocus(lf, rs);
        ASSERT_TRUE(out) << out.message();
        const double want = sum / n;
        EXPECT_NEAR(out->plane(0)[0], want, 1.2e-7 * (n + 4) * want + 1e-43);  // float sum over n views
    }
}

// A NaN pixel in one view stays local: pixels farther from it than the
// shift plus the filter reach are finite; finite views give finite output.
TEST(stress_lightfield, a_nan_pixel_stays_local) {
    GDOF_STRESS_RNG(rng, 4004);
    for (int iter = 0; iter < 30; ++iter) {
        const int w = rng.integer(18, 60), h = rng.integer(18, 60);
        const int rows = rng.integer(1, 7), cols = rng.integer(1, 7);
        LightField lf = make_lightfield(rows, cols, {w, h}, 1, [&](int, int, std::size_t) { return rng.pixel(); });
        RefocusOptions rs;
        rs.focus_disparity = rng.uniform(-2.0, 2.0);
        rs.aperture_radius = rng.uniform(0.0, 4.0);
        // Finite first.
        auto clean = refocus(lf, rs);
        ASSERT_TRUE(clean) << clean.message();
        EXPECT_EQ(first_nonfinite(*clean), "");
        const int view = rng.integer(0, rows * cols - 1);
        const int nx = rng.integer(8, w - 9), ny = rng.integer(8, h - 9);
        lf.views[std::size_t(view)].at(0, nx, ny) = float(kStressNaN);
        SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " views of " << w << "x" << h << ", NaN in view " << view
                                          << " at (" << nx << ", " << ny << "), disparity " << rs.focus_disparity << ", aperture "
                                          << rs.aperture_radius);
        auto out = refocus(lf, rs);
        ASSERT_TRUE(out) << out.message();
        const double reach = std::fabs(rs.focus_disparity) * std::max(rows, cols) + 3.0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                if (std::max(std::abs(x - nx), std::abs(y - ny)) > reach && !std::isfinite(out->at(0, x, y))) {
                    ADD_FAILURE() << "NaN spread to (" << x << ", " << y << ")";
                    return;
                }
    }
}

// NaN / Inf / negative settings and bad grids are errors naming the setting.
TEST(stress_lightfield, invalid_settings_are_errors_naming_them) {
    GDOF_STRESS_RNG(rng, 4005);
    const LightField lf = make_lightfield(3, 3, {8, 4}, 3, [](int v, int c, std::size_t i) { return float(v + c) + 0.1f * float(i); });
    const std::vector<double> bad = {kStressNaN, kStressInf, -kStressInf};
    for (int iter = 0; iter < 20; ++iter) {
        RefocusOptions rs;
        const bool disparity = rng.chance(0.5);
        if (disparity) rs.focus_disparity = rng.pick(bad);
        else rs.aperture_radius = rng.chance(0.5) ? rng.pick(bad) : -rng.log_uniform(1e-300, 1e3);
        auto out = refocus(lf, rs);
        ASSERT_FALSE(out) << "disparity " << rs.focus_disparity << ", aperture " << rs.aperture_radius;
        EXPECT_TRUE(contains(out.message(), disparity ? "focus_disparity" : "aperture_radius")) << out.message();

        ExtractStackOptions spec;
        StackRequest q;
        if (disparity) q.focus_disparity = rng.chance(0.5) ? kStressInf : -kStressInf;
        else q.aperture_radius = rs.aperture_radius;
        spec.references = {{0.5, kStressNaN, 1.0}, q};
        auto plan = plan_stack(lf, spec);
        ASSERT_FALSE(plan);
        EXPECT_TRUE(contains(plan.message(), "references[1]")) << plan.message();
    }
    ExtractStackOptions spec;
    spec.references = {{kStressNaN, -1.0, 1.0}};
    auto plan = plan_stack(lf, spec);
    ASSERT_FALSE(plan);
    EXPECT_TRUE(contains(plan.message(), "references[0].depth")) << plan.message();
    spec.references = {{1.0, kStressNaN, 1.0}};
    spec.coc_px = kStressNaN;
    plan = plan_stack(lf, spec);
    ASSERT_FALSE(plan);
    EXPECT_TRUE(contains(plan.message(), "coc_px")) << plan.message();

    LightField broken = lf;
    broken.views.pop_back();
    EXPECT_FALSE(refocus(broken, {}));
    broken = lf;
    broken.geometry.focal_baseline = kStressNaN;
    auto r = refocus(broken, {});
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.message(), "focal_baseline")) << r.message();
    broken = lf;
    broken.views[4] = Image::with_channels({"R", "G", "B"}, {0, 0, 8, 5});
    r = refocus(broken, {});
    ASSERT_FALSE(r);
    EXPECT_TRUE(contains(r.message(), "view_4")) << r.message();
}

// Geometry at the extremes: depth <-> disparity round trips over depths
// 1e-4 .. 1e7 and +inf for focal baselines of either sign and any size;
// refocused depth of field is either "none" (both NaN) or an ordered interval
// with near >= 0 that contains the focus depth.
TEST(stress_lightfield, geometry_round_trips_and_depth_of_field_brackets_the_focus) {
    GDOF_STRESS_RNG(rng, 4006);
    for (int iter = 0; iter < 2000; ++iter) {
        LightFieldGeometry g;
        g.focal_baseline = (rng.chance(0.8) ? 1.0 : -1.0) * rng.log_uniform(1e-3, 1e6);
        g.disparity_at_infinity = rng.chance(0.3) ? 0.0 : rng.uniform(-5.0, 5.0);
        g.depth_known = true;
        const double z = rng.chance(0.05) ? kStressInf : rng.log_uniform(1e-4, 1e7);
        const double d = g.disparity_of_depth(z);
        SCOPED_TRACE("focal_baseline " + num(g.focal_baseline) + ", d_inf " + num(g.disparity_at_infinity) + ", depth " + num(z) +
                     ", disparity " + num(d));
        ASSERT_FALSE(std::isnan(d));
        const double back = g.depth_of_disparity(d);
        if (std::isinf(z)) {
            EXPECT_TRUE(std::isinf(back)) << back;
        } else if (std::fabs(g.focal_baseline / z) > 1e-9 * std::fabs(g.disparity_at_infinity)) {
            // The round trip loses what d_inf's rounding hides of fb / z.
            const double rel = 1e-15 * (std::fabs(d) + std::fabs(g.disparity_at_infinity)) / std::fabs(g.focal_baseline / z);
            EXPECT_NEAR(back, z, 4 * rel * z + 1e-12 * z) << "round trip";
        }
        const double r = random_aperture(rng), coc = rng.log_uniform(1e-3, 1e3);
        const DepthRange dof = refocus_depth_of_field(g, d, r, coc);
        EXPECT_EQ(std::isnan(dof.near), std::isnan(dof.far));
        if (std::isnan(dof.near)) continue;
        EXPECT_GE(dof.near, 0.0);
        EXPECT_LE(dof.near, dof.far);
        if (std::isfinite(z)) {
            EXPECT_TRUE(dof.near <= z * (1 + 1e-9) && z <= dof.far * (1 + 1e-9)) << "[" << num(dof.near) << ", " << num(dof.far) << "]";
        }
    }
}

// Stacks extracted from an ordinary light field with extreme references
// (focus from 1e-4 to +inf, apertures to 1000, on 1x10000 / 10000x1 views):
// every image finite, every reference's near <= far without NaN.
TEST(stress_lightfield, extracted_stacks_are_finite) {
    GDOF_STRESS_RNG(rng, 4007);
    for (int iter = 0; iter < 8; ++iter) {
        const Size sz = random_size(rng, 40);
        const int rows = rng.integer(1, 5), cols = rng.integer(1, 5);
        LightField lf = make_lightfield(rows, cols, sz, 3, [&](int, int, std::size_t) { return rng.pixel(); });
        lf.geometry.focal_baseline = rng.log_uniform(1e-2, 1e4);
        lf.geometry.disparity_at_infinity = rng.uniform(-1.0, 0.0);
        lf.geometry.depth_known = true;
        ExtractStackOptions spec;
        const int n = rng.integer(1, 6);
        for (int i = 0; i < n; ++i) {
            StackRequest q;
            if (rng.chance(0.5)) q.focus_disparity = rng.uniform(0.0, 3.0) + 1e-3 * i;
            else q.focus_depth = rng.chance(0.2) ? kStressInf : rng.log_uniform(1e-4, 1e7) * (1 + 1e-3 * i);
            q.aperture_radius = random_aperture(rng) + 1e-3 * i;
            spec.references.push_back(q);
        }
        spec.coc_px = rng.log_uniform(0.01, 100.0);
        SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " views of " << sz.w << "x" << sz.h << ", " << n << " references");
        auto st = extract_stack(lf, spec);
        ASSERT_TRUE(st) << st.message();
        ASSERT_EQ(st->images.size(), std::size_t(n));
        for (int i = 0; i < n; ++i) {
            const StackReference& r = st->stack.references[std::size_t(i)];
            EXPECT_FALSE(std::isnan(r.near) || std::isnan(r.far)) << "reference " << i;
            EXPECT_LE(r.near, r.far) << "reference " << i;
            EXPECT_EQ(first_nonfinite(st->images[std::size_t(i)]), "") << "reference " << i;
        }
    }
}
