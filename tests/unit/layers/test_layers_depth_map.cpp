// layers_from_depth_map: depth slices of a flat RGBA + depth image and the
// background extension behind nearer slices.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "gdof/layers.h"
#include "gdof/plate.h"

using namespace gdof;

namespace {

const Roi kWin{-4, 2, 60, 50};  // negative origin on purpose

bool in_disc(int x, int y) { return (x - 26) * (x - 26) + (y - 26) * (y - 26) <= 100; }
bool in_box(int x, int y) { return x >= 34 && x < 46 && y >= 10 && y < 22; }

// Smooth wall texture.
float wall(int c, int x, int y) {
    switch (c) {
        case 0: return 0.3f + 0.2f * std::sin(float(x) / 6.0f);
        case 1: return 0.4f + 0.1f * std::cos(float(y) / 5.0f);
        default: return 0.2f;
    }
}

// Opaque RGBA + Z: a red disc at depth 2 in front of a textured wall at 10
// (and, optionally, a blue box at depth 5).
Image scene(bool with_box = false, bool with_alpha = true) {
    std::vector<std::string> ch = {"R", "G", "B"};
    if (with_alpha) ch.push_back("A");
    ch.push_back("Z");
    Image img = Image::with_channels(ch, kWin);
    const int zc = img.channel_index("Z");
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            float rgb[3] = {wall(0, x, y), wall(1, x, y), wall(2, x, y)};
            float z = 10.0f;
            if (with_box && in_box(x, y)) {
                rgb[0] = 0.1f, rgb[1] = 0.1f, rgb[2] = 0.9f;
                z = 5.0f;
            }
            if (in_disc(x, y)) {
                rgb[0] = 0.9f, rgb[1] = 0.1f, rgb[2] = 0.1f;
                z = 2.0f;
            }
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = rgb[c];
            if (with_alpha) img.at(3, x, y) = 1.0f;
            img.at(zc, x, y) = z;
        }
    return img;
}

std::vector<const Image*> pointers(const std::vector<Layer>& layers) {
    std::vector<const Image*> out;
    for (const auto& l : layers) out.push_back(&l.image);
    return out;
}

float at_or(const Image& img, int c, int x, int y, float dflt) {
    return img.data_window().contains(x, y) ? img.at(c, x, y) : dflt;
}

}  // namespace

TEST(layers_depth_map, TwoSlicesAndTheFarSliceContinuesBehindTheDisc) {
    SliceOptions opt;
    auto r = layers_from_depth_map(scene(), opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    const Layer& fg = (*r)[0];
    const Layer& bg = (*r)[1];
    EXPECT_EQ(fg.depth_near, 2.0);
    EXPECT_EQ(fg.depth_far, 2.0);
    EXPECT_EQ(bg.depth_near, 10.0);
    EXPECT_EQ(fg.image.data_window(), (Roi{16, 16, 37, 37}));
    EXPECT_EQ(bg.image.data_window(), kWin);
    // Front slice: the disc only.
    EXPECT_EQ(fg.image.at(3, 26, 26), 1.0f);
    EXPECT_EQ(fg.image.at(3, 16, 16), 0.0f);
    EXPECT_TRUE(std::isnan(fg.image.at(4, 16, 16)));
    // Far slice behind the disc: opaque, depth of the wall, colour close to the wall's.
    double err = 0, worst = 0;
    int n = 0;
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            if (!in_disc(x, y)) {
                for (int c = 0; c < 3; ++c) ASSERT_EQ(bg.image.at(c, x, y), wall(c, x, y));
                continue;
            }
            ASSERT_EQ(bg.image.at(3, x, y), 1.0f);
            EXPECT_NEAR(bg.image.at(4, x, y), 10.0f, 1e-5f);
            for (int c = 0; c < 3; ++c) {
                const double e = std::fabs(bg.image.at(c, x, y) - wall(c, x, y));
                err += e;
                worst = std::max(worst, e);
                ++n;
                EXPECT_GT(bg.image.at(c, x, y), 0.05f) << "black behind the disc at " << x << "," << y;
            }
        }
    std::cout << "[ measured ] extension behind the disc vs the true wall: mean |diff| " << err / n << ", max " << worst
              << "\n";
    EXPECT_LT(err / n, 0.05);
    EXPECT_LT(worst, 0.25);
    // Compositing the slices gives the input back (opaque input).
    const Image src = scene();
    Image comp = composite_layers(pointers(*r), kWin).value();
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x)
            for (int c = 0; c < 4; ++c) ASSERT_EQ(comp.at(c, x, y), src.at(c, x, y)) << x << "," << y;
}

