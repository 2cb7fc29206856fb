// Numerical stress: heat diffusion (method 3) from the solvers up to whole
// inputs (issue 7, item 4). Random radius maps 0..1000 px, HDR (1e6) and
// denormal pixels, 1x1, 1x10000 and 10000x1 images, empty layers, depths
// 1e-4..1e7, +inf (sky), NaN and denormal depths, NaN/Inf colour.
// Properties: no NaN/Inf out; premultiplied totals conserved (insulated
// borders); the maximum principle (a constant stays constant, values stay
// within the input's range, opaque stays opaque); empty layers change
// nothing; invalid input is an error naming the layer, channel and pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "defocus_test_helpers.h"
#include "diffusion/diffusion_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/diffusion.h"
#include "gdof/fill.h"
#include "gdof/layers.h"
#include "stress_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

// The exact operator (conservative to rounding); the pyramid's own totals
// are tested in test_defocus_pyramid.cpp.
DefocusOptions full_resolution() {
    DefocusOptions s;
    s.diffusion.pyramid = false;
    return s;
}

// The stress sizes: 1x1, a 1-pixel row and column of 10000, and random small ones.
// A radius map: all zero, constant, or random with zero patches, up to r_max.
std::vector<float> random_radii(StressRng& rng, std::size_t n, double r_max) {
    std::vector<float> r(n, 0.0f);
    const int mode = rng.integer(0, 3);
    const float c = float(rng.uniform(0.0, r_max));
    for (std::size_t i = 0; i < n; ++i) {
        if (mode == 0) r[i] = 0.0f;
        else if (mode == 1) r[i] = c;
        else r[i] = rng.chance(0.3) ? 0.0f : rng.chance(0.05) ? kDenormF : float(rng.uniform(0.0, r_max));
    }
    return r;
}

double sum(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s;
}

BlurField parse_field(const std::string& json) {
    auto f = BlurField::parse(json);
    EXPECT_TRUE(f) << f.message() << "\n" << json;
    return f ? f.value() : BlurField();
}

// A thin lens focused at the near clip or anywhere, f/0.5 .. f/1024, clamped
// to `max_radius` px (JSON) so extreme depths stay within the solver's range.
std::string random_thin_lens_json(StressRng& rng, double max_radius) {
    const double f = rng.log_uniform(10.0, 200.0);
    const double s = rng.chance(0.3) ? f / 1000.0 * (1.0 + rng.log_uniform(1e-6, 1e-2)) : rng.log_uniform(f / 500.0, 1e4);
    return R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": )" + num(f) + R"(, "f_number": )" +
           num(rng.log_uniform(0.5, 1024.0)) + R"(, "focus_distance": )" + num(s) + "}, \"max_radius\": " +
           num(max_radius) + "}";
}

double plane_min(const Image& img, int c, const Roi& r) {
    double m = kStressInf;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) m = std::min(m, value_at(img, c, x, y));
    return m;
}
double plane_max(const Image& img, int c, const Roi& r) {
    double m = -kStressInf;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) m = std::max(m, value_at(img, c, x, y));
    return m;
}

}  // namespace

