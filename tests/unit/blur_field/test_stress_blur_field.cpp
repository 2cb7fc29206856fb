// Numerical stress: the blur field and the thin lens under randomised and
// extreme inputs (issue 7, item 4): f-numbers 0.5..1024, focus at the near
// clip (just beyond the focal length), depths 1e-4..1e7, +inf (sky), float
// denormals, NaN; randomly built JSON fields (every kind and combinator);
// 1x1 and 1x10000 frames. Properties: B is never NaN (except for a NaN
// depth, as documented) and never negative, agrees with the thin-lens
// formulas, per-ray profiles stay sorted and NaN-free, invalid input is an
// error naming the culprit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "defocus_test_helpers.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "stress_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

std::string describe(const ThinLens& l) {
    return "f=" + num(l.focal_length_mm) + " mm, N=" + num(l.f_number) + ", s=" + num(l.focus_distance) +
           ", sensor=" + num(l.sensor_width_mm) + " mm, width=" + num(l.image_width_px) + " px, unit=" +
           num(l.scene_unit_mm) + " mm";
}

// A physically plausible random lens over the stress ranges. Focus is at
// the near clip (just beyond the focal length) a quarter of the time.
ThinLens random_lens(StressRng& rng) {
    ThinLens l;
    l.focal_length_mm = rng.log_uniform(1.0, 1000.0);
    l.f_number = rng.chance(0.1) ? rng.pick(std::vector<double>{0.5, 1024.0}) : rng.log_uniform(0.5, 1024.0);
    l.sensor_width_mm = rng.log_uniform(1.0, 100.0);
    l.image_width_px = double(rng.pick(std::vector<int>{1, 2, 640, 1920, 10000}));
    l.scene_unit_mm = rng.chance(0.7) ? 1000.0 : rng.log_uniform(1.0, 1e4);
    const double f_units = l.focal_length_mm / l.scene_unit_mm;
    if (rng.chance(0.25)) l.focus_distance = f_units * (1.0 + rng.log_uniform(1e-9, 1.0));  // near clip
    else l.focus_distance = std::max(f_units * 1.001, rng.log_uniform(1e-4, 1e7));
    return l;
}

const std::vector<Roi> kFrames = {{0, 0, 1, 1}, {0, 0, 10000, 1}, {0, 0, 1, 10000}, {-7, 3, 633, 363}};