TEST(layers_depth_map, EveryPixelBelongsToExactlyOneSlice) {
    // Alpha varies (premultiplied colour): each present pixel is own data of
    // exactly one slice (its depth, its alpha); the others hold it only as
    // extension (filled depth, alpha 1) or not at all.
    Image img = scene(true);
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            const float a = 0.25f + 0.75f * float((x * 7 + y * 3) % 11) / 10.0f;
            for (int c = 0; c < 3; ++c) img.at(c, x, y) *= a;
            img.at(3, x, y) = a;
        }
    SliceOptions opt;
    opt.extend_px = 4;
    auto r = layers_from_depth_map(img, opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            int owners = 0;
            double alpha = 0;
            for (const auto& L : *r) {
                const float z = at_or(L.image, 4, x, y, NAN);
                if (z == img.at(4, x, y) && at_or(L.image, 3, x, y, 0) == img.at(3, x, y)) {
                    ++owners;
                    alpha += at_or(L.image, 3, x, y, 0);
                    for (int c = 0; c < 3; ++c) ASSERT_EQ(L.image.at(c, x, y), img.at(c, x, y));
                }
            }
            ASSERT_EQ(owners, 1) << x << "," << y;
            ASSERT_EQ(alpha, img.at(3, x, y));
        }
}

TEST(layers_depth_map, ExtensionReachesExtendPxBehindMiddleSlices) {
    SliceOptions opt;
    opt.extend_px = 3;
    auto r = layers_from_depth_map(scene(true), opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    const Image& mid = (*r)[1].image;
    const Image& far = (*r)[2].image;
    EXPECT_EQ((*r)[1].depth_near, 5.0);
    // Disc pixels (hidden behind the front slice): the middle slice covers
    // those within 3 px of the box and nearer to it than to the wall,
    // opaquely, with the box's colour and depth.
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            if (!in_disc(x, y)) continue;
            double d = 1e9;
            for (int by = 10; by < 22; ++by)
                for (int bx = 34; bx < 46; ++bx)
                    if (!in_disc(bx, by)) d = std::min(d, std::hypot(double(x - bx), double(y - by)));
            // Only the background seen nearest extends behind a pixel
            // (layers.h): the box where it is nearer than the wall.
            double dw = 1e9;
            for (int wy = kWin.y0; wy < kWin.y1; ++wy)
                for (int wx = kWin.x0; wx < kWin.x1; ++wx)
                    if (!in_disc(wx, wy) && !in_box(wx, wy)) dw = std::min(dw, std::hypot(double(x - wx), double(y - wy)));
            const float a = at_or(mid, 3, x, y, 0.0f);
            if (d <= 3.0 && d <= dw) {
                ASSERT_EQ(a, 1.0f) << x << "," << y;
                EXPECT_NEAR(mid.at(2, x, y), 0.9f, 1e-5f);
                EXPECT_NEAR(mid.at(4, x, y), 5.0f, 1e-5f);
            } else {
                ASSERT_EQ(a, 0.0f) << x << "," << y << " d=" << d;
            }
            // The farthest slice covers every hidden pixel.
            ASSERT_EQ(far.at(3, x, y), 1.0f);
        }
    // Wall pixels are not hidden: the middle slice never covers them.
    EXPECT_EQ(at_or(mid, 3, 33, 10, 0.0f), 0.0f);
    // Box pixels are hidden for the far slice: covered, wall depth.
    EXPECT_EQ(far.at(3, 40, 15), 1.0f);
    EXPECT_NEAR(far.at(4, 40, 15), 10.0f, 1e-5f);
    // Without extension the middle slice is its own coverage only.
    SliceOptions none;
    auto r0 = layers_from_depth_map(scene(true), none);
    ASSERT_TRUE(r0) << r0.message();
    EXPECT_EQ((*r0)[1].image.data_window(), (Roi{34, 10, 46, 22}));
}

TEST(layers_depth_map, FarthestBackingFadesTowardEmptiness) {
    Image img = scene();
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < 22; ++x)
            if (!in_disc(x, y))
                for (int c = 0; c < 4; ++c) img.at(c, x, y) = 0.0f;
    SliceOptions opt;
    opt.extend_px = 12;
    auto r = layers_from_depth_map(img, opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    const Image& far = (*r)[1].image;
    double left = 0, right = 0;
    int nleft = 0, nright = 0, partial = 0;
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            if (!in_disc(x, y)) continue;
            const float a = at_or(far, 3, x, y, 0.0f);
            ASSERT_GE(a, 0.0f);
            ASSERT_LE(a, 1.0f);
            if (a > 0.0f && a < 0.9f) ++partial;
            if (x <= 20) left += a, ++nleft;
            if (x >= 30) right += a, ++nright;
        }
    ASSERT_GT(nleft, 0);
    ASSERT_GT(nright, 0);
    EXPECT_GT(partial, 0);
    EXPECT_GT(right / nright, 0.9);
    EXPECT_LT(left / nleft, right / nright - 0.2);
}

