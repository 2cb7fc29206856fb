// Live-action plates as they come: a depth map as its own file (--depth), a
// multipart file with depth in its own part, a stereo file (every view, or
// --view), focus from a pixel (--focus-at) and --probe. Each is checked
// against the same plate given as one RGBA + Z file, or the thin lens.
#include <cmath>
#include <cstdio>

#include "cli_test_helpers.h"
#include "gdof/camera.h"

using namespace gdof::test;

namespace {

constexpr int kW = 64, kH = 48;
const char* kLens = " --focal-length-mm 35 --sensor-width-mm 36 --f-number 1 --focus-distance 3";

// A red bar at depth 2 over a textured wall at 5 (left) / 6 (right view).
float colour(int x, int y, int c, int view) {
    if (x >= 20 && x < 30) return c == 0 ? 1.0f : 0.0f;
    return 0.2f + 0.1f * float((x / 4 + y / 4 + c + view) % 3);
}
float depth(int x, int, int view) { return x >= 20 && x < 30 ? 2.0f : 5.0f + float(view); }

// The thin lens of kLens's focal length and sensor at an f-number and focus.
gdof::ThinLens lens_of(double f_number, double focus_distance) {
    gdof::ThinLens l;
    l.focal_length_mm = 35, l.sensor_width_mm = 36, l.f_number = f_number, l.focus_distance = focus_distance;
    l.image_width_px = kW;
    return l;
}

struct PartDesc {
    std::string name, view;
    std::vector<std::string> channels;
    std::function<float(int, int, int)> value;
};

// A multipart EXR (OIIO subimages with name and view attributes).
void write_parts(const std::string& path, const std::vector<PartDesc>& parts) {
    std::vector<OIIO::ImageSpec> specs;
    for (const PartDesc& p : parts) {
        OIIO::ImageSpec s(kW, kH, int(p.channels.size()), OIIO::TypeDesc::FLOAT);
        s.channelnames = p.channels;
        s.alpha_channel = -1, s.z_channel = -1;
        s.attribute("name", p.name);
        if (!p.view.empty()) s.attribute("view", p.view);
        specs.push_back(s);
    }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, int(specs.size()), specs.data())) << out->geterror();
    for (std::size_t k = 0; k < parts.size(); ++k) {
        if (k > 0) {
            ASSERT_TRUE(out->open(path, specs[k], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
        }
        const std::size_t nc = parts[k].channels.size();
        std::vector<float> px(std::size_t(kW) * kH * nc);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (std::size_t c = 0; c < nc; ++c) px[(std::size_t(y) * kW + std::size_t(x)) * nc + c] = parts[k].value(x, y, int(c));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
}

void write_plate(const std::string& path, int view, bool with_z) {
    std::vector<std::string> ch = {"R", "G", "B", "A"};
    if (with_z) ch.push_back("Z");
    write_exr(path, kW, kH, ch, [=](int x, int y, int c) {
        return c < 3 ? colour(x, y, c, view) : c == 3 ? 1.0f : depth(x, y, view);
    });
}

double max_diff(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) return INFINITY;
    double m = 0;
    for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, double(std::abs(a[i] - b[i])));
    return m;
}

}  // namespace

