// Light-field geometry: disparity <-> depth, depth of field of refocused
// images against hand-computed values, and stack planning.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gdof/lightfield.h"
#include "lightfield_test_helpers.h"
#include "test_support.h"

using namespace gdof;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

LightFieldGeometry geom(double fb, double d_inf) {
    LightFieldGeometry g;
    g.focal_baseline = fb;
    g.disparity_at_infinity = d_inf;
    g.depth_known = true;
    return g;
}

LightField small_lf(const LightFieldGeometry& g) {
    test::Plane p{0.0, Roi{}, test::smooth_texture(1.0)};
    LightField lf = test::make_planes_lightfield(5, 5, 24, 16, {p});
    lf.geometry = g;
    return lf;
}
}  // namespace

TEST(lightfield, disparity_and_depth_round_trip) {
    const LightFieldGeometry g = geom(2.0, -0.5);
    EXPECT_DOUBLE_EQ(g.disparity_of_depth(4.0), 0.0);   // 2/4 - 0.5
    EXPECT_DOUBLE_EQ(g.disparity_of_depth(kInf), -0.5);
    EXPECT_DOUBLE_EQ(g.depth_of_disparity(0.0), 4.0);
    EXPECT_DOUBLE_EQ(g.depth_of_disparity(1.5), 1.0);
    EXPECT_EQ(g.depth_of_disparity(-0.5), kInf);
    EXPECT_TRUE(std::isnan(g.depth_of_disparity(-0.6)));  // beyond infinity
    for (double z : {0.3, 1.0, 7.5, 100.0}) EXPECT_NEAR(g.depth_of_disparity(g.disparity_of_depth(z)), z, 1e-12 * z);
}

TEST(lightfield, depth_of_field_matches_hand_computed_values) {
    const LightFieldGeometry g = geom(2.0, -0.5);
    // d_f = 0.5, r = 2, c = 1: in focus d in [0, 1]: near = 2 / 1.5, far = 2 / 0.5.
    DepthRange a = refocus_depth_of_field(g, 0.5, 2.0, 1.0);
    EXPECT_DOUBLE_EQ(a.near, 2.0 / 1.5);
    EXPECT_DOUBLE_EQ(a.far, 4.0);
    // d_f = 0, r = 1, c = 1: d in [-1, 1]; -1 is beyond infinity, so far = inf.
    DepthRange b = refocus_depth_of_field(g, 0.0, 1.0, 1.0);
    EXPECT_DOUBLE_EQ(b.near, 2.0 / 1.5);
    EXPECT_EQ(b.far, kInf);
    // Lower bound exactly at infinity: far = inf.
    DepthRange c = refocus_depth_of_field(g, 0.0, 2.0, 1.0);  // d in [-0.5, 0.5]
    EXPECT_DOUBLE_EQ(c.near, 2.0);
    EXPECT_EQ(c.far, kInf);
    // d_f = 1, r = 3, c = 0.75: d in [0.75, 1.25]: near = 2 / 1.75, far = 2 / 1.25.
    DepthRange d = refocus_depth_of_field(g, 1.0, 3.0, 0.75);
    EXPECT_DOUBLE_EQ(d.near, 2.0 / 1.75);
    EXPECT_DOUBLE_EQ(d.far, 2.0 / 1.25);
    // Radius 0: a pinhole, everything in focus.
    DepthRange e = refocus_depth_of_field(g, 0.3, 0.0, 1.0);
    EXPECT_EQ(e.near, 0.0);
    EXPECT_EQ(e.far, kInf);
    // Entirely beyond infinity: no depth.
    DepthRange f = refocus_depth_of_field(g, -3.0, 1.0, 1.0);
    EXPECT_TRUE(std::isnan(f.near) && std::isnan(f.far));
}

TEST(lightfield, negative_focal_baseline_orders_the_grid_the_other_way) {
    const LightFieldGeometry g = geom(-2.0, 0.5);
    EXPECT_DOUBLE_EQ(g.disparity_of_depth(2.0), -0.5);
    // d_f = -0.5, r = 2, c = 1: d in [-1, 0]: 1/z = (d - 0.5) / -2 in [0.25, 0.75].
    DepthRange a = refocus_depth_of_field(g, -0.5, 2.0, 1.0);
    EXPECT_DOUBLE_EQ(a.near, 1.0 / 0.75);
    EXPECT_DOUBLE_EQ(a.far, 4.0);
}