// The solvers on random radius maps (ADI up to 1000 px; explicit up to 20 px,
// its cost grows with R^2): finite output, totals conserved, values within
// the input's range (maximum principle), a constant plane unchanged (a
// denormal one may become 0), a 1x1 image bit-identical.
TEST(stress_diffusion, solvers_conserve_totals_and_obey_the_maximum_principle) {
    GDOF_STRESS_RNG(rng, 2001);
    for (int iter = 0; iter < 60; ++iter) {
        const Size sz = random_size(rng, 48);
        const std::size_t n = std::size_t(sz.w) * std::size_t(sz.h);
        DiffusionOptions ds;
        ds.solver = rng.chance(0.5) ? DiffusionSolver::Adi : DiffusionSolver::Explicit;
        const bool big = sz.w * sz.h > 3000;
        const double r_max =
            ds.solver == DiffusionSolver::Explicit ? (big ? 4.0 : 20.0) : rng.pick(std::vector<double>{2.0, 60.0, 1000.0});
        const std::vector<float> radius = random_radii(rng, n, r_max);
        std::vector<float> hdr(n), constant(n, float(rng.pixel())), orig;
        for (float& v : hdr) v = rng.pixel();
        orig = hdr;
        const std::vector<float> constant_in = constant;
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", solver " << to_string(ds.solver) << ", radii up to "
                                          << r_max << ", constant " << constant_in[0]);
        const Status st = test::diffuse_vectors({&hdr, &constant}, sz.w, sz.h, radius, ds);
        ASSERT_TRUE(st) << st.message();

        const double s_in = sum(orig), s_out = sum(hdr);
        EXPECT_NEAR(s_out, s_in, 1e-4 * s_in + 1e-30) << "total not conserved";
        const float lo = *std::min_element(orig.begin(), orig.end()), hi = *std::max_element(orig.begin(), orig.end());
        std::size_t bad = 0, first = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const bool ok = std::isfinite(hdr[i]) && hdr[i] >= lo * (1 - 1e-5f) - 1e-30f && hdr[i] <= hi * (1 + 1e-5f);
            if (!ok && bad++ == 0) first = i;
        }
        EXPECT_EQ(bad, 0u) << "first at index " << first << ": " << hdr[first] << " outside [" << lo << ", " << hi << "]";
        // A denormal constant may be flushed to zero (the solvers run with
        // FTZ/DAZ: docs/diffusion.md); any normal one stays.
        const bool denormal = std::fpclassify(constant_in[0]) == FP_SUBNORMAL;
        for (std::size_t i = 0; i < n; ++i)
            if (!(std::fabs(constant[i] - constant_in[i]) <= 1e-5f * constant_in[i]) && !(denormal && constant[i] == 0.0f)) {
                ADD_FAILURE() << "constant plane changed at index " << i << ": " << constant[i];
                break;
            }
        if (n == 1) {
            const bool flushed = std::fpclassify(orig[0]) == FP_SUBNORMAL && hdr[0] == 0.0f;
            EXPECT_TRUE(flushed || std::memcmp(hdr.data(), orig.data(), sizeof(float)) == 0)
                << "1x1 must be the identity (a denormal may become 0): " << orig[0] << " -> " << hdr[0];
        }
    }
}

// Invalid radii (NaN, +-inf, negative, above max_radius) anywhere: an error
// naming that pixel, and the planes are left untouched.
TEST(stress_diffusion, invalid_radii_are_errors_naming_the_pixel) {
    GDOF_STRESS_RNG(rng, 2002);
    const std::vector<float> bad_values = {float(kStressNaN), float(kStressInf), -float(kStressInf), -1.0f, -kDenormF, 5000.0f};
    for (int iter = 0; iter < 40; ++iter) {
        const Size sz = random_size(rng, 48);
        const std::size_t n = std::size_t(sz.w) * std::size_t(sz.h);
        std::vector<float> radius = random_radii(rng, n, 10.0);
        const std::size_t at = std::size_t(rng.integer(0, int(n) - 1));
        const float bad = rng.pick(bad_values);
        radius[at] = bad;
        std::vector<float> plane(n);
        for (float& v : plane) v = rng.pixel();
        const std::vector<float> orig = plane;
        DiffusionOptions ds;
        ds.solver = rng.chance(0.5) ? DiffusionSolver::Adi : DiffusionSolver::Explicit;
        const Status st = test::diffuse_vectors({&plane}, sz.w, sz.h, radius, ds);
        const std::string where = "(" + std::to_string(int(at % std::size_t(sz.w))) + ", " +
                                  std::to_string(int(at / std::size_t(sz.w)));
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", radius " << bad << " at " << where << ")");
        ASSERT_FALSE(st);  // also -1e-41: negative radii are errors (diffusion.h)
        EXPECT_TRUE(contains(st.message(), where)) << st.message();
        EXPECT_EQ(std::memcmp(plane.data(), orig.data(), n * sizeof(float)), 0) << "planes changed on error";
    }
}