// A random blur-field node as JSON (depth scale up to 1e7, radii up to 1000 px).
std::string random_node(StressRng& rng, int depth) {
    auto vec = [&](double scale) {
        return "[" + num(rng.uniform(-scale, scale)) + ", " + num(rng.uniform(-scale, scale)) + ", " +
               num(rng.uniform(0.0, scale)) + "]";
    };
    const int kind = rng.integer(0, depth >= 2 ? 3 : 8);
    switch (kind) {
        case 0: {  // thin_lens
            const double f = rng.log_uniform(5.0, 500.0);
            return R"({"kind": "thin_lens", "focal_length_mm": )" + num(f) + R"(, "f_number": )" +
                   num(rng.log_uniform(0.5, 1024.0)) + R"(, "focus_distance": )" +
                   num(f / 1000.0 * (1.0 + rng.log_uniform(1e-6, 1e6))) + "}";
        }
        case 1: {  // focal_planes
            std::string depths;
            const int n = rng.integer(1, 4);
            for (int i = 0; i < n; ++i) depths += (i ? ", " : "") + num(rng.log_uniform(1e-4, 1e7) * (1.0 + 1e-3 * i));
            const bool smooth = rng.chance(0.5);
            std::string s = R"({"kind": "focal_planes", "depths": [)" + depths + "], \"max_blur\": " +
                            num(rng.uniform(0.0, 1000.0));
            if (n == 1 || rng.chance(0.5)) s += ", \"slope\": " + num(rng.log_uniform(1e-6, 1e6));
            s += std::string(", \"interpolation\": \"") + (smooth ? "smooth" : "linear") + "\"}";
            return s;
        }
        case 2: {  // region
            const double scale = rng.log_uniform(1e-3, 1e7);
            std::string s = R"({"kind": "region", "mode": ")" + std::string(rng.chance(0.5) ? "focus" : "blur") +
                            R"(", "blur": )" + num(rng.uniform(0.0, 1000.0)) + R"(, "falloff": )" +
                            num(rng.chance(0.2) ? 0.0 : rng.log_uniform(1e-4, 1e6)) + R"(, "interpolation": ")" +
                            (rng.chance(0.5) ? "smooth" : "linear") + "\", ";
            switch (rng.integer(0, 2)) {
                case 0:
                    return s + R"("shape": "sphere", "center": )" + vec(scale) + R"(, "radius": )" +
                           num(rng.uniform(0.0, scale)) + "}";
                case 1:
                    return s + R"("shape": "box", "center": )" + vec(scale) + R"(, "size": [)" +
                           num(rng.uniform(0.0, scale)) + ", " + num(rng.uniform(0.0, scale)) + ", " +
                           num(rng.uniform(0.0, scale)) + R"(], "rotation_deg": [)" + num(rng.uniform(-180, 180)) +
                           ", " + num(rng.uniform(-180, 180)) + ", " + num(rng.uniform(-180, 180)) + "]}";
                default:
                    return s + R"("shape": "plane", "point": )" + vec(scale) + R"(, "normal": )" + vec(1.0) +
                           R"(, "thickness": )" + num(rng.uniform(0.0, scale)) + "}";
            }
        }
        case 3: {  // image_map (supplied as "m")
            return R"({"kind": "image_map", "image": "m", "scale": )" + num(rng.uniform(0.0, 1000.0)) + "}";
        }
        case 4:
        case 5:
        case 6: {
            const char* ops[] = {"min", "max", "add", "mul"};
            std::string s = std::string(R"({"kind": ")") + ops[rng.integer(0, 3)] + R"(", "children": [)";
            const int n = rng.integer(1, 3);
            for (int i = 0; i < n; ++i) s += (i ? ", " : "") + random_node(rng, depth + 1);
            return s + "]}";
        }
        case 7:
            return R"({"kind": "scale", "factor": )" + num(rng.chance(0.2) ? 0.0 : rng.log_uniform(1e-3, 1e3)) +
                   R"(, "child": )" + random_node(rng, depth + 1) + "}";
        default:
            return R"({"kind": "clamp", "min": )" + num(rng.uniform(0.0, 2.0)) + R"(, "max": )" +
                   num(rng.uniform(2.0, 1000.0)) + R"(, "child": )" + random_node(rng, depth + 1) + "}";
    }
}

// The painted map used by image_map nodes: random values, also negative,
// NaN, HDR and denormal ones (negative and NaN count as 0).
std::shared_ptr<Image> random_map(StressRng& rng, const Roi& display) {
    const Roi w{0, 0, rng.integer(1, 9), rng.integer(1, 9)};
    auto img = std::make_shared<Image>(Image::with_channels({"Y"}, w));
    img->set_display_window(w);
    for (int y = 0; y < w.y1; ++y)
        for (int x = 0; x < w.x1; ++x) {
            const int k = rng.integer(0, 9);
            img->at(0, x, y) = k == 0   ? float(kStressNaN)
                               : k == 1 ? -1.0f
                               : k == 2 ? kDenormF
                               : k == 3 ? float(kStressInf)  // e.g. a half overflow in a painted EXR
                                        : rng.pixel();
        }
    (void)display;
    return img;
}

struct RandomField {
    std::string json;
    BlurField field;
    double max_radius = kStressInf;
};

RandomField random_field(StressRng& rng, const Roi& display) {
    RandomField r;
    const bool clamp = rng.chance(0.3);
    if (clamp) r.max_radius = rng.uniform(0.0, 1000.0);
    r.json = R"({"blurfield": )" + random_node(rng, 0) + (clamp ? ", \"max_radius\": " + num(r.max_radius) : "") + "}";
    BlurField::Context ctx;
    ctx.images["m"] = random_map(rng, display);
    auto f = BlurField::parse(r.json, ctx);
    EXPECT_TRUE(f) << f.message() << "\n" << r.json;
    if (f) r.field = f.value();
    return r;
}

}  // namespace