TEST(layers_depth_map, InvalidDepthGoesToTheFarthestSlice) {
    Image img = scene(false, false);  // no alpha: opaque
    const int zc = img.channel_index("Z");
    img.at(zc, 0, 5) = 0.0f;    // metric 0: invalid
    img.at(zc, 26, 26) = NAN;   // inside the disc
    auto r = layers_from_depth_map(img, SliceOptions{});
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    const Layer& fg = (*r)[0];
    const Layer& bg = (*r)[1];
    EXPECT_TRUE(std::isinf(bg.depth_far));
    EXPECT_EQ(bg.depth_near, 10.0);
    EXPECT_TRUE(std::isinf(bg.image.at(4, 0, 5)));
    EXPECT_EQ(bg.image.at(3, 0, 5), 1.0f);
    EXPECT_EQ(bg.image.at(0, 26, 26), 0.9f);  // own pixel of the far slice
    EXPECT_EQ(fg.image.at(3, 26, 26), 0.0f);
    EXPECT_EQ(fg.image.at(3, 25, 26), 1.0f);
}

TEST(layers_depth_map, InverseDepthEncoding) {
    Image img = scene(true);
    const int zc = img.channel_index("Z");
    for (std::size_t i = 0; i < img.npixels(); ++i) img.plane(zc)[i] = 1.0f / img.plane(zc)[i];
    SliceOptions opt;
    opt.source.depth_decode.encoding = DepthEncoding::Inverse;
    auto r = layers_from_depth_map(img, opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    EXPECT_NEAR((*r)[0].depth_near, 2.0, 1e-6);
    EXPECT_NEAR((*r)[1].depth_near, 5.0, 1e-6);
    EXPECT_NEAR((*r)[2].depth_near, 10.0, 1e-5);
    EXPECT_NEAR((*r)[0].image.at(4, 26, 26), 2.0f, 1e-6f);
    // Same slicing as the metric image.
    auto m = layers_from_depth_map(scene(true), SliceOptions{});
    ASSERT_TRUE(m);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ((*r)[i].image.data_window(), (*m)[i].image.data_window());
}

TEST(layers_depth_map, CountKeepsEmptySlices) {
    SliceOptions opt;
    opt.split.mode = LayerSplit::Mode::Count;
    opt.split.count = 3;  // 1/depth from 1/2 to 1/10: slices [2, 2.73), [2.73, 4.29), [4.29, 10]
    auto r = layers_from_depth_map(scene(), opt);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    EXPECT_TRUE((*r)[1].image.data_window().empty());
    EXPECT_NE((*r)[1].name.find("empty"), std::string::npos) << (*r)[1].name;
    EXPECT_NEAR(1 / (*r)[1].slice_near - 1 / (*r)[1].slice_far, (0.5 - 0.1) / 3, 1e-12);
    EXPECT_EQ((*r)[2].image.at(3, 26, 26), 1.0f);  // the farthest non-empty slice still extends
}

TEST(layers_depth_map, ErrorsNameWhatIsMissing) {
    Image noz = Image::with_channels({"R", "G", "B", "A"}, kWin);
    auto a = layers_from_depth_map(noz, SliceOptions{});
    ASSERT_FALSE(a);
    EXPECT_NE(a.message().find("depth channel"), std::string::npos) << a.message();
    EXPECT_NE(a.message().find("Z"), std::string::npos) << a.message();
    SliceOptions named;
    named.source.depth_channel = "dist";
    auto b = layers_from_depth_map(scene(), named);
    ASSERT_FALSE(b);
    EXPECT_NE(b.message().find("'dist'"), std::string::npos) << b.message();
    Image nocolour = Image::with_channels({"Y", "Z"}, kWin);
    auto c = layers_from_depth_map(nocolour, SliceOptions{});
    ASSERT_FALSE(c);
    EXPECT_NE(c.message().find("'R'"), std::string::npos) << c.message();
    SliceOptions byid;
    byid.split.mode = LayerSplit::Mode::ById;
    auto d = layers_from_depth_map(scene(), byid);
    ASSERT_FALSE(d);
    EXPECT_NE(d.message().find("deep"), std::string::npos) << d.message();
}

TEST(layers_depth_map, IndependentOfThreadCount) {
    Exec one;
    one.nthreads = 1;
    Exec many;
    many.nthreads = 3;
    SliceOptions opt;
    opt.extend_px = 5;
    auto a = layers_from_depth_map(scene(true), opt, one);
    auto b = layers_from_depth_map(scene(true), opt, many);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->size(), b->size());
    for (std::size_t l = 0; l < a->size(); ++l) {
        const Image& x = (*a)[l].image;
        const Image& y = (*b)[l].image;
        ASSERT_EQ(x.data_window(), y.data_window());
        for (int c = 0; c < x.nchannels(); ++c)
            ASSERT_EQ(std::memcmp(x.plane(c), y.plane(c), x.npixels() * sizeof(float)), 0);
    }
}