// An opaque layer covering the frame with a constant blur (0..1000 px) and
// HDR / denormal colour: premultiplied totals conserved, alpha stays 1 at
// every pixel, nothing non-finite, output window = the frame.
TEST(stress_diffusion, opaque_constant_blur_layer_conserves_premultiplied_totals) {
    GDOF_STRESS_RNG(rng, 2003);
    for (int iter = 0; iter < 24; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi frame{rng.integer(-5, 5), rng.integer(-5, 5), 0, 0};
        const Roi f{frame.x0, frame.y0, frame.x0 + sz.w, frame.y0 + sz.h};
        const double R = rng.chance(0.2) ? 0.0 : rng.log_uniform(0.01, 1000.0);
        const double depth = rng.depth();
        std::vector<Rgba> colours(f.npixels());
        for (auto& c : colours) c = {rng.pixel(), rng.pixel(), rng.pixel(), 1.0f};
        auto colour = [&](int x, int y) { return colours[std::size_t(y - f.y0) * std::size_t(sz.w) + std::size_t(x - f.x0)]; };
        Layer layer = make_layer(f, f, colour, depth);
        DefocusOptions s;
        s.diffusion.pyramid = false;  // the exact operator; the pyramid's totals: test_defocus_pyramid
        s.diffusion.solver = R <= 8 && f.npixels() < 3000 && rng.chance(0.5) ? DiffusionSolver::Explicit : DiffusionSolver::Adi;
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << " at (" << f.x0 << ", " << f.y0 << "), R " << R
                                          << ", depth " << depth << ", solver " << to_string(s.diffusion.solver));
        auto out = defocus_layers({layer}, constant_field(f, R), test_camera(f), s);
        ASSERT_TRUE(out) << out.message();
        EXPECT_EQ(out->data_window(), f);
        EXPECT_EQ(first_nonfinite(*out), "");
        for (int c = 0; c < 4; ++c) {
            // Pixel values below the float normal range may be flushed to zero (FTZ/DAZ).
            const double in = channel_sum(layer.image, c), o = channel_sum(*out, c);
            EXPECT_NEAR(o, in, 1e-4 * in + double(f.npixels()) * FLT_MIN) << "channel " << c;
        }
        EXPECT_NEAR(plane_min(*out, 3, f), 1.0, 1e-5);
        EXPECT_NEAR(plane_max(*out, 3, f), 1.0, 1e-5);
    }
}

// A single layer with random coverage (semi-transparent, holes, HDR colour)
// and a random per-pixel blur map (image_map, 0..R px): totals conserved
// (the frame and the work regions insulate), alpha within [0, 1], finite.
TEST(stress_diffusion, partial_layer_with_varying_blur_conserves_totals) {
    GDOF_STRESS_RNG(rng, 2004);
    for (int iter = 0; iter < 24; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi f{0, 0, sz.w, sz.h};
        const double R = rng.pick(std::vector<double>{1.0, 30.0, 1000.0});
        std::vector<float> map(f.npixels());
        for (float& m : map) m = rng.chance(0.2) ? 0.0f : float(rng.uniform(0.0, 1.0));
        std::vector<Rgba> colours(f.npixels());
        for (auto& c : colours) {
            const float a = rng.chance(0.3) ? 0.0f : rng.chance(0.5) ? 1.0f : float(rng.uniform(0.0, 1.0));
            c = {a * rng.pixel(), a * rng.pixel(), a * rng.pixel(), a};
        }
        Layer layer = make_layer(f, f, [&](int x, int y) { return colours[std::size_t(y) * std::size_t(sz.w) + std::size_t(x)]; }, 3.0);
        const BlurField field = map_field(f, [&](int x, int y) { return map[std::size_t(y) * std::size_t(sz.w) + std::size_t(x)]; }, R);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", R " << R);
        auto out = defocus_layers({layer}, field, test_camera(f), full_resolution());
        ASSERT_TRUE(out) << out.message();
        EXPECT_EQ(first_nonfinite(*out), "");
        for (int c = 0; c < 4; ++c) {
            const double in = channel_sum(layer.image, c), o = channel_sum(*out, c);
            EXPECT_NEAR(o, in, 1e-4 * in + 1e-30) << "channel " << c;
        }
        EXPECT_GE(plane_min(*out, 3, out->data_window()), 0.0);
        EXPECT_LE(plane_max(*out, 3, out->data_window()), 1.0 + 1e-5);
    }
}