// ThinLens::coc_radius_px over random lenses (f/0.5 .. f/1024, focus at the
// near clip) and depths 1e-4 .. 1e7, +inf, 0, negative, denormal, NaN.
TEST(stress_blur_field, thin_lens_coc_is_finite_ordered_and_matches_the_field) {
    GDOF_STRESS_RNG(rng, 1001);
    for (int iter = 0; iter < 400; ++iter) {
        const ThinLens l = random_lens(rng);
        SCOPED_TRACE("lens " + describe(l));
        ASSERT_TRUE(l.validate()) << l.validate().message();
        const double s = l.focus_distance;
        const double at_inf = l.coc_radius_px_at_infinity();
        ASSERT_TRUE(std::isfinite(at_inf) && at_inf > 0) << at_inf;
        EXPECT_EQ(l.coc_radius_px(kStressInf), at_inf);
        EXPECT_EQ(l.coc_radius_px(s), 0.0);  // exactly sharp at the focus distance
        EXPECT_TRUE(std::isinf(l.coc_radius_px(0.0)));
        EXPECT_TRUE(std::isinf(l.coc_radius_px(-rng.log_uniform(1e-4, 1e7))));
        EXPECT_TRUE(std::isnan(l.coc_radius_px(kStressNaN)));
        const double den = l.coc_radius_px(double(kDenormF));
        EXPECT_FALSE(std::isnan(den)) << "denormal depth";
        EXPECT_GE(den, 0.0);

        // Random depths: finite, non-negative, decreasing towards s from the
        // front, increasing beyond it and bounded by the value at infinity.
        std::vector<double> z(24);
        for (double& d : z) d = rng.log_uniform(1e-4, 1e7);
        std::sort(z.begin(), z.end());
        double prev = 0;
        for (std::size_t i = 0; i < z.size(); ++i) {
            const double c = l.coc_radius_px(z[i]);
            ASSERT_TRUE(std::isfinite(c) && c >= 0) << "depth " << num(z[i]) << " -> " << c;
            if (i > 0 && z[i] <= s) {
                EXPECT_LE(c, prev * (1 + 1e-12)) << "depth " << num(z[i]);
            }
            if (i > 0 && z[i - 1] >= s) {
                EXPECT_GE(c, prev * (1 - 1e-12)) << "depth " << num(z[i]);
            }
            if (z[i] >= s) {
                EXPECT_LE(c, at_inf * (1 + 1e-12)) << "depth " << num(z[i]);
            }
            prev = c;
        }

        // The thin_lens blur field gives the same radii (the camera supplies the width).
        const Roi frame = rng.pick(kFrames);
        ThinLens lw = l;
        lw.image_width_px = frame.width();
        auto field = BlurField::from_thin_lens(l);
        ASSERT_TRUE(field) << field.message();
        const Camera cam = test_camera(frame);
        for (int k = 0; k < 8; ++k) {
            const double d = rng.depth();
            const double px = rng.uniform(frame.x0, frame.x1), py = rng.uniform(frame.y0, frame.y1);
            const float b = field->evaluate_pixel(cam, px, py, d);
            const double want = lw.coc_radius_px(d);
            ASSERT_FALSE(std::isnan(b)) << "depth " << num(d);
            ASSERT_GE(b, 0.0f);
            if (std::isinf(float(want))) EXPECT_TRUE(std::isinf(b)) << "depth " << num(d) << " B " << b;
            else EXPECT_NEAR(b, want, 1e-5 * want + 1e-30) << "depth " << num(d);
        }
    }
}