TEST(lightfield, stack_plan_fills_near_far_and_light_field_fields) {
    const LightField lf = small_lf(geom(2.0, -0.5));
    ExtractStackOptions spec;
    spec.coc_px = 1.0;
    spec.references = {{0.5, std::nan(""), 2.0}, {std::nan(""), 4.0, 1.0}, {std::nan(""), kInf, 2.0}};
    auto st = plan_stack(lf, spec);
    ASSERT_TRUE(st) << st.message();
    const FocalStack& s = *st;
    ASSERT_EQ(s.references.size(), 3u);
    EXPECT_EQ(s.width, 24);
    EXPECT_EQ(s.height, 16);
    EXPECT_DOUBLE_EQ(s.references[0].focus_disparity, 0.5);
    EXPECT_DOUBLE_EQ(s.references[0].aperture_radius_views, 2.0);
    EXPECT_DOUBLE_EQ(s.references[0].focus_distance, 2.0);
    EXPECT_DOUBLE_EQ(s.references[0].near, 2.0 / 1.5);
    EXPECT_DOUBLE_EQ(s.references[0].far, 4.0);
    EXPECT_DOUBLE_EQ(s.references[1].focus_disparity, 0.0);  // depth 4 -> 2/4 - 0.5
    EXPECT_DOUBLE_EQ(s.references[1].focus_distance, 4.0);
    EXPECT_DOUBLE_EQ(s.references[2].focus_disparity, -0.5);  // infinity
    EXPECT_TRUE(std::isnan(s.references[2].focus_distance));  // no finite focus distance
    EXPECT_DOUBLE_EQ(s.references[2].near, 2.0 / 0.5);        // d in [-1, 0]: 1/z = (0 + 0.5) / 2
    EXPECT_EQ(s.references[2].far, kInf);
    // The manifest writer keeps them (near/far explicit, far "inf").
    const std::string json = format_stack_manifest(s);
    EXPECT_NE(json.find("\"focus_disparity\""), std::string::npos);
    EXPECT_NE(json.find("\"inf\""), std::string::npos);
}

TEST(lightfield, stack_plan_rejects_duplicates_and_focus_beyond_infinity) {
    const LightField lf = small_lf(geom(2.0, -0.5));
    ExtractStackOptions dup;
    dup.references = {{0.0, std::nan(""), 1.0}, {std::nan(""), 4.0, 1.0}};  // depth 4 is disparity 0
    auto a = plan_stack(lf, dup);
    ASSERT_FALSE(a);
    EXPECT_NE(a.message().find("references[1]"), std::string::npos) << a.message();
    EXPECT_NE(a.message().find("duplicate"), std::string::npos) << a.message();

    ExtractStackOptions beyond;
    beyond.references = {{-3.0, std::nan(""), 1.0}};
    auto b = plan_stack(lf, beyond);
    ASSERT_FALSE(b);
    EXPECT_NE(b.message().find("beyond infinity"), std::string::npos) << b.message();

    ExtractStackOptions neg;
    neg.references = {{0.0, std::nan(""), -1.0}};
    auto c = plan_stack(lf, neg);
    ASSERT_FALSE(c);
    EXPECT_NE(c.message().find("references[0].aperture"), std::string::npos) << c.message();

    ExtractStackOptions coc;
    coc.coc_px = 0;
    coc.references = {{0.0, std::nan(""), 1.0}};
    EXPECT_FALSE(plan_stack(lf, coc));
}

TEST(lightfield, extract_stack_refocuses_every_reference_in_order) {
    test::Plane near{1.0, Roi{6, 4, 18, 12}, test::smooth_texture(1.0)};
    test::Plane far{0.0, Roi{}, test::smooth_texture(2.0)};
    LightField lf = test::make_planes_lightfield(5, 5, 24, 16, {near, far});
    ExtractStackOptions spec;
    spec.references = {{0.0, std::nan(""), 2.0}, {1.0, std::nan(""), 2.0}, {0.5, std::nan(""), 0.0}};
    std::vector<double> progress;
    Exec exec;
    exec.nthreads = 1;
    exec.progress = [&](double f) { progress.push_back(f); };
    auto r = extract_stack(lf, spec, {}, exec);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->images.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        auto want = refocus(lf, {r->stack.references[i].focus_disparity, r->stack.references[i].aperture_radius_views});
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 24; ++x) ASSERT_EQ(r->images[i].at(0, x, y), want->at(0, x, y));
    }
    ASSERT_FALSE(progress.empty());
    EXPECT_NEAR(progress.back(), 1.0, 1e-9);
    for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_GE(progress[i], progress[i - 1] - 1e-12);

    // With a sink, images go to it and are not kept.
    std::vector<std::size_t> seen;
    auto s = extract_stack(lf, spec, [&](std::size_t i, Image&&) {
        seen.push_back(i);
        return i == 1 ? Status::error("disk full") : Status::ok();
    });
    ASSERT_FALSE(s);
    EXPECT_EQ(s.message(), "disk full");
    EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1}));
}
