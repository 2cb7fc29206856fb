// Thin-lens CoC, depth-of-field limits and hyperfocal distance against values
// computed by hand from the formulas (written out in the comments).
#include <cmath>
#include <limits>

#include "gdof/camera.h"
#include "test_support.h"

using gdof::ThinLens;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// 50 mm f/2 focused at 2 m, 36 mm sensor, 1920 px wide, scene units metres.
ThinLens lens50() {
    ThinLens l;
    l.focal_length_mm = 50;
    l.f_number = 2;
    l.focus_distance = 2;
    l.sensor_width_mm = 36;
    l.image_width_px = 1920;
    l.scene_unit_mm = 1000;
    return l;
}

void expect_rel(double got, double want, double rel = 1e-9) {
    EXPECT_NEAR(got, want, rel * std::fabs(want)) << "got " << got << " want " << want;
}

}  // namespace

TEST(thin_lens, CocHandValues) {
    const ThinLens l = lens50();
    ASSERT_TRUE(l.validate()) << l.validate().message();
    // Aperture A = f/N = 25 mm; s - f = 2000 - 50 = 1950 mm; px per mm = 1920/36 = 160/3.
    // z = 4 m: c = 25 * 50 * |4000 - 2000| / (4000 * 1950) = 25/78 mm
    //          radius = c/2 * 160/3 = 25/156 * 160/3 = 4000/468 px = 8.547008547...
    expect_rel(l.coc_diameter_mm(4.0), 25.0 / 78.0);
    expect_rel(l.coc_radius_px(4.0), 4000.0 / 468.0);
    // z = 1 m: c = 1250 * 1000 / (1000 * 1950) = 25/39 mm; radius = 25/78 * 160/3 = 4000/234 px.
    expect_rel(l.coc_diameter_mm(1.0), 25.0 / 39.0);
    expect_rel(l.coc_radius_px(1.0), 4000.0 / 234.0);
    // z -> inf: c = A f / (s - f) = 1250 / 1950 = 25/39 mm (same as at s/2).
    expect_rel(l.coc_diameter_mm(kInf), 25.0 / 39.0);
    expect_rel(l.coc_radius_px_at_infinity(), 4000.0 / 234.0);
    // z = 0.5 m: c = 1250 * 1500 / (500 * 1950) = 1.923076923 mm = 25/13; radius = 25/26 * 160/3 = 4000/78.
    expect_rel(l.coc_radius_px(0.5), 4000.0 / 78.0);
}

TEST(thin_lens, ZeroAtFocusAndShape) {
    const ThinLens l = lens50();
    EXPECT_EQ(l.coc_radius_px(2.0), 0.0);
    // Strictly decreasing before the focus distance, increasing after it.
    double prev = kInf;
    for (double z = 0.1; z < 2.0; z *= 1.05) {
        const double c = l.coc_radius_px(z);
        EXPECT_LT(c, prev) << z;
        prev = c;
    }
    prev = 0;
    for (double z = 2.001; z < 1e4; z *= 1.2) {
        const double c = l.coc_radius_px(z);
        EXPECT_GT(c, prev) << z;
        EXPECT_LT(c, l.coc_radius_px_at_infinity());
        prev = c;
    }
    // Symmetric in inverse depth: 1/z1 + 1/z2 = 2/s gives equal CoC.
    for (double z1 : {1.2, 1.5, 1.9}) {
        const double z2 = 1.0 / (2.0 / 2.0 - 1.0 / z1);
        expect_rel(l.coc_radius_px(z1), l.coc_radius_px(z2), 1e-12);
    }
    // Linear in f-number: doubling N halves the CoC.
    ThinLens l2 = l;
    l2.f_number = 4;
    expect_rel(l2.coc_radius_px(5.0), 0.5 * l.coc_radius_px(5.0), 1e-12);
}

TEST(thin_lens, SpecialDepths) {
    const ThinLens l = lens50();
    EXPECT_TRUE(std::isinf(l.coc_radius_px(0.0)));
    EXPECT_TRUE(std::isinf(l.coc_radius_px(-1.0)));
    EXPECT_TRUE(std::isnan(l.coc_radius_px(std::numeric_limits<double>::quiet_NaN())));
    EXPECT_TRUE(std::isfinite(l.coc_radius_px(0.02)));  // inside the focal length: large but finite
}