// Empty layers (empty data window, no coverage, NaN depth everywhere) in any
// position of the list change nothing: the result is bit-identical to the
// one without them (their windows lie inside the result's: a layer's data
// window is part of the result by definition). No layers: an empty result.
TEST(stress_diffusion, empty_layers_change_nothing) {
    GDOF_STRESS_RNG(rng, 2005);
    const Roi f{0, 0, 40, 30};
    for (int iter = 0; iter < 8; ++iter) {
        std::vector<Layer> real;
        const int nreal = rng.integer(1, 3);
        for (int i = 0; i < nreal; ++i) {
            const Roi w{rng.integer(-3, 20), rng.integer(-3, 15), rng.integer(21, 44), rng.integer(16, 33)};
            const float a = float(rng.uniform(0.2, 1.0));
            real.push_back(make_layer(w, f, [&](int x, int y) { return Rgba{a * texture(x, y, 0), a * texture(x, y, 1), a, a}; },
                                      2.0 + i));
        }
        std::vector<Layer> with_empty;
        for (const Layer& l : real) {
            while (rng.chance(0.5)) {
                Layer e;
                switch (rng.integer(0, 2)) {
                    case 0:  // empty data window
                        e.image = Image(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, Roi{}, f);
                        break;
                    case 1:  // a window with no coverage (Z NaN everywhere)
                        e = make_layer(Roi{0, 0, 40, 30}, f, [](int, int) { return Rgba{0, 0, 0, 0}; });
                        break;
                    default: {  // a small window somewhere in the frame, transparent black at depth 1e-4
                        const int x0 = rng.integer(0, 39), y0 = rng.integer(0, 29);
                        e = make_layer(Roi{x0, y0, x0 + 1, y0 + rng.integer(1, 30 - y0)}, f,
                                       [](int, int) { return Rgba{0, 0, 0, 0}; });
                        e.image.at(4, x0, y0) = 1e-4f;
                        break;
                    }
                }
                e.depth_near = e.depth_far = kStressNaN;
                with_empty.push_back(std::move(e));
            }
            with_empty.push_back(l);
        }
        const BlurField field = map_field(f, [](int x, int) { return float(x % 7); }, 2.0);
        DefocusOptions s;
        s.diffusion.adi_steps = 4;  // speed: the property does not depend on the kernel's shape
        auto a = defocus_layers(real, field, test_camera(f), s);
        auto b = defocus_layers(with_empty, field, test_camera(f), s);
        ASSERT_TRUE(a) << a.message();
        ASSERT_TRUE(b) << b.message();
        EXPECT_TRUE(bit_identical(*a, *b)) << with_empty.size() - real.size() << " empty layers changed the result";
    }
    auto none = defocus_layers(std::vector<Layer>{}, BlurField(), test_camera(f), {});
    ASSERT_TRUE(none) << none.message();
    EXPECT_TRUE(none->data_window().empty());
}

