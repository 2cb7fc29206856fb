// A real handheld focus sweep (../shared/data/focalstack/keyboard: 32 phone
// frames, far focus to near, not aligned, no focus metadata): the alignment
// finds the lens's breathing as a monotonic scale and explains each
// neighbour better than no motion does, and the depth from focus puts the
// near keys (the bottom of the frame) in the late frames and the far end of
// the keyboard (the top) in the early ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gdof/focus_sweep.h"
#include "gdof/io/image_io.h"
#include "test_support.h"

using namespace gdof;

// A real depth-from-defocus pair (../shared/data/focalstack/breakfast: 25 mm,
// f/8.3, focused at 529 and 869 mm): the wall behind is sharper in the far
// frame; the bread in front lies nearer (which of the two frames shows each
// of its pixels sharper depends on where it stands between them, which the
// data does not say, so only the order is asked).
TEST(FocusSweepReal, BreakfastPairOrdersNearAndFar) {
    GDOF_REQUIRE_SHARED(near_path, "focalstack/breakfast/breakfast_near.png");
    GDOF_REQUIRE_SHARED(far_path, "focalstack/breakfast/breakfast_far.png");
    std::vector<Image> frames;
    for (const std::string& p : {near_path, far_path}) {
        auto r = io::read_flat(p);
        ASSERT_TRUE(r) << r.message();
        frames.push_back(std::move(r).value());
    }
    ASSERT_TRUE(align_sweep(frames));
    auto d = depth_from_focus(frames, {529.0, 869.0});
    ASSERT_TRUE(d) << d.message();
    const Image& p = d.value().plate;
    const int z = p.channel_index("Z");
    auto mean_at = [&](int x0, int y0, int x1, int y1) {
        double sum = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) sum += p.at(z, x, y);
        return sum / double((x1 - x0) * (y1 - y0));
    };
    const double bread = mean_at(40, 220, 200, 400), wall = mean_at(0, 0, 640, 120);
    std::printf("[ measured ] breakfast: mean depth of the bread %.0f mm, of the wall %.0f mm\n", bread, wall);
    EXPECT_GT(wall, 800.0);
    EXPECT_LT(bread, wall - 150.0);
}

TEST(FocusSweepReal, KeyboardSweepAlignsAndOrdersDepth) {
    GDOF_REQUIRE_SHARED(first, "focalstack/keyboard/00.jpg");
    std::vector<Image> frames;
    for (int k = 0; k < 32; ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "focalstack/keyboard/%02d.jpg", k);
        auto r = io::read_flat(::gdof::test::shared_file(name));
        ASSERT_TRUE(r) << name << ": " << r.message();
        frames.push_back(std::move(r).value());
    }
    auto al = align_sweep(frames);
    ASSERT_TRUE(al) << al.message();
    const SweepAlignment& a = al.value();
    // Breathing: the scale moves one way through the sweep (to the reference
    // frame 16 and beyond), by more than 2% end to end.
    const double s0 = a.maps.front().scale(), s1 = a.maps.back().scale();
    std::printf("[ measured ] scale %.4f (frame 1) .. %.4f (frame 32)\n", s0, s1);
    EXPECT_GT(std::abs(s1 - s0), 0.02) << s0 << " .. " << s1;
    int reversals = 0;
    for (std::size_t k = 1; k < a.maps.size(); ++k)
        if ((a.maps[k].scale() - a.maps[k - 1].scale()) * (s1 - s0) < 0) ++reversals;
    EXPECT_EQ(reversals, 0);
    for (std::size_t k = 0; k < a.maps.size(); ++k)
        if (k != a.reference) {
            EXPECT_LT(a.residual_after[k], a.residual_before[k]) << "frame " << k + 1;
        }
    auto d = depth_from_focus(frames, {});
    ASSERT_TRUE(d) << d.message();
    const Image& p = d.value().plate;
    const int idx = p.channel_index("focus.index");
    double top = 0, bottom = 0;
    int nt = 0, nb = 0;
    const int H = p.height(), W = p.width();
    for (int y = 0; y < H; ++y)
        for (int x = W / 8; x < W / 2; ++x) {  // the keyboard's left half (the right is the desk)
            if (y < H / 5) top += p.at(idx, x, y), ++nt;
            if (y >= H - H / 5) bottom += p.at(idx, x, y), ++nb;
        }
    top /= nt;
    bottom /= nb;
    std::printf("[ measured ] mean frame index: top fifth %.1f, bottom fifth %.1f; %zu holes of %zu\n", top, bottom,
                d.value().stats.holes, d.value().stats.pixels);
    EXPECT_GT(bottom - top, 10.0) << "mean frame index: top rows " << top << ", bottom rows " << bottom;
}
