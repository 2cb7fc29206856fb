// Numerical stress: compositing focal stacks (method 2) and its inputs
// (issue 7, item 4): stacks of 1..40 references with limits from 0 / 1e-4
// to 1e7 and +inf, HDR (1e6), denormal and NaN reference pixels, desired
// focus with NaN / inf / reversed intervals, 1x1, 1x10000 and 10000x1
// windows, a stack of one image; focus surfaces, blur-field focus and
// manifests at the extremes (f/0.5 .. f/1024, focus at the near clip,
// acceptable CoCs from 1e-300 to 1e300 px).
// Properties: the hard pick copies the best reference (brute force)
// bit for bit; the soft blend is a convex combination of the references it
// selected and never reads the others; desired intervals never hold NaN
// for valid input; invalid input is an error naming the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "defocus_test_helpers.h"
#include "gdof/compositing.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "stress_test_helpers.h"

using namespace gdof;
using namespace gdof::test;

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A reference's depth of field: near 0, 1e-4 .. 1e7; far up to 1e7 or +inf.
DepthInterval random_limits(StressRng& rng) {
    const double near = rng.chance(0.05) ? 0.0 : rng.log_uniform(1e-4, 1e7);
    const double far = rng.chance(0.2) ? kStressInf : rng.chance(0.05) ? near : near * (1.0 + rng.log_uniform(1e-6, 1e3));
    return {near, far};
}

// A desired interval per pixel: random, exactly a reference's, NaN, inf, reversed.
void random_desired(StressRng& rng, const std::vector<DepthInterval>& refs, float& n, float& f) {
    const int k = rng.integer(0, 9);
    if (k == 0) {
        const DepthInterval& r = rng.pick(refs);
        n = float(r.near), f = float(r.far);
    } else if (k == 1) {
        n = rng.chance(0.5) ? float(kStressNaN) : 1.0f;
        f = rng.chance(0.5) ? float(kStressNaN) : 2.0f;
    } else if (k == 2) {
        n = rng.chance(0.5) ? float(kStressInf) : 0.0f;
        f = float(kStressInf);
    } else if (k == 3) {  // reversed (surfaces may cross)
        n = float(rng.log_uniform(1.0, 1e7));
        f = float(rng.log_uniform(1e-4, 1.0));
    } else {
        const DepthInterval r = random_limits(rng);
        n = float(r.near), f = float(r.far);
    }
}

Image random_reference(StressRng& rng, const Size& sz) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, {0, 0, sz.w, sz.h});
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i)
            img.plane(c)[i] = rng.chance(0.01) ? float(kStressNaN) : rng.chance(0.01) ? float(kStressInf) : rng.pixel();
    return img;
}

// Brute force: the best reference by deviation, ties to the lower index; -1 for none.
int brute_best(const std::vector<DepthInterval>& refs, double n, double f) {
    if (std::isnan(n) || std::isnan(f)) return -1;
    int best = -1;
    Deviation bd;
    for (int i = 0; i < int(refs.size()); ++i) {
        const Deviation d = stack_deviation(n, f, refs[std::size_t(i)].near, refs[std::size_t(i)].far);
        if (best < 0 || d < bd) best = i, bd = d;
    }
    return best;
}

struct RandomStack {
    std::vector<DepthInterval> limits;
    std::vector<Image> images;
    StackIndex index;
    std::vector<const Image*> ptrs() const {
        std::vector<const Image*> p;
        for (const Image& i : images) p.push_back(&i);
        return p;
    }
};

RandomStack random_stack(StressRng& rng, const Size& sz, int n) {
    RandomStack s;
    for (int i = 0; i < n; ++i) {
        s.limits.push_back(random_limits(rng));
        s.images.push_back(random_reference(rng, sz));
    }
    auto idx = StackIndex::build(s.limits);
    EXPECT_TRUE(idx) << idx.message();
    if (idx) s.index = idx.value();
    return s;
}

