// The solvers take their planes and radius map as views: any layout gives
// the bits of a planar buffer, a cropped window diffuses only itself, and a
// view of the wrong shape is an error naming both shapes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gdof/diffusion.h"
#include "gdof/image.h"

using namespace gdof;

namespace {

const Roi kWin{-3, 4, 26, 21};  // 29 x 17, negative origin

float texture(int x, int y, int c) { return 0.5f + 0.4f * std::sin(0.7f * float(x) + 1.3f * float(c)) * std::cos(0.45f * float(y)); }
float radius_at(int x, int y) { return x < 6 ? 0.0f : 1.0f + 0.2f * float((x + 2 * y) % 17); }  // up to 4.2 px, a sharp band

// Three planes back to back and the radius map over kWin.
struct Planar {
    std::vector<float> planes = std::vector<float>(3 * kWin.npixels()), radius = std::vector<float>(kWin.npixels());
    Planar() {
        const ImageView v = view();
        for (int y = kWin.y0; y < kWin.y1; ++y)
            for (int x = kWin.x0; x < kWin.x1; ++x) {
                for (int c = 0; c < 3; ++c) v.at(c, x, y) = texture(x, y, c);
                radius[std::size_t(y - kWin.y0) * std::size_t(kWin.width()) + std::size_t(x - kWin.x0)] = radius_at(x, y);
            }
    }
    ImageView view() { return ImageView::planar(planes.data(), 3, kWin); }
    ConstImageView radius_view() const { return ConstImageView::planar(radius.data(), 1, kWin); }
};

DiffusionOptions with_solver(DiffusionSolver s) {
    DiffusionOptions o;
    o.solver = s;
    return o;
}

}  // namespace

TEST(diffusion_views, InterleavedPlanesAndRadiusGiveThePlanarBits) {
    for (DiffusionSolver solver : {DiffusionSolver::Explicit, DiffusionSolver::Adi}) {
        Planar ref;
        ASSERT_TRUE(diffuse_planes(ref.view(), ref.radius_view(), with_solver(solver)));
        // RGB interleaved with a spare fourth channel, rows bottom-up; the
        // radius the fourth channel of another interleaved buffer.
        std::vector<float> inter(4 * kWin.npixels(), 7.0f), rbuf(2 * kWin.npixels(), 0.0f);
        const std::ptrdiff_t row = 4 * kWin.width();
        const ImageView iv = ImageView::interleaved(inter.data() + (kWin.height() - 1) * row, 4, kWin, -row);
        const ImageView rv = ImageView::interleaved(rbuf.data(), 2, kWin, 2 * kWin.width());
        for (int y = kWin.y0; y < kWin.y1; ++y)
            for (int x = kWin.x0; x < kWin.x1; ++x) {
                for (int c = 0; c < 3; ++c) iv.at(c, x, y) = texture(x, y, c);
                rv.at(1, x, y) = radius_at(x, y);
            }
        ASSERT_TRUE(diffuse_planes(iv.channels(0, 3), rv.channels(1, 1), with_solver(solver)));
        for (int c = 0; c < 4; ++c)
            for (int y = kWin.y0; y < kWin.y1; ++y)
                for (int x = kWin.x0; x < kWin.x1; ++x)
                    ASSERT_EQ(iv.at(c, x, y), c < 3 ? ref.view().at(c, x, y) : 7.0f)
                        << to_string(solver) << " channel " << c << " at " << x << "," << y;
    }
}

TEST(diffusion_views, ImageChannelsAndACroppedWindowDiffuseInPlace) {
    Planar ref;
    ASSERT_TRUE(diffuse_planes(ref.view(), ref.radius_view(), {}));
    // The same planes as an Image: its channels_view is used directly.
    Image img = Image::with_channels({"R", "G", "B"}, kWin);
    for (int c = 0; c < 3; ++c)
        for (int y = kWin.y0; y < kWin.y1; ++y)
            for (int x = kWin.x0; x < kWin.x1; ++x) img.at(c, x, y) = texture(x, y, c);
    ASSERT_TRUE(diffuse_planes(img.channels_view(), ref.radius_view(), {}));
    for (int c = 0; c < 3; ++c)
        EXPECT_EQ(std::vector<float>(img.plane(c), img.plane(c) + img.npixels()),
                  std::vector<float>(ref.view().plane(c), ref.view().plane(c) + kWin.npixels()));

    // kWin cut out of a larger image: inside, the bits of kWin on its own
    // (its edges insulate); outside, nothing changes.
    const Roi big = kWin.grown(5);
    Image host = Image::with_channels({"R", "G", "B"}, big);
    std::vector<float> rbig(big.npixels(), 9.0f);  // would blur a lot, were it used outside kWin
    const ImageView rb = ImageView::planar(rbig.data(), 1, big);
    for (int c = 0; c < 3; ++c)
        for (int y = big.y0; y < big.y1; ++y)
            for (int x = big.x0; x < big.x1; ++x) host.at(c, x, y) = texture(x, y, c);
    for (int y = kWin.y0; y < kWin.y1; ++y)
        for (int x = kWin.x0; x < kWin.x1; ++x) rb.at(0, x, y) = radius_at(x, y);
    ASSERT_TRUE(diffuse_planes(host.channels_view().cropped(kWin), ConstImageView(rb).cropped(kWin), {}));
    for (int c = 0; c < 3; ++c)
        for (int y = big.y0; y < big.y1; ++y)
            for (int x = big.x0; x < big.x1; ++x)
                ASSERT_EQ(host.at(c, x, y), kWin.contains(x, y) ? ref.view().at(c, x, y) : texture(x, y, c))
                    << c << " " << x << "," << y;
}

TEST(diffusion_views, ViewsOfTheWrongShapeAreErrorsNamingBoth) {
    Planar p;
    const std::vector<float> before = p.planes;
    const Roi other{kWin.x0, kWin.y0, kWin.x1, kWin.y1 - 1};
    Status st = diffuse_planes(p.view(), ConstImageView::planar(p.radius.data(), 1, other), {});
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_NE(st.message().find("radius map"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find(to_string(other)), std::string::npos) << st.message();
    EXPECT_NE(st.message().find(to_string(kWin)), std::string::npos) << st.message();
    st = diffuse_planes(p.view(), ConstImageView::planar(p.planes.data(), 2, kWin), {});
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("2 channels"), std::string::npos) << st.message();
    st = diffuse_planes(ImageView{nullptr, 3, kWin, 0, 1, kWin.width()}, p.radius_view(), {});
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("the planes"), std::string::npos) << st.message();
    // The solvers themselves check their diffusivity map the same way.
    for (auto solve : {&diffuse_explicit, &diffuse_adi}) {
        st = solve(p.view(), ConstImageView::planar(p.radius.data(), 1, other), DiffusionOptions{}, Exec{});
        ASSERT_FALSE(st);
        EXPECT_NE(st.message().find("diffusivity map"), std::string::npos) << st.message();
    }
    EXPECT_EQ(p.planes, before);
    // No pixels, or no planes: nothing to do.
    EXPECT_TRUE(diffuse_planes(ImageView::planar(nullptr, 3, Roi{2, 2, 2, 9}), ConstImageView::planar(nullptr, 1, Roi{2, 2, 2, 9}), {}));
    EXPECT_TRUE(diffuse_planes(p.view().channels(0, 0), p.radius_view(), {}));
    EXPECT_EQ(p.planes, before);
}