TEST(cli_plates, DepthAsItsOwnFileEqualsOneFileAndSizesMustMatch) {
    ScratchDir dir;
    const std::string plate = dir.file("plate.exr"), z = dir.file("depth.exr"), both = dir.file("both.exr");
    write_plate(plate, 0, false);
    write_plate(both, 0, true);
    write_exr(z, kW, kH, {"Z"}, [](int x, int y, int) { return depth(x, y, 0); });
    auto a = run_gdof(quote(plate) + " --depth " + quote(z) + kLens + " --diffuse -o " + quote(dir.file("a.exr")));
    ASSERT_EQ(a.exit_code, 0) << a.output;
    auto b = run_gdof(quote(both) + kLens + " --diffuse -o " + quote(dir.file("b.exr")));
    ASSERT_EQ(b.exit_code, 0) << b.output;
    EXPECT_EQ(max_diff(read_pixels(dir.file("a.exr")), read_pixels(dir.file("b.exr"))), 0.0);
    // The blurred bar spreads over the sharp wall: red beside it.
    OIIO::ImageSpec spec;
    auto px = read_pixels(dir.file("a.exr"), &spec);
    EXPECT_GT(px[(std::size_t(24) * spec.width + 32) * spec.nchannels], 0.25f);

    // Sizes that differ: an error naming both files and sizes, no output.
    const std::string small = dir.file("small.exr");
    write_exr(small, 32, 32, {"Z"}, [](int, int, int) { return 3.0f; });
    auto bad = run_gdof(quote(plate) + " --depth " + quote(small) + kLens + " --diffuse -o " + quote(dir.file("c.exr")));
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_TRUE(contains(bad.output, "small.exr") && contains(bad.output, "32x32") && contains(bad.output, "64x48") &&
                contains(bad.output, "plate.exr"))
        << bad.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("c.exr")));

    // --depth-channel after --depth: the same name as attached changes
    // nothing; another one is a usage error naming both and the order, not
    // a depth that is silently not found.
    auto same = run_gdof(quote(plate) + " --depth " + quote(z) + " --depth-channel Z" + kLens + " --diffuse -o " +
                         quote(dir.file("d.exr")));
    ASSERT_EQ(same.exit_code, 0) << same.output;
    EXPECT_EQ(max_diff(read_pixels(dir.file("d.exr")), read_pixels(dir.file("b.exr"))), 0.0);
    auto late = run_gdof(quote(plate) + " --depth " + quote(z) + " --depth-channel Y" + kLens + " --diffuse -o " +
                         quote(dir.file("e.exr")));
    EXPECT_EQ(late.exit_code, 2) << late.output;
    EXPECT_TRUE(contains(late.output, "--depth-channel Y") && contains(late.output, "depth.exr") &&
                contains(late.output, "'Z'") && contains(late.output, "before --depth"))
        << late.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("e.exr")));
}

TEST(cli_plates, MultipartDepthPartAndEveryViewOfAStereoFile) {
    ScratchDir dir;
    const std::string stereo = dir.file("stereo.exr");
    auto rgba = [](int view) { return [=](int x, int y, int c) { return c < 3 ? colour(x, y, c, view) : 1.0f; }; };
    auto zpart = [](int view) { return [=](int x, int y, int) { return depth(x, y, view); }; };
    write_parts(stereo, {{"rgba_left", "left", {"R", "G", "B", "A"}, rgba(0)},
                         {"depth_left", "left", {"Z"}, zpart(0)},
                         {"rgba_right", "right", {"R", "G", "B", "A"}, rgba(1)},
                         {"depth_right", "right", {"Z"}, zpart(1)}});
    std::vector<std::vector<float>> single(2);
    for (int v = 0; v < 2; ++v) {
        const std::string p = dir.file("view" + std::to_string(v) + ".exr");
        write_plate(p, v, true);
        auto r = run_gdof(quote(p) + kLens + " --diffuse -o " + quote(dir.file("single" + std::to_string(v) + ".exr")));
        ASSERT_EQ(r.exit_code, 0) << r.output;
        single[std::size_t(v)] = read_pixels(dir.file("single" + std::to_string(v) + ".exr"));
    }
    // Every view, one output part each, each equal to its view on its own.
    auto all = run_gdof(quote(stereo) + kLens + " --diffuse -o " + quote(dir.file("all.exr")));
    ASSERT_EQ(all.exit_code, 0) << all.output;
    for (int v = 0; v < 2; ++v) {
        OIIO::ImageSpec spec;
        auto px = read_pixels(dir.file("all.exr"), &spec, v);
        EXPECT_EQ(spec.get_string_attribute("view"), v == 0 ? "left" : "right");
        EXPECT_EQ(max_diff(px, single[std::size_t(v)]), 0.0) << "view " << v;
    }
    // --view picks one; a view that is not there is named with those that are.
    auto right = run_gdof(quote(stereo) + " --view right" + kLens + " --diffuse -o " + quote(dir.file("right.exr")));
    ASSERT_EQ(right.exit_code, 0) << right.output;
    EXPECT_EQ(max_diff(read_pixels(dir.file("right.exr")), single[1]), 0.0);
    auto none = run_gdof(quote(stereo) + " --view centre" + kLens + " --diffuse -o " + quote(dir.file("x.exr")));
    EXPECT_EQ(none.exit_code, 1);
    EXPECT_TRUE(contains(none.output, "'centre'") && contains(none.output, "'left', 'right'")) << none.output;
    // --part by name: the left view's two parts.
    auto parts = run_gdof(quote(stereo) + " --part rgba_left,depth_left" + kLens + " --diffuse -o " +
                          quote(dir.file("parts.exr")));
    ASSERT_EQ(parts.exit_code, 0) << parts.output;
    EXPECT_EQ(max_diff(read_pixels(dir.file("parts.exr")), single[0]), 0.0);
}