DesiredFocus random_desired_focus(StressRng& rng, const Size& sz, const std::vector<DepthInterval>& refs) {
    DesiredFocus d;
    d.window = {0, 0, sz.w, sz.h};
    d.near.resize(d.npixels());
    d.far.resize(d.npixels());
    for (std::size_t i = 0; i < d.npixels(); ++i) random_desired(rng, refs, d.near[i], d.far[i]);
    return d;
}

}  // namespace

// Hard pick: every output pixel is, bit for bit, the pixel of the reference
// a brute-force search finds best (HDR, denormal, even NaN pixels are
// copied, not computed); a NaN desired interval selects nothing (0, index -1).
TEST(stress_compositing, hard_pick_copies_the_best_reference_bit_for_bit) {
    GDOF_STRESS_RNG(rng, 3001);
    for (int iter = 0; iter < 30; ++iter) {
        const Size sz = random_size(rng, 70);
        const int n = rng.chance(0.2) ? 1 : rng.integer(1, 40);
        const RandomStack s = random_stack(rng, sz, n);
        const DesiredFocus d = random_desired_focus(rng, sz, s.limits);
        CompositeOptions cs;
        cs.aovs = true;
        cs.tile_size = rng.pick(std::vector<int>{1, 8, 64, 1000});
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", " << n << " references, tile " << cs.tile_size);
        auto sel = select_references(s.index, d, cs);
        ASSERT_TRUE(sel) << sel.message();
        MemoryStackPixels px(s.ptrs());
        auto out = composite_stack(sel.value(), px, cs);
        ASSERT_TRUE(out) << out.message();
        const int ci = out->channel_index("stack.index");
        long bad = 0;
        std::string first;
        for (int y = 0; y < sz.h; ++y)
            for (int x = 0; x < sz.w; ++x) {
                const std::size_t o = d.offset(x, y);
                const int want = brute_best(s.limits, d.near[o], d.far[o]);
                bool ok = out->at(ci, x, y) == float(want);
                for (int c = 0; c < 4; ++c)
                    ok = ok && same_bits(out->at(c, x, y), want < 0 ? 0.0f : s.images[std::size_t(want)].at(c, x, y));
                if (!ok && bad++ == 0)
                    first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), desired [" + num(d.near[o]) +
                            ", " + num(d.far[o]) + "]: expected reference " + std::to_string(want) + ", index AOV " +
                            num(out->at(ci, x, y));
            }
        EXPECT_EQ(bad, 0) << first;
    }
}