// Parameters anywhere in the double range (denormal to 1e308, 0, negative,
// NaN, inf): validate() either rejects the lens with a message naming a
// parameter, or the lens and its blur field never produce NaN for a
// non-NaN depth.
TEST(stress_blur_field, thin_lens_validate_rejects_what_would_give_nan) {
    GDOF_STRESS_RNG(rng, 1002);
    const std::vector<std::string> names = {"focal_length_mm", "f_number",       "focus_distance",
                                            "sensor_width_mm", "image_width_px", "scene_unit_mm"};
    auto wild = [&]() -> double {
        switch (rng.integer(0, 9)) {
            case 0: return kStressNaN;
            case 1: return rng.chance(0.5) ? kStressInf : -kStressInf;
            case 2: return 0.0;
            case 3: return -rng.log_uniform(1e-3, 1e3);
            case 4: return rng.log_uniform(4.9e-324, 1e-300);  // denormal .. tiny
            case 5: return rng.log_uniform(1e300, 1.7e308);    // huge
            default: return rng.log_uniform(1e-3, 1e4);
        }
    };
    const Camera cam = test_camera({0, 0, 640, 360});
    int accepted = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        ThinLens l = random_lens(rng);
        const int nbad = rng.integer(1, 2);
        for (int k = 0; k < nbad; ++k) {
            switch (rng.integer(0, 5)) {
                case 0: l.focal_length_mm = wild(); break;
                case 1: l.f_number = wild(); break;
                case 2: l.focus_distance = wild(); break;
                case 3: l.sensor_width_mm = wild(); break;
                case 4: l.image_width_px = wild(); break;
                default: l.scene_unit_mm = wild(); break;
            }
        }
        SCOPED_TRACE("lens " + describe(l));
        const Status st = l.validate();
        auto field = BlurField::from_thin_lens(l);
        if (!st) {
            bool named = false;
            for (const auto& n : names) named = named || contains(st.message(), n);
            EXPECT_TRUE(named) << st.message();
            ThinLens unit_width = l;  // the field takes the width from the camera
            unit_width.image_width_px = 1;
            if (!unit_width.validate()) {
                EXPECT_FALSE(field);
            }
            continue;
        }
        ++accepted;
        const double depths[] = {l.focus_distance, 1e-4, 1e7, kStressInf, double(kDenormF), 1e300, 0.0, -1.0,
                                 rng.log_uniform(1e-4, 1e7)};
        for (double d : depths) {
            EXPECT_FALSE(std::isnan(l.coc_radius_px(d))) << "depth " << num(d);
            EXPECT_FALSE(std::isnan(l.coc_diameter_mm(d))) << "depth " << num(d);
        }
        if (field) {
            for (double d : depths) EXPECT_FALSE(std::isnan(field->evaluate_pixel(cam, 320.5, 180.5, d))) << "depth " << num(d);
        }
    }
    EXPECT_GT(accepted, 100);  // the test also exercises valid lenses

    // The same through JSON: each value is a valid positive number, together they overflow.
    auto f = BlurField::parse(
        R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 1e-310, "focus_distance": 2}})");
    ASSERT_FALSE(f);
    EXPECT_TRUE(contains(f.message(), "blurfield.f_number")) << f.message();
}

// Random JSON fields of every kind and combinator, evaluated over extreme
// depths (including +inf = sky, which layers may hold at covered pixels) on
// 1x1, 1x10000, 10000x1 and ordinary frames: never NaN, never negative,
// never above max_radius; the batch and single-point paths agree.
TEST(stress_blur_field, random_fields_are_never_nan_at_extreme_depths) {
    GDOF_STRESS_RNG(rng, 1003);
    for (int iter = 0; iter < 300; ++iter) {
        const Roi frame = rng.pick(kFrames);
        const RandomField rf = random_field(rng, frame);
        SCOPED_TRACE("field " + rf.json);
        const Camera cam = test_camera(frame);
        std::vector<PixelDepth> samples(64);
        for (auto& s : samples) {
            s.x = rng.chance(0.2) ? double(frame.x0) : rng.uniform(frame.x0, frame.x1);
            s.y = rng.chance(0.2) ? double(frame.y1) : rng.uniform(frame.y0, frame.y1);
            s.depth = rng.depth();
        }
        std::vector<float> out(samples.size());
        ASSERT_TRUE(rf.field.evaluate(cam, std::span<const PixelDepth>(samples), std::span<float>(out)));
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const auto& s = samples[i];
            ASSERT_FALSE(std::isnan(out[i])) << "at pixel (" << num(s.x) << ", " << num(s.y) << "), depth "
                                             << num(s.depth);
            EXPECT_GE(out[i], 0.0f);
            if (std::isfinite(rf.max_radius)) {
                EXPECT_LE(out[i], float(rf.max_radius));
            }
            const float single = rf.field.evaluate_pixel(cam, s.x, s.y, s.depth);
            EXPECT_TRUE(single == out[i]) << single << " vs " << out[i];
        }
    }
}

