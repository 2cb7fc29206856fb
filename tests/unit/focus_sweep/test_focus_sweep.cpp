// Focus sweeps (gdof/focus_sweep.h) against an analytic sweep
// (sweep_test_helpers.h): the alignment recovers the drift it was made with,
// the depth from focus finds each strip's depth, the all-in-focus plate is
// sharp where every single frame is not, and bad sweeps are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "gdof/focus_sweep.h"
#include "sweep_test_helpers.h"

using namespace gdof;
using sweep_test::make_sweep;

namespace {

std::vector<Image> frames_of(const sweep_test::Sweep& s) {
    std::vector<Image> f;
    for (std::size_t k = 0; k < s.focus.size(); ++k) f.push_back(s.frame(k));
    return f;
}

// The inverse of a similarity, written out independently of the library.
void invert_apply(const Similarity& m, double x, double y, double& xo, double& yo) {
    const double d = m.a * m.a + m.b * m.b, X = x - m.tx, Y = y - m.ty;
    xo = (m.a * X + m.b * Y) / d;
    yo = (-m.b * X + m.a * Y) / d;
}

}  // namespace

TEST(FocusSweep, SimilarityComposesAsMaps) {
    Similarity f{1.01, 0.02, 3, -2}, g{0.98, -0.01, -1, 4};
    const Similarity h = g.after(f);
    double x1, y1, x2, y2, x3, y3;
    f.apply(17, 40, x1, y1);
    g.apply(x1, y1, x2, y2);
    h.apply(17, 40, x3, y3);
    EXPECT_NEAR(x2, x3, 1e-9);
    EXPECT_NEAR(y2, y3, 1e-9);
    EXPECT_NEAR(f.scale(), std::hypot(1.01, 0.02), 1e-12);
}

TEST(FocusSweep, AlignmentRecoversTheDrift) {
    const auto s = make_sweep();
    std::vector<Image> frames = frames_of(s);
    auto r = align_sweep(frames);
    ASSERT_TRUE(r) << r.message();
    const SweepAlignment& a = r.value();
    EXPECT_EQ(a.reference, 4u);
    // maps[k] takes a reference (scene) pixel to frame k's: the inverse of
    // the frame -> scene map the sweep was made with.
    const double pts[5][2] = {{0, 0}, {320, 0}, {0, 180}, {320, 180}, {160, 90}};
    for (std::size_t k = 0; k < frames.size(); ++k) {
        double worst = 0;
        for (const auto& p : pts) {
            double xe, ye, xg, yg;
            invert_apply(s.scene_from_frame[k], p[0], p[1], xe, ye);
            a.maps[k].apply(p[0], p[1], xg, yg);
            worst = std::max(worst, std::hypot(xg - xe, yg - ye));
        }
        std::printf("[ measured ] frame %zu: worst corner %.3f px from the drift it was made with\n", k + 1, worst);
        EXPECT_LT(worst, 0.12) << "frame " << k + 1;
        if (k != a.reference) {
            EXPECT_LT(a.residual_after[k], 0.5 * a.residual_before[k]) << "frame " << k + 1;
        }
    }
    // The common window excludes what the outer frames do not see (up to 4 x 0.7 px of shift, 1.2% of scale).
    EXPECT_GT(a.common.x0, 0);
    EXPECT_LT(a.common.x1, 320);
    EXPECT_GT(a.common.width(), 280);
}