// Soft blend (K = 2..16): per pixel the weights are >= 0 and sum to 1, and
// the output lies within the range of the references it selected. Pixels of
// references a pixel did not select are poisoned with NaN after selection:
// they must never be read into the result.
TEST(stress_compositing, soft_blend_is_a_convex_combination_of_the_selected_references) {
    GDOF_STRESS_RNG(rng, 3002);
    for (int iter = 0; iter < 30; ++iter) {
        const Size sz = random_size(rng, 70);
        const int n = rng.integer(1, 30);
        RandomStack s = random_stack(rng, sz, n);
        for (Image& img : s.images)  // finite references: the result must be finite
            for (int c = 0; c < 4; ++c)
                for (std::size_t i = 0; i < img.npixels(); ++i)
                    if (!std::isfinite(img.plane(c)[i])) img.plane(c)[i] = 0.5f;
        const DesiredFocus d = random_desired_focus(rng, sz, s.limits);
        CompositeOptions cs;
        cs.soft_k = rng.integer(2, 16);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", " << n << " references, K " << cs.soft_k);
        auto sel = select_references(s.index, d, cs);
        ASSERT_TRUE(sel) << sel.message();
        const StackSelection& S = sel.value();
        // Poison what was not selected (weight 0 or absent).
        for (int y = 0; y < sz.h; ++y)
            for (int x = 0; x < sz.w; ++x) {
                const std::size_t p = d.offset(x, y);
                std::vector<char> chosen(std::size_t(n), 0);
                for (int k = 0; k < S.k; ++k) {
                    const int r = S.index[p * std::size_t(S.k) + std::size_t(k)];
                    const bool weighted = S.weight.empty() || S.weight[p * std::size_t(S.k) + std::size_t(k)] > 0;
                    if (r >= 0 && weighted) chosen[std::size_t(r)] = 1;
                }
                for (int r = 0; r < n; ++r)
                    if (!chosen[std::size_t(r)])
                        for (int c = 0; c < 4; ++c) s.images[std::size_t(r)].at(c, x, y) = float(kStressNaN);
            }
        MemoryStackPixels px(s.ptrs());
        auto out = composite_stack(S, px, cs);
        ASSERT_TRUE(out) << out.message();
        long bad = 0;
        std::string first;
        for (int y = 0; y < sz.h; ++y)
            for (int x = 0; x < sz.w; ++x) {
                const std::size_t p = d.offset(x, y);
                double wsum = 0;
                if (bad == 0) first.clear();
                bool ok = true;
                for (int c = 0; c < 4; ++c) {
                    double lo = kStressInf, hi = -kStressInf;
                    int m = 0;
                    for (int k = 0; k < S.k; ++k) {
                        const int r = S.index[p * std::size_t(S.k) + std::size_t(k)];
                        const float w = S.weight.empty() ? 1.0f : S.weight[p * std::size_t(S.k) + std::size_t(k)];
                        if (r < 0 || !(w > 0)) continue;
                        ok = ok && w <= 1.0f;
                        if (c == 0) wsum += w;
                        const double v = s.images[std::size_t(r)].at(c, x, y);
                        lo = std::min(lo, v), hi = std::max(hi, v);
                        ++m;
                    }
                    const double v = out->at(c, x, y);
                    // Float weights and sums: 1e-5 of the largest magnitude,
                    // plus a few float denormal steps (HDR and denormal inputs).
                    const double tol = 1e-5 * std::max(std::fabs(lo), std::fabs(hi)) + 1e-43;
                    const bool in = m == 0 ? v == 0.0 : std::isfinite(v) && v >= lo - tol && v <= hi + tol;
                    if (!in && first.empty())
                        first = "channel " + std::to_string(c) + ": " + num(v) + " outside [" + num(lo) + ", " + num(hi) + "]; ";
                    ok = ok && in;
                }
                if (wsum > 0) ok = ok && std::fabs(wsum - 1.0) <= 1e-5;
                if (!ok && bad++ == 0)
                    first += "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), desired [" + num(d.near[p]) + ", " +
                             num(d.far[p]) + "], weights sum " + num(wsum);
            }
        EXPECT_EQ(bad, 0) << first;
    }
}

// A stack of one image: whatever the desired focus (random, inf, reversed),
// hard or soft, the result is that image; only NaN desired pixels are 0.
TEST(stress_compositing, a_stack_of_one_image_reproduces_it) {
    GDOF_STRESS_RNG(rng, 3003);
    for (int iter = 0; iter < 20; ++iter) {
        const Size sz = random_size(rng, 70);
        const RandomStack s = random_stack(rng, sz, 1);
        const DesiredFocus d = random_desired_focus(rng, sz, s.limits);
        CompositeOptions cs;
        cs.soft_k = rng.chance(0.5) ? 1 : rng.integer(2, 16);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", limits [" << s.limits[0].near << ", "
                                          << s.limits[0].far << "], K " << cs.soft_k);
        auto sel = select_references(s.index, d, cs);
        ASSERT_TRUE(sel) << sel.message();
        MemoryStackPixels px(s.ptrs());
        auto out = composite_stack(sel.value(), px, cs);
        ASSERT_TRUE(out) << out.message();
        long bad = 0;
        for (int y = 0; y < sz.h; ++y)
            for (int x = 0; x < sz.w; ++x) {
                const std::size_t o = d.offset(x, y);
                const bool none = std::isnan(d.near[o]) || std::isnan(d.far[o]);
                for (int c = 0; c < 4; ++c)
                    if (!same_bits(out->at(c, x, y), none ? 0.0f : s.images[0].at(c, x, y))) ++bad;
            }
        EXPECT_EQ(bad, 0);
    }
}