// Per-ray profiles over [1e-4, 1e7] (and from the lens plane, depth 0) for
// random fields and pixels: sorted, NaN-free, InFocus exactly where B == 0,
// subdivision capped by max_vertices.
TEST(stress_blur_field, ray_profiles_over_huge_depth_ranges_stay_sorted_and_finite) {
    GDOF_STRESS_RNG(rng, 1004);
    for (int iter = 0; iter < 150; ++iter) {
        const Roi frame = rng.pick(kFrames);
        const RandomField rf = random_field(rng, frame);
        SCOPED_TRACE("field " + rf.json);
        const Camera cam = test_camera(frame);
        const double px = rng.uniform(frame.x0, frame.x1), py = rng.uniform(frame.y0, frame.y1);
        const double dmin = rng.chance(0.2) ? 0.0 : 1e-4, dmax = rng.chance(0.5) ? 1e7 : rng.log_uniform(1e-3, 1e7);
        RayProfileOptions opts;
        opts.max_vertices = 300;
        opts.tolerance_px = rng.log_uniform(1e-3, 1.0);
        auto p = rf.field.sample_along_ray(cam, px, py, dmin, dmax, opts);
        ASSERT_TRUE(p) << p.message();
        ASSERT_GE(p->size(), 2u);
        ASSERT_EQ(p->radius.size(), p->size());
        ASSERT_EQ(p->kind.size(), p->size());
        EXPECT_EQ(p->depth.front(), dmin);
        EXPECT_EQ(p->depth.back(), dmax);
        std::size_t samples = 0;
        for (std::size_t i = 0; i < p->size(); ++i) {
            ASSERT_FALSE(std::isnan(p->radius[i])) << "vertex " << i << " depth " << num(p->depth[i]);
            EXPECT_GE(p->radius[i], 0.0);
            if (i > 0) {
                EXPECT_LT(p->depth[i - 1], p->depth[i]) << "vertex " << i;
            }
            EXPECT_EQ(p->kind[i] == RayProfile::InFocus, p->radius[i] == 0.0) << "vertex " << i;
            samples += p->kind[i] == RayProfile::Sample;
        }
        EXPECT_LE(samples, std::size_t(opts.max_vertices));
        for (int k = 0; k < 16; ++k) EXPECT_FALSE(std::isnan(p->radius_at(rng.uniform(dmin, dmax))));

        auto iv = rf.field.in_focus_interval(cam, px, py, rng.uniform(0.0, 10.0), dmin, kStressInf, opts);
        ASSERT_TRUE(iv) << iv.message();
        double last = -1;
        for (const DepthInterval& d : iv->intervals) {
            EXPECT_FALSE(std::isnan(d.near) || std::isnan(d.far));
            EXPECT_LE(d.near, d.far);
            EXPECT_GT(d.near, last);  // sorted, disjoint
            last = d.far;
        }
        const DepthInterval prim = iv->primary();
        EXPECT_FALSE(std::isnan(prim.near) || std::isnan(prim.far));
    }
}