// Continued surfaces (off by default): a floor receding upwards is cut into
// two slices; the far slice holds the near slice's floor pixels next to the
// cut, with their own colour and depth, up to extend_px away; a pole
// standing on the near floor (one depth, so it does not come nearer) is not
// continued behind itself. The source serves the same layers as the list.
TEST(layers_from_depth_map, ContinuedSurfacesCarryTheNearerFloorNotThePole) {
    const Roi win{0, 0, 40, 60};
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, win);
    auto floor_z = [](int y) { return float(2.0 + 0.1 * (59 - y)); };  // 2 at the bottom row, 7.9 at the top
    auto pole = [](int x, int y) { return x >= 18 && x < 22 && y >= 53; };
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 40; ++x) {
            const bool p = pole(x, y);
            img.at(0, x, y) = p ? 0.9f : 0.01f * float(x);
            img.at(1, x, y) = p ? 0.1f : 0.01f * float(y);
            img.at(2, x, y) = 0.5f;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = p ? 2.3f : floor_z(y);
        }
    SliceOptions o;
    o.split.mode = LayerSplit::Mode::Count;
    o.split.count = 2;
    o.extend_px = 6.0;
    o.continue_surfaces = true;
    auto layers = layers_from_depth_map(img, o);
    ASSERT_TRUE(layers) << layers.message();
    ASSERT_EQ(layers->size(), 2u);
    const Image& near = (*layers)[0].image;
    const Image& far = (*layers)[1].image;
    // The cut: the first row (from the top) that is in the near slice.
    int cut = -1;
    for (int y = 0; y < 60 && cut < 0; ++y)
        if (near.data_window().contains(2, y) && near.at(3, 2, y) > 0.0f) cut = y;
    ASSERT_GT(cut, 0);
    ASSERT_LT(cut, 53);  // above the pole
    for (int d = 0; d < 4; ++d) {  // continued rows below the cut: the floor's own pixel
        const int y = cut + d;
        ASSERT_TRUE(far.data_window().contains(2, y));
        EXPECT_EQ(far.at(0, 2, y), img.at(0, 2, y)) << y;
        EXPECT_EQ(far.at(1, 2, y), img.at(1, 2, y)) << y;
        EXPECT_EQ(far.at(4, 2, y), img.at(4, 2, y)) << y;
    }
    // No pole in the far slice: nothing of its colour anywhere there.
    for (int y = far.data_window().y0; y < far.data_window().y1; ++y)
        for (int x = far.data_window().x0; x < far.data_window().x1; ++x) {
            if (pole(x, y)) {
                EXPECT_NE(far.at(0, x, y), 0.9f) << x << "," << y;
            }
        }
    // The source gives the same layers.
    auto src = depth_map_layer_source(img, o);
    ASSERT_TRUE(src) << src.message();
    ASSERT_EQ((*src)->size(), 2);
    for (int i = 0; i < 2; ++i) {
        Layer storage;
        auto made = (*src)->make(i, storage);
        ASSERT_TRUE(made);
        const Image& a = (*made)->image;
        const Image& b = (*layers)[std::size_t(i)].image;
        ASSERT_EQ(a.data_window(), b.data_window());
        for (int c = 0; c < 4; ++c)
            for (std::size_t k = 0; k < a.npixels(); ++k) ASSERT_EQ(a.plane(c)[k], b.plane(c)[k]);
    }
}