// Index construction: invalid limits (NaN, negative, inf near, far < near)
// are errors naming the reference; valid extremes are accepted.
TEST(stress_compositing, invalid_reference_limits_are_errors_naming_the_reference) {
    GDOF_STRESS_RNG(rng, 3004);
    const std::vector<DepthInterval> bad = {{kStressNaN, 1.0}, {1.0, kStressNaN}, {-1e-300, 1.0}, {kStressInf, kStressInf},
                                            {2.0, 1.0},        {-kStressInf, 1.0}, {1e7, 1e-4}};
    for (int iter = 0; iter < 30; ++iter) {
        std::vector<DepthInterval> refs(std::size_t(rng.integer(1, 20)));
        for (auto& r : refs) r = random_limits(rng);
        ASSERT_TRUE(StackIndex::build(refs));
        const int at = rng.integer(0, int(refs.size()) - 1);
        refs[std::size_t(at)] = rng.pick(bad);
        auto idx = StackIndex::build(refs);
        ASSERT_FALSE(idx) << "limits [" << refs[std::size_t(at)].near << ", " << refs[std::size_t(at)].far << "] accepted";
        EXPECT_TRUE(contains(idx.message(), "reference " + std::to_string(at))) << idx.message();
    }
}

// B-spline focus surfaces with control depths 1e-4 .. 1e7 and +inf over
// 1x1, 1x10000, 10000x1 images: no NaN, finite near, +inf far only with an
// infinite control point; invalid control grids and values are errors.
TEST(stress_compositing, focus_surfaces_at_extreme_depths_and_sizes) {
    GDOF_STRESS_RNG(rng, 3005);
    for (int iter = 0; iter < 40; ++iter) {
        const Size sz = random_size(rng, 70);
        auto grid = [&](bool allow_inf, bool& has_inf) {
            const int nx = rng.integer(1, 6), ny = rng.integer(1, 6);
            std::vector<double> v(std::size_t(nx * ny));
            has_inf = false;
            for (double& x : v) {
                x = allow_inf && rng.chance(0.1) ? kStressInf : rng.chance(0.05) ? 0.0 : rng.log_uniform(1e-4, 1e7);
                has_inf = has_inf || std::isinf(x);
            }
            const bool interp = !has_inf && rng.chance(0.3);
            auto s = BSplineSurface::create(nx, ny, v, interp);
            EXPECT_TRUE(s) << s.message();
            return s ? s.value() : BSplineSurface();
        };
        bool near_inf = false, far_inf = false;
        FocusSurfaces fs{grid(false, near_inf), grid(true, far_inf)};
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", far grid " << fs.far.nx() << "x" << fs.far.ny()
                                          << (far_inf ? " with inf" : "") << (fs.near.interpolating() ? ", near interpolated" : ""));
        auto d = desired_from_surfaces(fs, sz.w, sz.h);
        ASSERT_TRUE(d) << d.message();
        ASSERT_EQ(d->npixels(), std::size_t(sz.w) * std::size_t(sz.h));
        for (std::size_t i = 0; i < d->npixels(); ++i) {
            ASSERT_FALSE(std::isnan(d->near[i]) || std::isnan(d->far[i])) << "pixel index " << i;
            ASSERT_TRUE(std::isfinite(d->near[i])) << "near is " << d->near[i] << " at index " << i;
            if (!far_inf) {
                ASSERT_TRUE(std::isfinite(d->far[i])) << "far is " << d->far[i] << " at index " << i;
            }
        }
    }
    // Invalid control grids.
    EXPECT_FALSE(BSplineSurface::create(2, 1, {1.0, kStressNaN}));
    EXPECT_FALSE(BSplineSurface::create(2, 1, {1.0, -kStressInf}));
    EXPECT_FALSE(BSplineSurface::create(2, 1, {1.0, kStressInf}, true));
    EXPECT_FALSE(BSplineSurface::create(0, 1, {}));
    EXPECT_FALSE(BSplineSurface::create(2, 2, {1.0, 2.0, 3.0}));
    auto p = parse_focus_surfaces(R"({"gdof_surfaces": 1, "near": {"grid": [[1, 2], [3, 1e400]]}, "far": "inf"})");
    ASSERT_FALSE(p);
    EXPECT_TRUE(contains(p.message(), "1e400") || contains(p.message(), "overflow")) << p.message();
    p = parse_focus_surfaces(R"({"gdof_surfaces": 1, "near": {"grid": [[1, 2], [3, "nan"]]}, "far": "inf"})");
    ASSERT_FALSE(p);
    EXPECT_TRUE(contains(p.message(), "near.grid[1][1]")) << p.message();
}