// Depths over the whole stress range (1e-4 .. 1e7, +inf = sky, denormal)
// with thin lenses f/0.5 .. f/1024 focused anywhere (also at the near clip)
// and with a region of focus: never NaN out; the lens clamped by the field's
// max_radius always works; unclamped, a radius beyond the solver's
// max_radius is an error naming the layer, the pixel and the value.
TEST(stress_diffusion, extreme_depths_are_blurred_or_refused_clearly) {
    GDOF_STRESS_RNG(rng, 2006);
    for (int iter = 0; iter < 30; ++iter) {
        const Roi f{0, 0, rng.integer(1, 24), rng.integer(1, 24)};
        std::vector<float> depth(f.npixels());
        for (float& d : depth) d = float(rng.depth());
        Layer layer;
        layer.image = Image(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, f, f);
        for (int y = 0; y < f.y1; ++y)
            for (int x = 0; x < f.x1; ++x) {
                for (int c = 0; c < 3; ++c) layer.image.at(c, x, y) = rng.pixel();
                layer.image.at(3, x, y) = 1.0f;
                layer.image.at(4, x, y) = depth[std::size_t(y) * std::size_t(f.x1) + std::size_t(x)];
            }
        layer.name = "extreme";
        const int kind = rng.integer(0, 2);
        std::string json;
        if (kind == 0) json = random_thin_lens_json(rng, rng.uniform(0.0, 1000.0));
        else if (kind == 1)
            json = R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, )" + num(rng.log_uniform(1e-4, 1e7)) +
                   R"(], "radius": )" + num(rng.log_uniform(1e-4, 1e6)) + R"(, "blur": )" + num(rng.uniform(0.0, 1000.0)) +
                   R"(, "falloff": )" + num(rng.log_uniform(1e-3, 1e6)) + "}}";
        else {  // the same thin lens without a clamp
            json = random_thin_lens_json(rng, 1.0);
            json = json.substr(0, json.find(", \"max_radius\"")) + "}";
        }
        SCOPED_TRACE(json);
        const BlurField field = parse_field(json);
        auto out = defocus_layers({layer}, field, test_camera(f), full_resolution());
        if (kind == 2 && !out) {
            EXPECT_TRUE(contains(out.message(), "layer 0 'extreme'")) << out.message();
            EXPECT_TRUE(contains(out.message(), "at pixel (") || contains(out.message(), "at covered pixel (")) << out.message();
            EXPECT_TRUE(contains(out.message(), "max_radius") || contains(out.message(), "finite radius")) << out.message();
            continue;
        }
        ASSERT_TRUE(out) << out.message();
        EXPECT_EQ(first_nonfinite(*out), "");
        for (int c = 0; c < 4; ++c)
            EXPECT_NEAR(channel_sum(*out, c), channel_sum(layer.image, c), 1e-4 * channel_sum(layer.image, c) + 1e-30)
                << "channel " << c;
    }
}

// NaN/Inf colour is an error naming the layer, the channel and the pixel.
// Denormal colour is fine. A NaN depth at a covered pixel is not an error:
// a layer's Z is read with the default depth decoding (camera.h), which
// makes invalid depths +inf (sky), so the pixel is blurred exactly as sky.
TEST(stress_diffusion, nan_depth_and_nonfinite_colour_are_errors_naming_the_pixel) {
    GDOF_STRESS_RNG(rng, 2007);
    const BlurField lens = parse_field(random_thin_lens_json(rng, 50.0));
    for (int iter = 0; iter < 30; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi f{rng.integer(-4, 4), rng.integer(-4, 4), 0, 0};
        const Roi w{f.x0, f.y0, f.x0 + sz.w, f.y0 + sz.h};
        Layer layer = make_layer(w, w, [](int x, int y) { return Rgba{texture(x, y, 0), kDenormF, 0.5f, 1.0f}; }, 2.0, "plate");
        const int x = rng.integer(w.x0, w.x1 - 1), y = rng.integer(w.y0, w.y1 - 1);
        const std::string pixel = "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
        const int what = rng.integer(0, 3);
        const int ch = rng.integer(0, 3);
        const std::string channel(1, "RGBA"[ch]);
        if (what == 0) layer.image.at(4, x, y) = float(kStressNaN);
        else layer.image.at(ch, x, y) = what == 1 ? float(kStressNaN) : what == 2 ? float(kStressInf) : -float(kStressInf);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", case " << what << " at " << pixel);
        auto out = defocus_layers({layer}, lens, test_camera(w), {});
        if (what == 0) {
            ASSERT_TRUE(out) << out.message();
            EXPECT_EQ(first_nonfinite(*out), "");
            layer.image.at(4, x, y) = float(kStressInf);
            auto sky = defocus_layers({layer}, lens, test_camera(w), {});
            ASSERT_TRUE(sky) << sky.message();
            EXPECT_TRUE(bit_identical(*out, *sky)) << "NaN depth is not blurred as sky";
            continue;
        }
        ASSERT_FALSE(out) << "accepted a non-finite input";
        EXPECT_TRUE(contains(out.message(), "layer 0 'plate'")) << out.message();
        EXPECT_TRUE(contains(out.message(), pixel)) << out.message();
        EXPECT_TRUE(contains(out.message(), "channel '" + channel + "'")) << out.message();
    }
}