TEST(FocusSweep, DepthFromFocusFindsEachStripsDepth) {
    const auto s = make_sweep();
    std::vector<Image> frames = frames_of(s);
    auto al = align_sweep(frames);
    ASSERT_TRUE(al) << al.message();
    auto r = depth_from_focus(frames, s.focus);
    ASSERT_TRUE(r) << r.message();
    const Image& p = r.value().plate;
    const int Z = p.channel_index("Z"), conf = p.channel_index("focus.confidence"), idx = p.channel_index("focus.index");
    ASSERT_GE(Z, 0);
    ASSERT_GE(conf, 0);
    ASSERT_GE(idx, 0);
    const double step = std::abs(1.0 / s.focus[1] - 1.0 / s.focus[0]);  // dioptres between frames
    std::vector<double> worst(s.strip_depth.size(), 0.0), mean(s.strip_depth.size(), 0.0);
    std::vector<int> count(s.strip_depth.size(), 0);
    for (int y = 16; y < s.height - 16; ++y)
        for (int x = 0; x < s.width; ++x) {
            if (s.boundary_distance(x + 0.5) < 16) continue;
            const int strip = s.strip_at(x + 0.5);
            if (std::size_t(strip) == s.flat_strip) {
                EXPECT_EQ(p.at(conf, x, y), 0.0f) << "a pixel with no texture has no depth of its own";
                continue;
            }
            const double err = std::abs(1.0 / p.at(Z, x, y) - 1.0 / s.strip_depth[std::size_t(strip)]) / step;
            worst[std::size_t(strip)] = std::max(worst[std::size_t(strip)], err);
            mean[std::size_t(strip)] += err;
            ++count[std::size_t(strip)];
        }
    for (std::size_t k = 0; k < s.strip_depth.size(); ++k) {
        if (k == s.flat_strip) continue;
        ASSERT_GT(count[k], 100);
        std::printf("[ measured ] strip at %.1f m: depth error mean %.3f, worst %.3f frame steps\n", s.strip_depth[k],
                    mean[k] / count[k], worst[k]);
        EXPECT_LT(mean[k] / count[k], 0.15) << "strip at " << s.strip_depth[k] << " m: mean error in frame steps";
        EXPECT_LT(worst[k], 0.5) << "strip at " << s.strip_depth[k] << " m: worst error in frame steps";
    }
    // The flat strip was a hole, filled: every depth finite and within the sweep.
    EXPECT_GE(r.value().stats.holes, std::size_t(s.width / 6 * (s.height - 32)));
    for (std::size_t i = 0; i < p.npixels(); ++i) {
        const float z = p.plane(Z)[i];
        ASSERT_TRUE(std::isfinite(z));
        ASSERT_GE(z, 0.9f - 1e-4f);
        ASSERT_LE(z, 6.0f + 1e-3f);
    }
}

TEST(FocusSweep, AllInFocusIsSharperThanAnyFrame) {
    const auto s = make_sweep();
    std::vector<Image> frames = frames_of(s);
    ASSERT_TRUE(align_sweep(frames));
    auto r = depth_from_focus(frames, s.focus);
    ASSERT_TRUE(r) << r.message();
    const Image& p = r.value().plate;
    // Error against the unblurred scene over the textured interiors, for the
    // plate and for each aligned frame.
    std::vector<double> frame_err(frames.size(), 0.0);
    double plate_err = 0;
    for (int y = 16; y < s.height - 16; ++y)
        for (int x = 0; x < s.width; ++x) {
            if (s.boundary_distance(x + 0.5) < 16 || std::size_t(s.strip_at(x + 0.5)) == s.flat_strip) continue;
            for (int c = 0; c < 3; ++c) {
                const double truth = s.colour(x + 0.5, y + 0.5, c, 0.0);
                plate_err += std::abs(p.at(c, x, y) - truth);
                for (std::size_t k = 0; k < frames.size(); ++k) frame_err[k] += std::abs(frames[k].at(c, x, y) - truth);
            }
        }
    const double best_frame = *std::min_element(frame_err.begin(), frame_err.end());
    std::printf("[ measured ] all in focus: error %.1f against the best single frame's %.1f (%.3f)\n", plate_err, best_frame,
                plate_err / best_frame);
    EXPECT_LT(plate_err, 0.35 * best_frame) << "plate " << plate_err << ", best single frame " << best_frame;
}

TEST(FocusSweep, IndexIsTheDepthWithoutFocusDistances) {
    const auto s = make_sweep(5);
    std::vector<Image> frames = frames_of(s);
    ASSERT_TRUE(align_sweep(frames));
    auto r = depth_from_focus(frames, {});
    ASSERT_TRUE(r) << r.message();
    const Image& p = r.value().plate;
    const int Z = p.channel_index("Z"), idx = p.channel_index("focus.index");
    for (std::size_t i = 0; i < p.npixels(); ++i) {
        ASSERT_EQ(p.plane(Z)[i], p.plane(idx)[i]);
        ASSERT_GE(p.plane(Z)[i], 1.0f);
        ASSERT_LE(p.plane(Z)[i], 5.0f);
    }
}