// Desired focus from a blur field over extreme depth images (NaN, -1, 0,
// +inf, denormal, 1e-4 .. 1e7) and lenses (f/0.5 .. f/1024, focus at the
// near clip), depth-only and grid-searched fields: no NaN, 0 <= near <= far.
TEST(stress_compositing, desired_focus_from_blur_fields_at_the_extremes) {
    GDOF_STRESS_RNG(rng, 3006);
    for (int iter = 0; iter < 40; ++iter) {
        const bool region = rng.chance(0.4);
        Size sz = random_size(rng, 70);
        if (region) sz = {std::min(sz.w, 40), std::min(sz.h, 40)};  // grid-searched: keep it small
        const Roi frame{0, 0, sz.w, sz.h};
        Image depth = Image::with_channels({"Z"}, frame);
        for (std::size_t i = 0; i < depth.npixels(); ++i) {
            const int k = rng.integer(0, 9);
            depth.plane(0)[i] = k == 0 ? float(kStressNaN) : k == 1 ? -1.0f : k == 2 ? 0.0f : float(rng.depth());
        }
        const double f = rng.log_uniform(10.0, 300.0);
        const double s = rng.chance(0.3) ? f / 1000.0 * (1.0 + rng.log_uniform(1e-6, 1e-2)) : rng.log_uniform(f / 900.0, 1e4);
        std::string lens = R"({"kind": "thin_lens", "focal_length_mm": )" + num(f) + R"(, "f_number": )" +
                           num(rng.log_uniform(0.5, 1024.0)) + R"(, "focus_distance": )" + num(s) + "}";
        std::string json = region ? R"({"blurfield": {"kind": "min", "children": [)" + lens +
                                        R"(, {"kind": "region", "shape": "sphere", "center": [0, 0, )" +
                                        num(rng.log_uniform(1e-3, 1e6)) + R"(], "radius": )" + num(rng.log_uniform(1e-4, 1e5)) +
                                        R"(, "blur": )" + num(rng.uniform(0.0, 1000.0)) + R"(, "falloff": 1}]}})"
                                  : R"({"blurfield": )" + lens + "}";
        auto field = BlurField::parse(json);
        ASSERT_TRUE(field) << field.message() << "\n" << json;
        BlurFocusOptions bs;
        bs.coc_px = rng.log_uniform(0.01, 100.0);
        bs.depth_min = rng.chance(0.5) ? 0.0 : 1e-4;
        bs.grid_step = rng.integer(0, 16);
        SCOPED_TRACE(::testing::Message() << sz.w << "x" << sz.h << ", coc " << bs.coc_px << ", depth_min " << bs.depth_min
                                          << ", field " << json);
        auto d = desired_from_blur_field(field.value(), test_camera(frame), depth, bs);
        ASSERT_TRUE(d) << d.message();
        for (std::size_t i = 0; i < d->npixels(); ++i) {
            ASSERT_FALSE(std::isnan(d->near[i]) || std::isnan(d->far[i]))
                << "pixel index " << i << ", depth " << depth.plane(0)[i];
            ASSERT_TRUE(d->near[i] >= 0 && d->near[i] <= d->far[i] && std::isfinite(d->near[i]))
                << "[" << d->near[i] << ", " << d->far[i] << "] at index " << i << ", depth " << depth.plane(0)[i];
        }
    }
}

