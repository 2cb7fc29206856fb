// Method 2 in memory: exact reproduction of a reference, piecewise-constant
// desired focus, the index against brute force, soft mode, AOVs, threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "gdof/compositing.h"
#include "gdof/focus_surfaces.h"
#include "test_support.h"

namespace gdof {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Reference i: textured content distinct per reference, alpha < 1 in places.
Image make_ref(int i, int W, int H) {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, {0, 0, W, H});
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            img.at(0, x, y) = float(i) + 0.01f * float(x);
            img.at(1, x, y) = float(i) * 0.5f + 0.003f * float(y * x % 17);
            img.at(2, x, y) = std::sin(float(i + x * 0.37f + y * 0.11f));
            img.at(3, x, y) = (x + y + i) % 5 == 0 ? 0.5f : 1.0f;
            img.at(4, x, y) = 100.0f;  // ignored
        }
    return img;
}

struct Stack {
    std::vector<Image> images;
    std::vector<DepthInterval> limits;
    StackIndex index;
    std::vector<const Image*> ptrs() const {
        std::vector<const Image*> p;
        for (const Image& i : images) p.push_back(&i);
        return p;
    }
};

Stack make_stack(int W, int H) {
    Stack s;
    s.limits = {{1.0, 1.5}, {1.4, 2.2}, {2.0, 3.5}, {3.0, 8.0}, {5.0, kInf}, {1.2, 1.9}};
    for (std::size_t i = 0; i < s.limits.size(); ++i) s.images.push_back(make_ref(int(i), W, H));
    auto idx = StackIndex::build(s.limits);
    EXPECT_TRUE(idx) << idx.message();
    s.index = idx.value();
    return s;
}

DesiredFocus constant_desired(int W, int H, double n, double f) {
    DesiredFocus d;
    d.window = {0, 0, W, H};
    d.near.assign(d.npixels(), float(n));
    d.far.assign(d.npixels(), float(f));
    return d;
}

Image run(const Stack& s, const DesiredFocus& d, const CompositeOptions& cs = {}, const Exec& exec = {},
          MemoryStackPixels* px_out = nullptr) {
    auto sel = select_references(s.index, d, cs, exec);
    EXPECT_TRUE(sel) << sel.message();
    MemoryStackPixels local(s.ptrs());
    MemoryStackPixels& px = px_out ? *px_out : local;
    auto out = composite_stack(sel.value(), px, cs, 0, 0, nullptr, exec);
    EXPECT_TRUE(out) << out.message();
    return out ? std::move(out).value() : Image{};
}

void expect_equals_ref(const Image& out, const Image& ref, const Roi& region, const std::string& what) {
    long bad = 0;
    for (int c = 0; c < 4; ++c)
        for (int y = region.y0; y < region.y1; ++y)
            for (int x = region.x0; x < region.x1; ++x)
                if (!same_bits(out.at(c, x, y), ref.at(c, x, y))) ++bad;
    EXPECT_EQ(bad, 0) << what;
}

TEST(compositing, desired_equal_to_a_reference_reproduces_it_exactly) {
    const int W = 150, H = 70;
    const Stack s = make_stack(W, H);
    for (std::size_t r = 0; r < s.limits.size(); ++r) {
        const DesiredFocus d = constant_desired(W, H, s.limits[r].near, s.limits[r].far);
        MemoryStackPixels px(s.ptrs());
        const Image out = run(s, d, {}, {}, &px);
        expect_equals_ref(out, s.images[r], {0, 0, W, H}, "reference " + std::to_string(r));
        for (int o = 0; o < int(s.limits.size()); ++o) {
            if (o != int(r)) {
                EXPECT_EQ(px.reads(o), 0) << "reference " << o << " read for " << r;
            }
        }
        // Soft mode too: a deviation of 0 takes the reference alone.
        CompositeOptions soft;
        soft.soft_k = 3;
        expect_equals_ref(run(s, d, soft), s.images[r], {0, 0, W, H}, "soft, reference " + std::to_string(r));
    }
}

TEST(compositing, piecewise_constant_maps_give_each_region_its_reference) {
    const int W = 131, H = 67;
    const Stack s = make_stack(W, H);
    DesiredFocus d = constant_desired(W, H, 0, 0);
    // Three regions: left third -> ref 1, middle -> ref 3, right -> ref 4, slightly off the exact limits.
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int r = x < W / 3 ? 1 : x < 2 * W / 3 ? 3 : 4;
            d.near[d.offset(x, y)] = float(s.limits[std::size_t(r)].near + 0.01);
            d.far[d.offset(x, y)] = float(std::isinf(s.limits[std::size_t(r)].far) ? kInf : s.limits[std::size_t(r)].far - 0.02);
        }
    MemoryStackPixels px(s.ptrs());
    CompositeOptions cs;
    cs.aovs = true;
    const Image out = run(s, d, cs, {}, &px);
    expect_equals_ref(out, s.images[1], {0, 0, W / 3, H}, "left");
    expect_equals_ref(out, s.images[3], {W / 3, 0, 2 * W / 3, H}, "middle");
    expect_equals_ref(out, s.images[4], {2 * W / 3, 0, W, H}, "right");
    for (int r : {0, 2, 5}) EXPECT_EQ(px.reads(r), 0) << r;
    // AOVs.
    const int ci = out.channel_index("stack.index"), cd = out.channel_index("stack.deviation");
    ASSERT_GE(ci, 0);
    ASSERT_GE(cd, 0);
    EXPECT_EQ(out.at(ci, 0, 0), 1.0f);
    EXPECT_EQ(out.at(ci, W - 1, H - 1), 4.0f);
    EXPECT_NEAR(out.at(cd, 0, 0), 0.03, 1e-5);
    EXPECT_NEAR(out.at(cd, W / 2, 5), 0.03, 1e-5);
    EXPECT_NEAR(out.at(cd, W - 1, 0), 0.01, 1e-5);  // far term 0 (both infinite)
}