// Two frames (a depth-from-defocus pair): each pixel is the frame it is
// sharper in; the ratio test compares it with the other frame.
TEST(FocusSweep, TwoFramesSayWhichIsSharper) {
    const auto s = make_sweep(2);  // focused at 0.9 m and 6 m
    std::vector<Image> frames = frames_of(s);
    ASSERT_TRUE(align_sweep(frames));
    auto r = depth_from_focus(frames, {});
    ASSERT_TRUE(r) << r.message();
    const Image& p = r.value().plate;
    const int idx = p.channel_index("focus.index");
    int near_ok = 0, far_ok = 0, near_n = 0, far_n = 0;
    for (int y = 16; y < s.height - 16; ++y)
        for (int x = 0; x < s.width; ++x) {
            if (s.boundary_distance(x + 0.5) < 16) continue;
            const double z = s.strip_depth[std::size_t(s.strip_at(x + 0.5))];
            if (z == 1.0) near_ok += p.at(idx, x, y) == 1.0f, ++near_n;
            if (z == 5.0) far_ok += p.at(idx, x, y) == 2.0f, ++far_n;
        }
    EXPECT_GT(near_ok, 0.95 * near_n);
    EXPECT_GT(far_ok, 0.95 * far_n);
}

TEST(FocusSweep, BadSweepsAreRefusedNamingTheCulprit) {
    const auto s = make_sweep(3);
    std::vector<Image> frames = frames_of(s);
    {
        std::vector<Image> one{frames[0]};
        auto r = align_sweep(one);
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find("at least 2 frames"), std::string::npos) << r.message();
    }
    {
        std::vector<Image> f = frames;
        f[2] = Image::with_channels({"R", "G", "B"}, Roi{0, 0, 100, 100});
        auto r = align_sweep(f);
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find("frame 3"), std::string::npos) << r.message();
    }
    {
        std::vector<Image> f = frames;
        f[1].at(1, 7, 9) = std::numeric_limits<float>::quiet_NaN();
        auto r = align_sweep(f);
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find("frame 2"), std::string::npos) << r.message();
        EXPECT_NE(r.message().find("(7, 9)"), std::string::npos) << r.message();
        auto d = depth_from_focus(f, s.focus);
        ASSERT_FALSE(d);
        EXPECT_NE(d.message().find("frame 2"), std::string::npos) << d.message();
    }
    {
        auto r = depth_from_focus(frames, {1.0, 3.0, 2.0});
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find("rise or fall"), std::string::npos) << r.message();
        auto q = depth_from_focus(frames, {1.0, 2.0});
        ASSERT_FALSE(q);
        auto z = depth_from_focus(frames, {1.0, 0.0, -2.0});
        ASSERT_FALSE(z);
    }
    {
        // Frames with no texture anywhere: nothing to measure.
        std::vector<Image> flat(3, Image::with_channels({"R", "G", "B"}, Roi{0, 0, 64, 64}));
        auto r = depth_from_focus(flat, {});
        ASSERT_FALSE(r);
        EXPECT_NE(r.message().find("no pixel is sharper"), std::string::npos) << r.message();
    }
    {
        // Two unrelated pictures are not one shot.
        auto other = make_sweep(3, 99);
        std::vector<Image> f{frames[0], other.frame(2)};
        // Shift the second by a third of the frame so no small motion explains it.
        Similarity m;
        m.tx = 110;
        f[1] = warp_similarity(f[1], m);
        auto r = align_sweep(f);
        ASSERT_FALSE(r) << r.value().report();
        EXPECT_NE(r.message().find("frame 2 against frame 1"), std::string::npos) << r.message();
        EXPECT_NE(r.message().find("no plausible match"), std::string::npos) << r.message();
    }
}

TEST(FocusSweep, SameBitsForAnyThreadCount) {
    const auto s = make_sweep(5);
    std::vector<Image> a = frames_of(s), b = a;
    Exec one, two;
    one.nthreads = 1;
    two.nthreads = 2;
    ASSERT_TRUE(align_sweep(a, {}, one));
    ASSERT_TRUE(align_sweep(b, {}, two));
    auto ra = depth_from_focus(a, s.focus, {}, one);
    auto rb = depth_from_focus(b, s.focus, {}, two);
    ASSERT_TRUE(ra);
    ASSERT_TRUE(rb);
    const Image& pa = ra.value().plate;
    const Image& pb = rb.value().plate;
    for (int c = 0; c < pa.nchannels(); ++c)
        for (std::size_t i = 0; i < pa.npixels(); ++i) ASSERT_EQ(pa.plane(c)[i], pb.plane(c)[i]) << "channel " << c;
}