// Whole flat inputs (RGBA + Z, and RGBA + Z + P like a render with a lit
// environment: sky pixels with A = 1, Z = +inf, P = NaN) with invalid and
// extreme depths (NaN, -1, 0, +inf, denormal, 1e-4, 1e7) on 1x1, 1x10000,
// 10000x1 and small frames: the default decoding makes invalid depths sky,
// the result is finite and an opaque plate stays opaque.
TEST(stress_diffusion, flat_plates_with_invalid_depths_and_sky) {
    GDOF_STRESS_RNG(rng, 2008);
    const std::vector<float> depths = {float(kStressNaN), -1.0f, 0.0f, float(kStressInf), kDenormF, 1e-4f, 1e7f, 2.0f, 5.0f};
    for (int iter = 0; iter < 10; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi f{0, 0, sz.w, sz.h};
        const bool with_p = rng.chance(0.5);
        std::vector<std::string> names = {"R", "G", "B", "A", "Z"};
        if (with_p) names.insert(names.end(), {"P.x", "P.y", "P.z"});
        Image img = Image::with_channels(names, f);
        const Camera cam = test_camera(f);
        for (int y = 0; y < f.y1; ++y)
            for (int x = 0; x < f.x1; ++x) {
                for (int c = 0; c < 3; ++c) img.at(c, x, y) = rng.pixel();
                img.at(3, x, y) = 1.0f;
                const float z = rng.pick(depths);
                img.at(4, x, y) = z;
                if (with_p) {
                    const bool finite = std::isfinite(z) && z > 0;
                    const Vec3 p = finite ? cam.unproject(x + 0.5, y + 0.5, z) : Vec3(kStressNaN, kStressNaN, kStressNaN);
                    img.at(5, x, y) = float(p.x), img.at(6, x, y) = float(p.y), img.at(7, x, y) = float(p.z);
                }
            }
        ImageSet set;
        set.parts.emplace_back(img);
        const std::string json = random_thin_lens_json(rng, rng.uniform(0.0, 200.0));
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << (with_p ? " with P" : "") << ", field " << json);
        DefocusOptions s;
        s.diffusion.adi_steps = 4;  // speed: the property does not depend on the kernel's shape
        auto out = defocus(set, parse_field(json), cam, s);
        // A plate without one valid depth (all NaN or <= 0; +inf is sky) has
        // nothing to fill its holes from: an error saying so.
        bool any_valid = false;
        for (std::size_t i = 0; i < img.npixels(); ++i) any_valid |= img.plane(4)[i] > 0.0f;
        if (!any_valid) {
            ASSERT_FALSE(out);
            EXPECT_NE(out.message().find("no valid depth"), std::string::npos) << out.message();
            continue;
        }
        ASSERT_TRUE(out) << out.message();
        const Image& o = out->flat(0);
        const int ca = o.channel_index("A");
        for (const char* n : {"R", "G", "B", "A"}) {
            const int c = o.channel_index(n);
            ASSERT_GE(c, 0);
            for (std::size_t i = 0; i < o.npixels(); ++i)
                if (!std::isfinite(o.plane(c)[i])) {
                    ADD_FAILURE() << "channel " << n << " is " << o.plane(c)[i] << " at index " << i;
                    break;
                }
        }
        EXPECT_NEAR(plane_min(o, ca, f), 1.0, 1e-4) << "an opaque plate must stay opaque";
    }
}