TEST(compositing, piecewise_constant_bspline_surfaces) {
    // 8 x 2 control grid: left 4 columns at reference 0's limits, right 4 at reference 2's.
    const int W = 160, H = 40;
    const Stack s = make_stack(W, H);
    std::vector<double> gn, gf;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 8; ++i) {
            const auto& l = s.limits[i < 4 ? 0 : 2];
            gn.push_back(l.near);
            gf.push_back(l.far);
        }
    FocusSurfaces fs{BSplineSurface::create(8, 2, gn).value(), BSplineSurface::create(8, 2, gf).value()};
    auto d = desired_from_surfaces(fs, W, H);
    ASSERT_TRUE(d) << d.message();
    const Image out = run(s, d.value());
    // Columns whose B-spline support lies in one half: u <= 2/7 and u >= 5/7.
    const int xl = int(std::floor(2.0 / 7.0 * W)) - 1, xr = int(std::ceil(5.0 / 7.0 * W)) + 1;
    expect_equals_ref(out, s.images[0], {0, 0, xl, H}, "left of the transition");
    expect_equals_ref(out, s.images[2], {xr, 0, W, H}, "right of the transition");
}

std::vector<std::pair<Deviation, int>> brute_force(const std::vector<DepthInterval>& refs, double n, double f) {
    std::vector<std::pair<Deviation, int>> v;
    for (int i = 0; i < int(refs.size()); ++i)
        v.push_back({stack_deviation(n, f, refs[std::size_t(i)].near, refs[std::size_t(i)].far), i});
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
        if (a.first < b.first) return true;
        if (b.first < a.first) return false;
        return a.second < b.second;
    });
    return v;
}

TEST(compositing, index_equals_brute_force_on_random_stacks) {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    long queries = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const int n = 1 + int(U(rng) * 60);
        std::vector<DepthInterval> refs;
        for (int i = 0; i < n; ++i) {
            // Quantised values make ties (equal near, equal deviations) common.
            double a = std::round(U(rng) * 20.0) / 4.0 + 0.25;
            double b = a + std::round(U(rng) * 12.0) / 4.0;
            if (U(rng) < 0.2) b = kInf;
            refs.push_back({a, b});
        }
        auto idx = StackIndex::build(refs);
        ASSERT_TRUE(idx) << idx.message();
        for (int q = 0; q < 60; ++q) {
            double qn = std::round(U(rng) * 24.0) / 4.0;
            double qf = qn + std::round(U(rng) * 16.0) / 4.0;
            if (U(rng) < 0.2) qf = kInf;
            if (U(rng) < 0.3) qn += U(rng) * 0.1, qf += U(rng) * 0.1;  // and some off-grid ones
            const int k = 1 + int(U(rng) * 5);
            int got[8];
            Deviation dev[8];
            const int m = idx->nearest(qn, qf, k, got, dev);
            const auto want = brute_force(refs, qn, qf);
            ASSERT_EQ(m, std::min(k, n));
            for (int i = 0; i < m; ++i) {
                ASSERT_EQ(got[i], want[std::size_t(i)].second)
                    << "trial " << trial << " query (" << qn << ", " << qf << ") k=" << k << " rank " << i;
                ASSERT_EQ(dev[i], want[std::size_t(i)].first);
            }
            ++queries;
        }
    }
    EXPECT_EQ(queries, 300 * 60);
    // NaN desired: nothing.
    auto idx = StackIndex::build({{1, 2}});
    int i0 = -1;
    EXPECT_EQ(idx->nearest(std::nan(""), 2, 1, &i0, nullptr), 0);
}

TEST(compositing, deviation_rules) {
    EXPECT_EQ(stack_deviation(1, 2, 1.5, 3).value, 1.5);
    EXPECT_EQ(stack_deviation(1, kInf, 1.5, kInf), (Deviation{0, 0.5}));
    EXPECT_EQ(stack_deviation(1, kInf, 1.5, 9), (Deviation{1, 0.5}));
    EXPECT_TRUE(stack_deviation(1, kInf, 100, kInf) < stack_deviation(1, kInf, 1, 1000));
    EXPECT_FALSE(StackIndex::build({{2, 1}}));
    EXPECT_FALSE(StackIndex::build({{kInf, kInf}}));
}