// Manifests with one reference at the lens extremes (f/0.5 .. f/1024, focus
// at the near clip, acceptable CoC radii from 1e-300 to 1e300 px): near/far
// computed without NaN and around the focus distance; bad values are errors
// naming the key path.
TEST(stress_compositing, manifests_at_the_lens_extremes) {
    GDOF_STRESS_RNG(rng, 3007);
    for (int iter = 0; iter < 200; ++iter) {
        const double f = rng.log_uniform(1.0, 1000.0);
        const double s = rng.chance(0.3) ? f / 1000.0 * (1.0 + rng.log_uniform(1e-9, 1e-1)) : rng.log_uniform(f / 900.0, 1e7);
        const double N = rng.log_uniform(0.5, 1024.0);
        const double coc = rng.chance(0.2) ? rng.pick(std::vector<double>{0.0, 1e-300, 1e300}) : rng.log_uniform(1e-3, 1e3);
        const int width = rng.pick(std::vector<int>{1, 640, 10000});
        const std::string json = R"({"gdof_stack": 1, "coc_px": )" + num(coc) + R"(, "focal_length_mm": )" + num(f) +
                                 R"(, "sensor_width_mm": 36, "width": )" + std::to_string(width) +
                                 R"(, "height": 1, "references": [{"file": "a.exr", "focus_distance": )" + num(s) +
                                 R"(, "f_number": )" + num(N) + "}]}";
        SCOPED_TRACE(json);
        auto m = parse_stack_manifest(json, "/tmp");
        ASSERT_TRUE(m) << m.message();
        const StackReference& r = m->references.at(0);
        ASSERT_FALSE(std::isnan(r.near) || std::isnan(r.far)) << "[" << r.near << ", " << r.far << "]";
        EXPECT_TRUE(std::isfinite(r.near) && r.near >= 0) << r.near;
        EXPECT_LE(r.near, s * (1 + 1e-12));
        EXPECT_GE(r.far, s * (1 - 1e-12));
        EXPECT_TRUE(StackIndex::build({{r.near, r.far}})) << "[" << r.near << ", " << r.far << "]";
    }
    // Invalid values name the key path.
    const std::string head =
        R"({"gdof_stack": 1, "focal_length_mm": 50, "sensor_width_mm": 36, "width": 100, "references": [{"file": "a.exr", )";
    const std::vector<std::pair<std::string, std::string>> bad = {
        {R"("focus_distance": 2, "f_number": -1)", "references[0].f_number"},
        {R"("focus_distance": 2, "f_number": 0)", "references[0].f_number"},
        {R"("focus_distance": 0.05, "f_number": 2)", "references[0]"},  // at the focal length
        {R"("focus_distance": 2, "f_number": 1e-310)", "references[0]"},  // valid alone, overflows with f
        {R"("focus_distance": 2, "f_number": "nan")", "references[0].f_number"},
        {R"("near": 3, "far": 2)", "references[0]"},
        {R"("near": -1, "far": 2)", "references[0].near"},
        {R"("near": 1, "far": "-inf")", "references[0].far"},
    };
    for (const auto& [body, key] : bad) {
        auto m = parse_stack_manifest(head + body + "}]}", "/tmp");
        ASSERT_FALSE(m) << body;
        EXPECT_TRUE(contains(m.message(), key)) << m.message();
    }
}