// Slicing an opaque plate with extreme depths into 1..16 depth layers and
// compositing them back is the identity (the nearest slice of each pixel is
// the pixel itself, opaque), whatever the extension does behind it.
TEST(stress_diffusion, slicing_an_opaque_plate_and_compositing_back_is_the_identity) {
    GDOF_STRESS_RNG(rng, 2009);
    for (int iter = 0; iter < 16; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi f{0, 0, sz.w, sz.h};
        Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, f);
        for (int y = 0; y < f.y1; ++y)
            for (int x = 0; x < f.x1; ++x) {
                for (int c = 0; c < 3; ++c) img.at(c, x, y) = rng.pixel();
                img.at(3, x, y) = 1.0f;
                img.at(4, x, y) = rng.chance(0.1) ? float(kStressNaN) : float(rng.depth());
            }
        SliceOptions so;
        so.split.mode = rng.chance(0.5) ? LayerSplit::Mode::Count : LayerSplit::Mode::Auto;
        so.split.count = rng.integer(1, 16);
        so.extend_px = rng.chance(0.5) ? 0.0 : rng.uniform(0.0, 1000.0);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", split "
                                          << (so.split.mode == LayerSplit::Mode::Count ? "count " : "auto ") << so.split.count
                                          << ", extend " << so.extend_px);
        auto layers = layers_from_depth_map(img, so);
        ASSERT_TRUE(layers) << layers.message();
        std::vector<const Image*> ptrs;
        for (const Layer& l : *layers) {
            ptrs.push_back(&l.image);
            const int z = l.image.channel_index("Z");
            ASSERT_GE(z, 0);
            const int a = l.image.channel_index("A");
            for (std::size_t i = 0; i < l.image.npixels(); ++i)
                if (l.image.plane(a)[i] > 0) {
                    ASSERT_FALSE(std::isnan(l.image.plane(z)[i])) << "covered pixel without depth in " << l.name;
                }
        }
        const Image back = composite_layers(ptrs, f).value();
        EXPECT_EQ(max_abs_diff(back, img, f), 0.0);
    }
}

// Push-pull fill over random weights: known pixels kept bit for bit, every
// filled value a weighted mean of known ones (within their range), finite;
// no weight at all: false and nothing changed.
TEST(stress_diffusion, push_pull_fill_stays_within_the_known_values) {
    GDOF_STRESS_RNG(rng, 2010);
    for (int iter = 0; iter < 40; ++iter) {
        const Size sz = random_size(rng, 48);
        const std::size_t n = std::size_t(sz.w) * std::size_t(sz.h);
        std::vector<float> weight(n), v(n);
        const double p_known = rng.pick(std::vector<double>{0.0, 0.001, 0.1, 0.9, 1.0});
        for (std::size_t i = 0; i < n; ++i) {
            weight[i] = rng.chance(p_known) ? (rng.chance(0.2) ? kDenormF : float(rng.uniform(0.0, 2.0))) : 0.0f;
            v[i] = weight[i] > 0 ? rng.pixel() : float(kStressNaN);  // unknown values are garbage
        }
        const std::vector<float> orig = v;
        float lo = float(kStressInf), hi = -float(kStressInf);
        bool any = false;
        for (std::size_t i = 0; i < n; ++i)
            if (weight[i] > 0) any = true, lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", known fraction " << p_known);
        const Roi win{0, 0, sz.w, sz.h};
        const bool filled = push_pull_fill(ImageView::planar(v.data(), 1, win), ConstImageView::planar(weight.data(), 1, win));
        EXPECT_EQ(filled, any);
        for (std::size_t i = 0; i < n; ++i) {
            if (!any || weight[i] > 0) {
                ASSERT_EQ(std::memcmp(&v[i], &orig[i], sizeof(float)), 0) << "pixel " << i << " changed";
                continue;
            }
            ASSERT_TRUE(std::isfinite(v[i]) && v[i] >= lo * (1 - 1e-5f) && v[i] <= hi * (1 + 1e-5f))
                << "pixel " << i << " filled with " << v[i] << ", known values in [" << lo << ", " << hi << "]";
        }
    }
}

namespace {

// A deep image with 0..4 samples per pixel: premultiplied HDR / denormal
// colour, alpha in [0, 1], depths over the stress range (also 0, negative and
// +inf, which go to the nearest / farthest layer).
DeepImage random_deep(StressRng& rng, const Roi& w) {
    DeepImage d(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, w, w);
    std::vector<std::uint32_t> counts(w.npixels());
    for (auto& c : counts) c = std::uint32_t(rng.integer(0, 4));
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (std::size_t s = 0; s < d.total_samples(); ++s) {
        const float a = rng.chance(0.3) ? 1.0f : float(rng.uniform(0.0, 1.0));
        for (int c = 0; c < 3; ++c) d.samples(c)[s] = a * rng.pixel();
        d.samples(3)[s] = a;
        const int k = rng.integer(0, 9);
        d.samples(4)[s] = k == 0 ? 0.0f : k == 1 ? -1.0f : float(rng.depth());
    }
    return d;
}

}  // namespace

