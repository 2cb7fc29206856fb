// On a real RGB-D frame (TUM, ../shared/data/rgbd/tum), a blurred foreground
// (the red chair, about 1.6 m, blur radius 10 px) must spread over the sharp
// background behind it (the desk and floor, 2 m and beyond, focused at
// 2.4 m) as a blurred object does: the coverage it puts on background pixels
// 1 to R/2 px outside its silhouette is compared with the analytic one, the
// foreground's mask blurred by the Gaussian of its radius (sigma = R / 2).
// The coverage is measured by linearity: the foreground's blue raised by 1,
// the difference of the two results divided by 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "gdof/plate.h"
#include "test_support.h"

using namespace gdof;

namespace {

// The mask blurred by a Gaussian of sigma s (separable, zero outside).
std::vector<double> gaussian_blur(const std::vector<double>& m, int W, int H, double s) {
    const int r = int(std::ceil(4 * s));
    std::vector<double> k(std::size_t(2 * r + 1));
    double sum = 0;
    for (int i = -r; i <= r; ++i) sum += k[std::size_t(i + r)] = std::exp(-0.5 * i * i / (s * s));
    for (double& v : k) v /= sum;
    std::vector<double> t(m.size(), 0.0), o(m.size(), 0.0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int i = -r; i <= r; ++i)
                if (x + i >= 0 && x + i < W) t[std::size_t(y) * W + x] += k[std::size_t(i + r)] * m[std::size_t(y) * W + x + i];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int i = -r; i <= r; ++i)
                if (y + i >= 0 && y + i < H) o[std::size_t(y) * W + x] += k[std::size_t(i + r)] * t[std::size_t(y + i) * W + x];
    return o;
}

}  // namespace

TEST(plate_coverage, BlurredForegroundCoversTheSharpBackgroundOfARealFrame) {
    GDOF_REQUIRE_SHARED(depth_path, "rgbd/tum/depth.png");
    GDOF_REQUIRE_SHARED(color_path, "rgbd/tum/color.png");
    auto colour = io::read_flat(color_path);
    ASSERT_TRUE(colour) << colour.message();
    io::ReadOptions raw;
    raw.colorspace = "raw";
    auto depth = io::read_flat(depth_path, raw);
    ASSERT_TRUE(depth) << depth.message();
    const Roi win = colour->data_window();
    const int W = win.width(), H = win.height();
    Image img = Image::with_channels({"R", "G", "B", "Z"}, win);
    const RgbaIndices ix = find_rgba(*colour);
    const int src[3] = {ix.r, ix.g, ix.b};
    for (int c = 0; c < 3; ++c) std::copy_n(colour->plane(src[c]), img.npixels(), img.plane(c));
    std::copy_n(depth->plane(0), img.npixels(), img.plane(3));
    DepthDecode decode;
    decode.encoding = DepthEncoding::Scaled;
    decode.scale = 65535.0 / 5000.0;

    // Focused on the background at 2.4 m; the aperture that blurs 1.6 m by 10 px.
    ThinLens lens;
    lens.focal_length_mm = 50, lens.sensor_width_mm = 36, lens.focus_distance = 2.4, lens.image_width_px = W;
    lens.f_number = 1.0;
    lens.f_number = lens.coc_radius_px(1.6) / 10.0;
    LensOverrides lo;
    lo.focal_length_mm = lens.focal_length_mm, lo.sensor_width_mm = lens.sensor_width_mm;
    lo.f_number = lens.f_number, lo.focus_distance = lens.focus_distance;
    const Camera cam = resolve_camera(Metadata{}, win, lo).value();
    const BlurField field = BlurField::from_thin_lens(lens).value();

    // The foreground: prepared depth below 1.75 m (the red chair).
    auto pd = prepare_plate_depth(img, 3, decode, cam);
    ASSERT_TRUE(pd) << pd.message();
    std::vector<double> fg(img.npixels(), 0.0);
    std::vector<float> fg_r;
    for (std::size_t i = 0; i < fg.size(); ++i)
        if (pd->depth[i] < 1.75f) fg[i] = 1.0, fg_r.push_back(float(lens.coc_radius_px(pd->depth[i])));
    ASSERT_GT(fg_r.size(), 5000u);
    std::nth_element(fg_r.begin(), fg_r.begin() + std::ptrdiff_t(fg_r.size() / 2), fg_r.end());
    const double R = fg_r[fg_r.size() / 2];

    DefocusOptions opt;
    opt.source.depth_decode = decode;
    ImageSet a, b;
    a.parts.emplace_back(img);
    Image marked = img;
    for (std::size_t i = 0; i < fg.size(); ++i) marked.plane(2)[i] += float(fg[i]);
    b.parts.emplace_back(marked);
    auto out_a = defocus(a, field, cam, opt);
    ASSERT_TRUE(out_a) << out_a.message();
    auto out_b = defocus(b, field, cam, opt);
    ASSERT_TRUE(out_b) << out_b.message();
    const Image& A = out_a->flat(0);
    const Image& B = out_b->flat(0);
    const int cb = A.channel_index("B");

    // Background pixels 1 .. R/2 px outside the silhouette, at 2 m or beyond
    // and sharper than 3 px.
    std::vector<float> dist;
    std::vector<unsigned char> mask(fg.size());
    for (std::size_t i = 0; i < fg.size(); ++i) mask[i] = fg[i] > 0;
    const std::vector<double> analytic = gaussian_blur(fg, W, H, R / 2.0);
    double measured_sum = 0, analytic_sum = 0;
    std::size_t n = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            if (mask[i] || pd->depth[i] < 2.0f || lens.coc_radius_px(pd->depth[i]) > 3.0) continue;
            double d = 1e9;  // distance to the foreground (a window search: R is small)
            const int r = int(std::ceil(R / 2));
            for (int yy = std::max(0, y - r); yy <= std::min(H - 1, y + r); ++yy)
                for (int xx = std::max(0, x - r); xx <= std::min(W - 1, x + r); ++xx)
                    if (mask[std::size_t(yy) * W + xx]) d = std::min(d, std::hypot(double(xx - x), double(yy - y)));
            if (d < 1.0 || d > R / 2) continue;
            measured_sum += double(B.at(cb, win.x0 + x, win.y0 + y)) - double(A.at(cb, win.x0 + x, win.y0 + y));
            analytic_sum += analytic[i];
            ++n;
        }
    ASSERT_GT(n, 100u);
    const double measured = measured_sum / double(n), expected = analytic_sum / double(n);
    std::printf("[ measured ] TUM red chair, R = %.2f px: coverage 1..R/2 px outside on %zu sharp background "
                "pixels %.4f, analytic %.4f\n",
                R, n, measured, expected);
    EXPECT_NEAR(measured, expected, 0.3 * expected);
}