// The in-focus interval of a thin lens equals its depth-of-field limits
// over f/0.5 .. f/1024, focus from the near clip to 1e4 units and acceptable
// CoCs from 0.1 to 100 px (docs: 1e-6 relative), up to the analysed range.
TEST(stress_blur_field, in_focus_interval_equals_thin_lens_dof_limits_at_the_extremes) {
    GDOF_STRESS_RNG(rng, 1005);
    for (int iter = 0; iter < 300; ++iter) {
        ThinLens l;
        l.focal_length_mm = rng.log_uniform(10.0, 300.0);
        l.f_number = rng.log_uniform(0.5, 1024.0);
        const double f_units = l.focal_length_mm / 1000.0;
        l.focus_distance = rng.chance(0.3) ? f_units * (1.0 + rng.log_uniform(1e-6, 1e-1)) : rng.log_uniform(f_units * 1.2, 1e4);
        const Roi frame{0, 0, rng.pick(std::vector<int>{1, 640, 10000}), 1};
        l.image_width_px = frame.width();
        const double coc = rng.log_uniform(0.1, 100.0);
        SCOPED_TRACE("lens " + describe(l) + ", coc " + num(coc));
        auto field = BlurField::from_thin_lens(l);
        ASSERT_TRUE(field) << field.message();
        const Camera cam = test_camera(frame);
        const double dmin = 1e-4;
        auto iv = field->in_focus_interval(cam, 0.5, 0.5, coc, dmin, kStressInf);
        ASSERT_TRUE(iv) << iv.message();
        ASSERT_FALSE(iv->empty());
        const DepthInterval got = iv->primary();
        const ThinLens::DofLimits want = l.dof_limits(coc);
        const double analysed = 1e12 * dmin;  // documented end of the analysis for depth_max = inf
        EXPECT_NEAR(got.near, std::max(want.near, dmin), 1e-6 * want.near);
        if (std::isinf(want.far) || want.far > analysed) EXPECT_TRUE(std::isinf(got.far)) << num(got.far);
        else EXPECT_NEAR(got.far, want.far, 1e-6 * want.far);
        EXPECT_TRUE(got.contains(l.focus_distance));
    }
}

// Invalid JSON values are errors naming the key path; numbers beyond the
// double range are errors naming the position.
TEST(stress_blur_field, invalid_values_are_errors_naming_the_key) {
    GDOF_STRESS_RNG(rng, 1006);
    struct Case {
        std::string before, key, after;
    };
    // Each text has one value left open: before + value + after.
    const std::vector<Case> cases = {
        {R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": )", "blurfield.focal_length_mm",
         R"(, "f_number": 2, "focus_distance": 2}})"},
        {R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": )", "blurfield.f_number",
         R"(, "focus_distance": 2}})"},
        {R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": )",
         "blurfield.focus_distance", "}}"},
        {R"({"blurfield": {"kind": "focal_planes", "depths": [1, )", "blurfield.depths", R"(], "max_blur": 3}})"},
        {R"({"blurfield": {"kind": "focal_planes", "depths": [1, 2], "max_blur": )", "blurfield.max_blur", "}}"},
        {R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 1], "radius": )", "blurfield.radius",
         R"(, "blur": 3}})"},
        {R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 1], "radius": 1, "blur": )",
         "blurfield.blur", "}}"},
        {R"({"blurfield": {"kind": "max", "children": [{"kind": "scale", "factor": )", "blurfield.children[0].factor",
         R"(, "child": {"kind": "focal_planes", "depths": [1], "slope": 1}}]}})"},
        {R"({"blurfield": {"kind": "focal_planes", "depths": [1], "slope": 1}, "max_radius": )", "max_radius", "}"},
    };
    const std::vector<std::string> bad_values = {"-1", "-1e-300", "\"nan\"", "\"inf\"", "null", "[]", "{}", "true"};
    for (int iter = 0; iter < 60; ++iter) {
        const Case& c = rng.pick(cases);
        const std::string v = rng.pick(bad_values);
        SCOPED_TRACE(c.before + v + c.after);
        auto f = BlurField::parse(c.before + v + c.after);
        ASSERT_FALSE(f);
        EXPECT_TRUE(contains(f.message(), c.key)) << f.message();
    }
    for (const Case& c : cases) {
        auto f = BlurField::parse(c.before + "1e400" + c.after);
        ASSERT_FALSE(f) << c.key;
        EXPECT_TRUE(contains(f.message(), "overflow") && contains(f.message(), "line")) << f.message();
    }
}