// A split silhouette pixel (a hole at a silhouette that the cleanup split,
// plate.h step 5) whose two parts fall into one slice is whole there, with
// the plate's colour, at the foreground's depth: the foreground's blur must
// carry it, as for every other mixed pixel (step 4). At the background's
// depth a pixel that is mostly disc took the wall's blur. With two slices
// its parts are still split between them.
TEST(layers_depth_map, ASplitPixelInOneSliceTakesTheForegroundsDepth) {
    const Image img = scene();
    const int W = kWin.width(), H = kWin.height();
    PlateDepth pd;
    pd.window = kWin;
    pd.depth.resize(std::size_t(W) * std::size_t(H));
    const int zc = img.channel_index("Z");
    for (std::size_t i = 0; i < pd.depth.size(); ++i) pd.depth[i] = img.plane(zc)[i];
    // The pixel just left of the disc: 80% disc, 20% wall.
    const int mx = 15, my = 26;
    ASSERT_FALSE(in_disc(mx, my));
    ASSERT_TRUE(in_disc(mx + 1, my));
    MixedPixel m;
    m.index = std::size_t(my - kWin.y0) * std::size_t(W) + std::size_t(mx - kWin.x0);
    m.fg_depth = 2.0f;
    m.fg_share = 0.8f;
    for (int c = 0; c < 3; ++c) {
        m.fg_rgb[c] = c == 0 ? 0.9f : 0.1f;
        m.bg_rgb[c] = wall(c, mx, my);
    }
    pd.mixed.push_back(m);
    pd.depth[m.index] = 10.0f;  // a split pixel's own depth is its background's

    SliceOptions one;
    one.split.mode = LayerSplit::Mode::Count;
    one.split.count = 1;
    one.depth = &pd;
    auto whole = layers_from_depth_map(img, one);
    ASSERT_TRUE(whole) << whole.message();
    ASSERT_EQ(whole->size(), 1u);
    const Image& l = (*whole)[0].image;
    EXPECT_EQ(l.at(4, mx, my), 2.0f) << "the wall's depth: the pixel would take the wall's blur";
    for (int c = 0; c < 3; ++c) EXPECT_EQ(l.at(c, mx, my), img.at(c, mx, my)) << c;
    EXPECT_EQ(l.at(3, mx, my), 1.0f);

    SliceOptions two = one;
    two.split.count = 2;
    auto split = layers_from_depth_map(img, two);
    ASSERT_TRUE(split) << split.message();
    ASSERT_EQ(split->size(), 2u);
    const Image& fg = (*split)[0].image;
    const Image& bg = (*split)[1].image;
    EXPECT_NEAR(fg.at(3, mx, my), 0.8f, 1e-6f);
    EXPECT_EQ(fg.at(4, mx, my), 2.0f);
    EXPECT_EQ(bg.at(4, mx, my), 10.0f);
    EXPECT_NEAR(bg.at(0, mx, my), wall(0, mx, my), 1e-6f);
}

// A box's anti-aliased edge a little deeper than the box (within
// `continuity`: the same surface) with a slice bound between the two depths:
// the edge joins the box's layer. Left alone in the next layer, it was the
// nearest thing to the pixels the box hides and continued the background
// there with the box's colour: blurring the box revealed more box instead
// of the wall.
TEST(layers_depth_map, ASurfacesEdgePixelsStayWithItAcrossABound) {
    constexpr int kEdge = 30;
    constexpr float kBox = 0.8f, kWall = 0.1f;
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kWin);
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) {
            const bool box = x <= kEdge;
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = box ? kBox : kWall;
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = x < kEdge ? 3.0f : x == kEdge ? 3.12f : 10.0f;
        }
    SliceOptions o;
    o.split.mode = LayerSplit::Mode::Count;
    o.split.count = 22;  // a bound at 1/d = 1/3 - (1/3 - 1/10) / 22: depth 3.099
    o.extend_px = 8;
    auto layers = layers_from_depth_map(img, o);
    ASSERT_TRUE(layers) << layers.message();
    const int y = (kWin.y0 + kWin.y1) / 2;
    int box_layer = -1;
    for (std::size_t k = 0; k < layers->size() && box_layer < 0; ++k)
        if (at_or((*layers)[k].image, 3, kEdge - 1, y, 0.0f) > 0.0f) box_layer = int(k);
    ASSERT_GE(box_layer, 0);
    EXPECT_EQ(at_or((*layers)[std::size_t(box_layer)].image, 3, kEdge, y, 0.0f), 1.0f) << "the edge is in the box's layer";
    // Behind the box, every layer that continues there continues the wall.
    for (std::size_t k = std::size_t(box_layer) + 1; k < layers->size(); ++k)
        for (int x = kEdge - 6; x < kEdge; ++x) {
            const Image& l = (*layers)[k].image;
            const float a = at_or(l, 3, x, y, 0.0f);
            if (a > 0.0f) {
                EXPECT_NEAR(l.at(0, x, y) / a, kWall, 1e-3f) << "layer " << k << ", x " << x;
            }
        }
}
