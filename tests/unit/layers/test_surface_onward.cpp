// A layer's surface onward (Layer::onward, SliceOptions::mark_onward): a
// blurred box standing on a sharp floor that recedes up the picture. The
// bound its silhouette needs lies between the box and the floor beside it,
// and so crosses the floor near the box's base: the near layer holds the box
// and the floor in front of it, the far layer the rest of the floor. The
// near layer's surface goes on past the bound, away from the box (there the
// defocus spreads it with the floor's own radii); beside the box's sides
// the floor is the box's background, over which the box must spread with
// its own blur, and none of it is onward.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gdof/image.h"
#include "gdof/layers.h"

using namespace gdof;

namespace {

constexpr int kW = 96, kH = 64;
constexpr int kBoxX0 = 36, kBoxX1 = 60, kBoxY0 = 16, kBoxY1 = 45;  // its base on row 44
constexpr float kBoxRadius = 6.0f, kFloorRadius = 1.0f;

// Linear in inverse depth down the picture, as a plane seen by a pinhole.
double floor_z(int y) { return 1.0 / (0.15 + 0.35 * y / (kH - 1)); }
bool in_box(int x, int y) { return x >= kBoxX0 && x < kBoxX1 && y >= kBoxY0 && y < kBoxY1; }

Image box_on_floor() {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, Roi{0, 0, kW, kH});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool box = in_box(x, y);
            img.at(0, x, y) = box ? 0.8f : 0.2f + 0.005f * float(x);
            img.at(1, x, y) = box ? 0.3f : 0.4f;
            img.at(2, x, y) = box ? 0.1f : 0.5f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = float(box ? floor_z(kBoxY1 - 1) : floor_z(y));
        }
    return img;
}

}  // namespace

TEST(surface_onward, GoesOnPastTheBoundAndNotBesideASilhouette) {
    const Image img = box_on_floor();
    std::vector<float> radius(img.npixels());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            radius[std::size_t(y) * kW + std::size_t(x)] = in_box(x, y) ? kBoxRadius : kFloorRadius;
    SliceOptions so;
    so.radius = radius;
    so.extend_px = 8.0;
    {
        auto plain = layers_from_depth_map(img, so);
        ASSERT_TRUE(plain) << plain.message();
        for (const Layer& l : *plain) EXPECT_TRUE(l.onward.empty()) << l.name << ": marked only when asked";
    }
    so.mark_onward = true;
    auto layers = layers_from_depth_map(img, so);
    ASSERT_TRUE(layers) << layers.message();
    ASSERT_GE(layers->size(), 2u) << "the box's silhouette needs a bound";
    const Layer& near = layers->front();
    ASSERT_GT(near.image.at(3, (kBoxX0 + kBoxX1) / 2, (kBoxY0 + kBoxY1) / 2), 0.0f) << "the box is in the nearest layer";
    ASSERT_FALSE(near.onward.empty()) << "the bound crosses the floor: its far part goes on from the near one";
    ASSERT_EQ(near.onward.size(), near.onward_box.npixels());
    const Roi lw = near.image.data_window();
    std::size_t onward = 0, far_from_box = 0;
    for (int y = near.onward_box.y0; y < near.onward_box.y1; ++y)
        for (int x = near.onward_box.x0; x < near.onward_box.x1; ++x) {
            const std::size_t o = std::size_t(y - near.onward_box.y0) * std::size_t(near.onward_box.width()) +
                                  std::size_t(x - near.onward_box.x0);
            if (!near.onward[o]) continue;
            ++onward;
            ASSERT_TRUE(lw.contains(x, y)) << x << "," << y;
            // Uncovered floor, past the layer's floor, holding its depth.
            EXPECT_FALSE(in_box(x, y)) << x << "," << y;
            EXPECT_EQ(near.image.at(3, x, y), 0.0f) << x << "," << y;
            EXPECT_EQ(near.image.at(0, x, y), 0.0f) << x << "," << y;
            EXPECT_FLOAT_EQ(near.image.at(4, x, y), float(floor_z(y))) << x << "," << y;
            EXPECT_GE(double(near.image.at(4, x, y)), near.depth_far) << x << "," << y;
            // Within reach (8 px) of the layer's own floor.
            bool reached = false;
            for (int yy = y; yy <= std::min(kH - 1, y + 8) && !reached; ++yy)
                reached = near.image.at(3, x, yy) > 0.0f;
            EXPECT_TRUE(reached) << x << "," << y;
            // Beside the box's sides, where the floor is more than 5% behind
            // it (rows 40 and up the picture; 4 rows of margin), within its
            // blur of the silhouette: the box's background, never onward.
            const bool beside = y <= 36 && ((x >= kBoxX0 - int(kBoxRadius) && x < kBoxX0) ||
                                            (x >= kBoxX1 && x < kBoxX1 + int(kBoxRadius)));
            EXPECT_FALSE(beside) << "onward beside the box's silhouette at " << x << "," << y;
            if (x < kBoxX0 - 12 || x >= kBoxX1 + 12) ++far_from_box;
        }
    std::printf("near layer %s: %zu onward pixels, %zu of them 12 px and more from the box's sides\n",
                near.name.c_str(), onward, far_from_box);
    // Away from the box the surface goes on the whole reach past the bound
    // on every column (8 rows).
    EXPECT_GE(far_from_box, std::size_t(8 * (kW - (kBoxX1 - kBoxX0) - 24)));
}