TEST(thin_lens, HyperfocalAndDofLimits) {
    const ThinLens l = lens50();
    // Acceptable CoC radius 1 px -> sensor diameter c = 2 / (160/3) = 0.0375 mm.
    expect_rel(l.acceptable_coc_mm(1.0), 0.0375);
    // H = f^2 / (N c) + f = 2500 / (2 * 0.0375) + 50 = 33333.33... + 50 mm = 33.38333... m
    expect_rel(l.hyperfocal_distance(1.0), (2500.0 / 0.075 + 50.0) / 1000.0);
    // H' = H - f = 100000/3 mm.  near = s H' / (H' + s - f), far = s H' / (H' - (s - f))
    const double hp = 100000.0 / 3.0;
    const double near_mm = 2000.0 * hp / (hp + 1950.0);  // 1889.466...
    const double far_mm = 2000.0 * hp / (hp - 1950.0);   // 2124.269...
    const auto lim = l.dof_limits(1.0);
    expect_rel(lim.near, near_mm / 1000.0);
    expect_rel(lim.far, far_mm / 1000.0);
    EXPECT_NEAR(lim.near, 1.889466, 1e-6);
    EXPECT_NEAR(lim.far, 2.124269, 1e-6);
    // The CoC at the limits is the acceptable CoC.
    expect_rel(l.coc_radius_px(lim.near), 1.0, 1e-12);
    expect_rel(l.coc_radius_px(lim.far), 1.0, 1e-12);
    // Standard form with H: near = s (H - f) / (H + s - 2f).
    const double H = l.hyperfocal_distance(1.0) * 1000.0;
    expect_rel(lim.near, 2000.0 * (H - 50.0) / (H + 2000.0 - 100.0) / 1000.0, 1e-12);

    // Focused at the hyperfocal distance: near = H/2, far = inf.
    ThinLens lh = l;
    lh.focus_distance = l.hyperfocal_distance(1.0);
    const auto limh = lh.dof_limits(1.0);
    expect_rel(limh.near, lh.focus_distance / 2.0, 1e-12);
    EXPECT_TRUE(std::isinf(limh.far));
    // Beyond: far stays infinite; the CoC at infinity is below the acceptable one.
    lh.focus_distance *= 1.5;
    EXPECT_TRUE(std::isinf(lh.dof_limits(1.0).far));
    EXPECT_LT(lh.coc_radius_px_at_infinity(), 1.0);
    // A zero CoC collapses to the focus distance.
    const auto lim0 = l.dof_limits(0.0);
    EXPECT_EQ(lim0.near, 2.0);
    EXPECT_EQ(lim0.far, 2.0);
}

TEST(thin_lens, SceneUnits) {
    ThinLens m = lens50();
    ThinLens cm = m;
    cm.scene_unit_mm = 10;       // centimetres
    cm.focus_distance = 200;     // 2 m
    expect_rel(cm.coc_radius_px(400), m.coc_radius_px(4.0), 1e-12);
    expect_rel(cm.dof_limits(1.0).near, 100.0 * m.dof_limits(1.0).near, 1e-12);
}

TEST(thin_lens, ValidationNamesParameter) {
    auto bad = [](auto mutate, const char* name) {
        ThinLens l = lens50();
        mutate(l);
        gdof::Status s = l.validate();
        EXPECT_FALSE(s);
        EXPECT_NE(s.message().find(name), std::string::npos) << s.message();
    };
    bad([](ThinLens& l) { l.f_number = 0; }, "f_number");
    bad([](ThinLens& l) { l.f_number = -2; }, "f_number");
    bad([](ThinLens& l) { l.focal_length_mm = 0; }, "focal_length_mm");
    bad([](ThinLens& l) { l.focal_length_mm = std::numeric_limits<double>::quiet_NaN(); }, "focal_length_mm");
    bad([](ThinLens& l) { l.focus_distance = 0.04; }, "focus_distance");  // 40 mm < 50 mm focal length
    bad([](ThinLens& l) { l.focus_distance = kInf; }, "focus_distance");
    bad([](ThinLens& l) { l.sensor_width_mm = -1; }, "sensor_width_mm");
    bad([](ThinLens& l) { l.image_width_px = 0; }, "image_width_px");
    bad([](ThinLens& l) { l.scene_unit_mm = 0; }, "scene_unit_mm");
}