// Deep input: split into 1..16 depth layers (or automatically) over extreme
// depths, the layers composite back to the flattened image (float rounding);
// the whole defocus is finite; a NaN / -inf depth or a non-finite alpha is an
// error naming the deep pixel and sample.
TEST(stress_diffusion, deep_inputs_split_composite_and_refuse_bad_samples) {
    GDOF_STRESS_RNG(rng, 2011);
    for (int iter = 0; iter < 12; ++iter) {
        const Size sz = random_size(rng, 48);
        const Roi w{0, 0, sz.w, sz.h};
        const DeepImage deep = random_deep(rng, w);
        LayerSplit split;
        split.mode = rng.chance(0.5) ? LayerSplit::Mode::Count : LayerSplit::Mode::Auto;
        split.count = rng.integer(1, 16);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", " << deep.total_samples() << " samples, split "
                                          << (split.mode == LayerSplit::Mode::Count ? "count " : "auto ") << split.count);
        auto layers = layers_from_deep(deep, split);
        ASSERT_TRUE(layers) << layers.message();
        auto flat = flatten_deep(deep);
        ASSERT_TRUE(flat) << flat.message();
        std::vector<const Image*> ptrs;
        for (const Layer& l : *layers) ptrs.push_back(&l.image);
        const Image back = composite_layers(ptrs, w).value();
        long bad = 0;
        for (int y = 0; y < sz.h; ++y)
            for (int x = 0; x < sz.w; ++x) {
                const std::size_t p = deep.pixel_index(x, y);
                double mag = 0;
                for (std::size_t k = deep.first_sample(p); k < deep.first_sample(p) + deep.sample_count(p); ++k)
                    for (int c = 0; c < 4; ++c) mag += std::fabs(deep.samples(c)[k]);
                for (int c = 0; c < 4; ++c)
                    if (!(std::fabs(value_at(back, c, x, y) - value_at(*flat, c, x, y)) <= 1e-5 * mag + 1e-40)) ++bad;
            }
        EXPECT_EQ(bad, 0) << "layers do not composite back to the flattened deep image";

        ImageSet set;
        set.parts.emplace_back(deep);
        DefocusOptions s;
        s.split = split;
        s.diffusion.adi_steps = 4;
        const std::string json = random_thin_lens_json(rng, rng.uniform(0.0, 100.0));
        auto out = defocus(set, parse_field(json), test_camera(w), s);
        ASSERT_TRUE(out) << out.message() << "\n" << json;
        EXPECT_EQ(first_nonfinite(out->flat(0)), "") << json;

        // One bad sample.
        if (deep.total_samples() == 0) continue;
        DeepImage broken = deep;
        const std::size_t k = std::size_t(rng.integer(0, int(deep.total_samples()) - 1));
        const bool bad_z = rng.chance(0.5);
        if (bad_z) broken.samples(4)[k] = rng.chance(0.5) ? float(kStressNaN) : -float(kStressInf);
        else broken.samples(3)[k] = rng.chance(0.5) ? float(kStressNaN) : float(kStressInf);
        std::size_t p = 0;
        while (deep.first_sample(p) + deep.sample_count(p) <= k) ++p;
        const std::string where = "deep pixel (" + std::to_string(int(p % std::size_t(sz.w))) + ", " +
                                  std::to_string(int(p / std::size_t(sz.w))) + ") sample " +
                                  std::to_string(k - deep.first_sample(p));
        auto r = layers_from_deep(broken, split);
        ASSERT_FALSE(r) << "accepted " << where;
        EXPECT_TRUE(contains(r.message(), where)) << r.message();
        EXPECT_TRUE(contains(r.message(), bad_z ? "depth Z" : "alpha A")) << r.message();
    }
}