TEST(compositing, soft_k1_is_the_hard_pick_and_soft_blends) {
    const int W = 97, H = 53;
    const Stack s = make_stack(W, H);
    DesiredFocus d = constant_desired(W, H, 0, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0.8, 6.0);
    for (std::size_t i = 0; i < d.npixels(); ++i) {
        const double n = U(rng);
        d.near[i] = float(n);
        d.far[i] = float(n + U(rng));
    }
    CompositeOptions hard, soft1;
    soft1.soft_k = 1;
    const Image a = run(s, d, hard), b = run(s, d, soft1);
    expect_equals_ref(a, b, {0, 0, W, H}, "soft 1 vs hard");

    // K = 2 between references 0 [1, 1.5] and 1 [1.4, 2.2]: a convex blend.
    CompositeOptions soft2;
    soft2.soft_k = 2;
    const DesiredFocus mid = constant_desired(W, H, 1.25, 1.85);
    auto sel = select_references(s.index, mid, soft2);
    ASSERT_TRUE(sel) << sel.message();
    const std::size_t p = 0;
    float wsum = 0;
    for (int k = 0; k < sel->k; ++k) wsum += sel->weight[p * 2 + std::size_t(k)];
    EXPECT_NEAR(wsum, 1.0f, 1e-6);
    const Image c = run(s, mid, soft2);
    const Image h = run(s, mid, hard);
    // Deviations: ref 5 [1.2, 1.9] 0.1, ref 1 [1.4, 2.2] 0.5, ref 0 [1, 1.5] 0.6 (= R): 5 blended with a little of 1.
    EXPECT_EQ(sel->index[0], 5);
    EXPECT_EQ(sel->index[1], 1);
    const double w5 = std::pow((0.6 - 0.1) / (0.6 * 0.1), 2), w1 = std::pow((0.6 - 0.5) / (0.6 * 0.5), 2);
    EXPECT_NEAR(sel->weight[0], w5 / (w5 + w1), 1e-5);
    EXPECT_FALSE(same_bits(c.at(0, 3, 3), h.at(0, 3, 3)));
    const float lo = std::min({s.images[0].at(0, 3, 3), s.images[1].at(0, 3, 3), s.images[5].at(0, 3, 3)});
    const float hi = std::max({s.images[0].at(0, 3, 3), s.images[1].at(0, 3, 3), s.images[5].at(0, 3, 3)});
    EXPECT_GE(c.at(0, 3, 3), lo);
    EXPECT_LE(c.at(0, 3, 3), hi);

    // Continuity: moving the desired interval a hair changes the blend a hair.
    const Image c2 = run(s, constant_desired(W, H, 1.2501, 1.8501), soft2);
    EXPECT_NEAR(c.at(0, 3, 3), c2.at(0, 3, 3), 1e-2);
}

TEST(compositing, threads_and_tile_size_do_not_change_the_output) {
    const int W = 211, H = 97;
    const Stack s = make_stack(W, H);
    DesiredFocus d = constant_desired(W, H, 0, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            d.near[d.offset(x, y)] = float(1.0 + 4.0 * x / W);
            d.far[d.offset(x, y)] = float(2.0 + 6.0 * y / H);
        }
    for (int k : {1, 3}) {
        CompositeOptions cs;
        cs.soft_k = k;
        cs.aovs = true;
        Exec one, all;
        one.nthreads = 1;
        const Image a = run(s, d, cs, one);
        const Image b = run(s, d, cs, all);
        cs.tile_size = 16;
        const Image c = run(s, d, cs, all);
        for (int ch = 0; ch < a.nchannels(); ++ch)
            for (std::size_t i = 0; i < a.npixels(); ++i) {
                ASSERT_TRUE(same_bits(a.plane(ch)[i], b.plane(ch)[i])) << "k " << k << " channel " << ch << " pixel " << i;
                ASSERT_TRUE(same_bits(a.plane(ch)[i], c.plane(ch)[i])) << "tile size, k " << k << " channel " << ch;
            }
    }
}

TEST(compositing, nan_desired_selects_nothing_and_reports_used_references) {
    const int W = 20, H = 10;
    const Stack s = make_stack(W, H);
    DesiredFocus d = constant_desired(W, H, s.limits[2].near, s.limits[2].far);
    d.near[5] = std::numeric_limits<float>::quiet_NaN();
    CompositeOptions cs;
    cs.aovs = true;
    auto sel = select_references(s.index, d, cs);
    ASSERT_TRUE(sel);
    EXPECT_EQ(sel->used_references(), std::vector<int>{2});
    EXPECT_EQ(sel->references_used(), 1);
    const Image out = run(s, d, cs);
    EXPECT_EQ(out.at(out.channel_index("stack.index"), 5, 0), -1.0f);
    EXPECT_EQ(out.at(3, 5, 0), 0.0f);
    EXPECT_EQ(out.at(0, 6, 0), s.images[2].at(0, 6, 0));
    // Settings errors.
    CompositeOptions bad;
    bad.soft_k = 0;
    EXPECT_FALSE(select_references(s.index, d, bad));
}

}  // namespace
}  // namespace gdof