TEST(cli_plates, FocusAtGivesTheDistanceOfThePixelsSurface) {
    ScratchDir dir;
    const std::string plate = dir.file("plate.exr");
    // Depth 5 on the wall with holes (0) and a speckle near the pixel asked.
    write_exr(plate, kW, kH, {"R", "G", "B", "A", "Z"}, [](int x, int y, int c) {
        if (c < 4) return c == 3 ? 1.0f : colour(x, y, c, 0);
        if ((x == 45 && y == 20) || (x == 46 && y == 21)) return 0.0f;
        if (x == 44 && y == 19) return 1.0f;
        return depth(x, y, 0);
    });
    auto r = run_gdof(quote(plate) + kLens + " --focus-at 45,20 --probe 45,20 --eval-blur -o " + quote(dir.file("b.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "pixel 45,20: depth 5,")) << r.output;
    OIIO::ImageSpec spec;
    auto px = read_pixels(dir.file("b.exr"), &spec);
    const int b = spec.channelindex("blur");
    const gdof::ThinLens l = lens_of(1, 5);
    // Sharp on the wall, the bar blurred as a lens focused at 5 blurs it.
    EXPECT_NEAR(px[(std::size_t(10) * kW + 50) * spec.nchannels + b], 0.0, 1e-4);
    EXPECT_NEAR(px[(std::size_t(10) * kW + 25) * spec.nchannels + b], l.coc_radius_px(2.0), 1e-3);
    // A pixel with no valid depth around it, or outside the image: named.
    auto out = run_gdof(quote(plate) + kLens + " --focus-at 500,20 --eval-blur -o " + quote(dir.file("c.exr")));
    EXPECT_EQ(out.exit_code, 1);
    EXPECT_TRUE(contains(out.output, "pixel (500, 20)") && contains(out.output, "--focus-at")) << out.output;
    // A depth inside the lens's focal length (millimetres read as metres, or a
    // 16-bit file read as 0..1): named as a depth decoding problem, no output.
    auto mm = run_gdof(quote(plate) + kLens + " --depth-encoding scaled --depth-scale 0.001 --focus-at 45,20 --diffuse -o " +
                       quote(dir.file("d.exr")));
    EXPECT_EQ(mm.exit_code, 1);
    EXPECT_TRUE(contains(mm.output, "--focus-at") && contains(mm.output, "focus at pixel (45, 20)") &&
                contains(mm.output, "0.005 scene units") &&
                contains(mm.output, "focal length (0.035)") && contains(mm.output, "--depth-scale"))
        << mm.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("d.exr")));
    // A hole wider than the median's window under the pixel: the depth the
    // hole fill gives there (the wall's 5), said on stderr.
    const std::string holed = dir.file("holed.exr");
    write_exr(holed, kW, kH, {"R", "G", "B", "A", "Z"}, [](int x, int y, int c) {
        if (c < 4) return c == 3 ? 1.0f : colour(x, y, c, 0);
        return std::abs(x - 50) <= 5 && std::abs(y - 10) <= 5 ? 0.0f : depth(x, y, 0);
    });
    // Said once, though the probe and the blur map each find the focus.
    auto h = run_gdof(quote(holed) + kLens + " --focus-at 50,10 --probe 50,10 --eval-blur -o " + quote(dir.file("h.exr")));
    ASSERT_EQ(h.exit_code, 0) << h.output;
    const std::string note = "no measured depth within 2 px; focusing at the depth the hole fill gives there (5)";
    const std::size_t first = h.output.find(note);
    EXPECT_TRUE(first != std::string::npos && h.output.find(note, first + 1) == std::string::npos &&
                contains(h.output, "pixel 50,10: depth 5, ") && contains(h.output, "blur 0 px"))
        << h.output;
}

TEST(cli_plates, ProbeTellsTheDepthBeforeAnyLensIsGiven) {
    // A probe is how a focus is chosen: it needs no f-number or focus
    // distance (no blur then), nor a focal length (only the depth then), and
    // says what is missing. The world position is the camera's unprojection.
    ScratchDir dir;
    const std::string plate = dir.file("plate.exr");
    write_exr(plate, kW, kH, {"R", "G", "B", "A", "Z"},
              [](int x, int y, int c) { return c < 4 ? (c == 3 ? 1.0f : colour(x, y, c, 0)) : depth(x, y, 0); });
    auto bare = run_gdof(quote(plate) + " --probe 45,20");
    ASSERT_EQ(bare.exit_code, 0) << bare.output;
    EXPECT_TRUE(contains(bare.output, "pixel 45,20: depth 5 (no world position or blur: no camera") &&
                contains(bare.output, "--focal-length-mm"))
        << bare.output;
    EXPECT_FALSE(contains(bare.output, "world (")) << bare.output;
    auto focal = run_gdof(quote(plate) + " --focal-length-mm 35 --sensor-width-mm 36 --probe 45,20");
    ASSERT_EQ(focal.exit_code, 0) << focal.output;
    const double fx = 35.0 / 36.0 * kW, wx = (45.5 - kW / 2.0) / fx * 5.0;
    char world[64];
    std::snprintf(world, sizeof world, "world (%g, ", wx);
    EXPECT_TRUE(contains(focal.output, "pixel 45,20: depth 5, ") && contains(focal.output, world) &&
                contains(focal.output, ", 5) (no blur") && contains(focal.output, "--focus-at"))
        << focal.output << " expected " << world;
    auto full = run_gdof(quote(plate) + kLens + " --probe 25,20");
    ASSERT_EQ(full.exit_code, 0) << full.output;
    const gdof::ThinLens l = lens_of(1, 3);
    const std::size_t b = full.output.find("blur ");
    ASSERT_NE(b, std::string::npos) << full.output;
    EXPECT_TRUE(contains(full.output, "pixel 25,20: depth 2, ")) << full.output;
    EXPECT_NEAR(std::stod(full.output.substr(b + 5)), l.coc_radius_px(2.0), 1e-4 * l.coc_radius_px(2.0)) << full.output;
    EXPECT_FALSE(contains(full.output, "(no ")) << full.output;
    // A distance along the ray cannot be decoded without a camera: named.
    auto range = run_gdof(quote(plate) + " --depth-range --probe 45,20");
    EXPECT_EQ(range.exit_code, 1);
    EXPECT_TRUE(contains(range.output, "needs a camera") && contains(range.output, "--focal-length-mm")) << range.output;
}

TEST(cli_plates, ProbeShowsASilhouettePixelTheDefocusSplits) {
    // The bar's right edge pixel (column 30) is 0.4 bar, 0.6 wall, with a
    // renderer's filtered Z. Focused on the bar, the defocus splits it (the
    // wall's share blurs with the wall) and the probe says into what;
    // focused on the wall, it stays whole and the probe says nothing of it.
    ScratchDir dir;
    const std::string plate = dir.file("edge.exr");
    constexpr float kShare = 0.4f;
    write_exr(plate, kW, kH, {"R", "G", "B", "A", "Z"}, [](int x, int, int c) {
        const float bar = c == 0 ? 1.0f : 0.0f, wall = 0.3f;
        if (c == 3) return 1.0f;
        if (x == 30) return c < 3 ? kShare * bar + (1 - kShare) * wall : kShare * 2.0f + (1 - kShare) * 5.0f;
        return c < 3 ? (x >= 20 && x < 30 ? bar : wall) : (x >= 20 && x < 30 ? 2.0f : 5.0f);
    });
    // f/0.1: the wall blurred by 3.3 px at this size.
    const std::string lens = " --focal-length-mm 35 --sensor-width-mm 36 --f-number 0.1 --focus-distance ";
    auto on_bar = run_gdof(quote(plate) + lens + "2 --probe 30,20");
    ASSERT_EQ(on_bar.exit_code, 0) << on_bar.output;
    const gdof::ThinLens l = lens_of(0.1, 2);
    const std::size_t at = on_bar.output.find("a split silhouette pixel: ");
    ASSERT_NE(at, std::string::npos) << on_bar.output;
    EXPECT_NEAR(std::stod(on_bar.output.substr(at + 26)), kShare, 0.05) << on_bar.output;
    char parts[160];
    std::snprintf(parts, sizeof parts, " foreground at depth 2 (blur 0 px), the rest at depth 5 (blur %g px)",
                  l.coc_radius_px(5.0));
    EXPECT_TRUE(contains(on_bar.output, parts)) << on_bar.output << " expected " << parts;
    auto on_wall = run_gdof(quote(plate) + lens + "5 --probe 30,20");
    ASSERT_EQ(on_wall.exit_code, 0) << on_wall.output;
    EXPECT_TRUE(contains(on_wall.output, "pixel 30,20: depth ")) << on_wall.output;
    EXPECT_FALSE(contains(on_wall.output, "split")) << on_wall.output;
}

TEST(cli_plates, RealRgbdFramesInOneCommand) {
    GDOF_REQUIRE_SHARED(tum_c, "rgbd/tum/color.png");
    GDOF_REQUIRE_SHARED(tum_d, "rgbd/tum/depth.png");
    GDOF_REQUIRE_SHARED(red_c, "rgbd/redwood/color.jpg");
    GDOF_REQUIRE_SHARED(red_d, "rgbd/redwood/depth.png");
    ScratchDir dir;
    // TUM: metres = counts / 5000; Redwood: millimetres (0..1 read -> x 65.535 m).
    const std::pair<std::string, std::string> runs[] = {
        {quote(tum_c) + " --depth-channel Y --depth-encoding scaled --depth-scale 13.107 --depth " + quote(tum_d), "tum"},
        {quote(red_c) + " --depth-channel Y --depth-encoding scaled --depth-scale 65.535 --depth " + quote(red_d), "redwood"}};
    for (const auto& [in, name] : runs) {
        const std::string out = dir.file(name + ".exr");
        auto r = run_gdof(in + " --focal-length-mm 50 --sensor-width-mm 36 --f-number 0.5 --focus-at 320,240 --stats "
                               "--diffuse -o " + quote(out));
        ASSERT_EQ(r.exit_code, 0) << r.output;
        // Holes are filled (reported), never sky.
        EXPECT_TRUE(contains(r.output, "filled")) << r.output;
        EXPECT_TRUE(contains(r.output, " 0 sky")) << r.output;
        OIIO::ImageSpec spec;
        auto px = read_pixels(out, &spec);
        ASSERT_EQ(spec.width, 640);
        for (float v : px) ASSERT_TRUE(std::isfinite(v)) << name;
        // Opaque: a filled plate has no transparent pixel.
        const int a = spec.channelindex("A");
        ASSERT_GE(a, 0);
        double amin = 1;
        for (std::size_t i = std::size_t(a); i < px.size(); i += std::size_t(spec.nchannels)) amin = std::min(amin, double(px[i]));
        EXPECT_GT(amin, 0.999) << name;
    }
}
