// gdof CLI: --blurfield and --eval-blur against the analytic thin-lens CoC.
#include <cmath>

#include "cli/cli_test_helpers.h"
#include "gdof/deep.h"
#include "gdof/io/image_io.h"

using namespace gdof::test;

namespace {

constexpr double kF = 50.0, kN = 2.0, kS = 3.0, kSensor = 36.0;  // mm, -, m, mm
constexpr int kW = 16, kH = 8, kFullW = 32, kFullH = 16;

// Thin lens written out: CoC diameter c = (f/N) f |z - s| / (z (s - f)) (mm),
// radius in output pixels = c/2 * image_width_px / sensor_width.
double coc_px(double depth_m, double n = kN) {
    const double f = kF, s = kS * 1000.0, z = depth_m * 1000.0;
    const double c = (f / n) * f * std::fabs(z - s) / (z * (s - f));
    return 0.5 * c * double(kFullW) / kSensor;
}

const char* kThinLens = R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2,
                            "focus_distance": 3, "sensor_width_mm": 36}})";

// Camera: world -> camera is a translation by +1 in z (camera at z = -1,
// looking down +z); lens from attributes; display window 32x16, data window
// 16x8 at (4, 2).
void camera_setup(OIIO::ImageSpec& s, bool with_lens) {
    s.x = 4;
    s.y = 2;
    s.full_x = 0;
    s.full_y = 0;
    s.full_width = kFullW;
    s.full_height = kFullH;
    const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1};
    s.attribute("worldToCamera", OIIO::TypeMatrix, m);
    s.attribute("focalLength", float(kF));
    s.attribute("sensorWidth", float(kSensor));
    if (with_lens) {
        s.attribute("fNumber", float(kN));
        s.attribute("focusDistance", float(kS));
    }
}

// World positions: z from 1 to ~10, varying per pixel; camera depth = z + 1.
double pz(int x, int y) { return 0.6 + 0.5 * x + 0.3 * y; }

void write_p_image(const std::string& path) {
    write_exr(path, kW, kH, {"R", "G", "B", "P.x", "P.y", "P.z"}, [](int x, int y, int c) {
        if (c < 3) return 0.5f;
        if (c == 3) return float(0.1 * x);
        if (c == 4) return float(-0.1 * y);
        return float(pz(x, y));
    }, [](OIIO::ImageSpec& s) { camera_setup(s, false); });
}

void write_z_image(const std::string& path, bool with_lens, const std::string& zname = "Z") {
    write_exr(path, kW, kH, {"R", "G", "B", zname}, [](int x, int y, int c) {
        return c < 3 ? 0.5f : float(pz(x, y) + 1.0);
    }, [with_lens](OIIO::ImageSpec& s) { camera_setup(s, with_lens); });
}

// Checks the "blur" channel of out against the thin lens for depth(x, y).
void expect_thin_lens(const std::string& out, double n = kN) {
    OIIO::ImageSpec s;
    auto px = read_pixels(out, &s);
    const int b = s.channelindex("blur");
    ASSERT_GE(b, 0) << "no blur channel in " << out;
    EXPECT_EQ(s.channelformat(b), OIIO::TypeDesc::FLOAT);
    ASSERT_EQ(s.x, 4);
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) {
            const int x = s.x + i, y = s.y + j;
            const double expect = coc_px(pz(x, y) + 1.0, n);
            const float got = px[std::size_t((j * kW + i) * s.nchannels + b)];
            ASSERT_NEAR(got, expect, 1e-4 * std::max(1.0, expect)) << "pixel " << x << "," << y;
        }
}

}  // namespace

TEST(cli_blur, EvalBlurFromPositionsMatchesThinLens) {
    ScratchDir dir;
    write_p_image(dir.file("in.exr"));
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("field.json")) + " --eval-blur -o " +
                      quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("out.exr"));
    // Other channels kept.
    OIIO::ImageSpec s;
    read_pixels(dir.file("out.exr"), &s);
    EXPECT_GE(s.channelindex("P.z"), 0);
    EXPECT_GE(s.channelindex("R"), 0);
}

TEST(cli_blur, EvalBlurFromDepthAndCameraMatchesThinLens) {
    ScratchDir dir;
    write_z_image(dir.file("in.exr"), false);
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof("--threads 2 " + quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                      " --eval-blur -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("out.exr"));
}

TEST(cli_blur, CustomDepthAndPositionChannelNames) {
    ScratchDir dir;
    write_z_image(dir.file("in.exr"), false, "depth.Z");
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                      " --depth-channel depth.Z --eval-blur -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("out.exr"));

    r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                 " --depth-channel Zfoo --eval-blur -o " + quote(dir.file("out2.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "Zfoo")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out2.exr")));

    write_exr(dir.file("pw.exr"), kW, kH, {"Pw.X", "Pw.Y", "Pw.Z"}, [](int x, int y, int c) {
        return c == 2 ? float(pz(x, y)) : 0.f;
    }, [](OIIO::ImageSpec& s) { camera_setup(s, false); });
    r = run_gdof(quote(dir.file("pw.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                 " --position-channels Pw --eval-blur -o " + quote(dir.file("pwout.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("pwout.exr"));
}

TEST(cli_blur, ThinLensFromCameraMetadataAndFlagOverrides) {
    ScratchDir dir;
    write_z_image(dir.file("in.exr"), true);
    // No --blurfield: the camera's own lens.
    auto r = run_gdof(quote(dir.file("in.exr")) + " --eval-blur -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("out.exr"));
    // --f-number overrides the metadata.
    r = run_gdof(quote(dir.file("in.exr")) + " --f-number 4 --eval-blur -o " + quote(dir.file("f4.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("f4.exr"), 4.0);
}

TEST(cli_blur, MissingPositionAndDepthIsNamed) {
    ScratchDir dir;
    write_exr(dir.file("rgb.exr"), 4, 4, {"R", "G", "B", "A"}, [](int, int, int) { return 1.f; });
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof(quote(dir.file("rgb.exr")) + " --blurfield " + quote(dir.file("field.json")) + " --eval-blur -o " +
                      quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "rgb.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "P.x")) << r.output;
    EXPECT_TRUE(contains(r.output, "'Z'")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

TEST(cli_blur, MissingCameraIsNamed) {
    ScratchDir dir;
    write_exr(dir.file("z.exr"), 4, 4, {"R", "G", "B", "Z"}, [](int, int, int) { return 2.f; });
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof(quote(dir.file("z.exr")) + " --blurfield " + quote(dir.file("field.json")) + " --eval-blur -o " +
                      quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "worldToCamera")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
    // An explicit lens gives a camera at the origin: works.
    r = run_gdof(quote(dir.file("z.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                 " --focal-length-mm 50 --eval-blur -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(cli_blur, BadBlurFieldJsonNamesFileAndKey) {
    ScratchDir dir;
    write_z_image(dir.file("in.exr"), false);
    write_text(dir.file("extra.json"), R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2,
                                          "focus_distance": 3, "bogus_key": 1}})");
    write_text(dir.file("negative.json"), R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50,
                                             "f_number": -2, "focus_distance": 3}})");
    write_text(dir.file("syntax.json"), "{\"blurfield\": {\"kind\": ");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"extra.json", "bogus_key"}, {"negative.json", "f_number"}, {"syntax.json", "syntax.json"}};
    for (const auto& [file, key] : cases) {
        auto r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file(file)) + " --eval-blur -o " +
                          quote(dir.file("out.exr")));
        EXPECT_EQ(r.exit_code, 1) << file << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, file)) << r.output;
        EXPECT_TRUE(contains(r.output, key)) << r.output;
        EXPECT_TRUE(contains(r.output, "gdof: error:")) << r.output;
        EXPECT_FALSE(fs::exists(dir.file("out.exr")));
    }
}

TEST(cli_blur, EvalBlurOnSequence) {
    ScratchDir dir;
    write_z_image(dir.file("in.0001.exr"), false);
    write_z_image(dir.file("in.0002.exr"), false);
    write_text(dir.file("field.json"), kThinLens);
    auto r = run_gdof("--frames 1-2 " + quote(dir.file("in.####.exr")) + " --blurfield " + quote(dir.file("field.json")) +
                      " --eval-blur -o " + quote(dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_thin_lens(dir.file("out.0001.exr"));
    expect_thin_lens(dir.file("out.0002.exr"));
}

TEST(cli_blur, EvalBlurOnDeepSamples) {
    ScratchDir dir;
    // 4x3 deep image, pixel i has i % 3 samples at depths 1 + 0.5 k + 0.1 i.
    gdof::DeepImage deep({{"R", gdof::PixelType::Half}, {"A", gdof::PixelType::Half}, {"Z", gdof::PixelType::Float}},
                         gdof::Roi{0, 0, 4, 3}, gdof::Roi{0, 0, kFullW, kFullH});
    std::vector<std::uint32_t> counts(12);
    for (int i = 0; i < 12; ++i) counts[std::size_t(i)] = std::uint32_t(i % 3);
    EXPECT_TRUE(deep.set_sample_counts(counts));
    for (std::size_t p = 0; p < 12; ++p)
        for (std::uint32_t k = 0; k < deep.sample_count(p); ++k)
            deep.samples(2)[deep.first_sample(p) + k] = float(1.0 + 0.5 * k + 0.1 * double(p));
    gdof::Metadata& md = deep.metadata;
    md.set_matrix("worldToCamera", gdof::Mat44::identity());
    md.set_float("focalLength", kF);
    md.set_float("sensorWidth", kSensor);
    gdof::ImageSet set;
    set.parts.push_back(std::move(deep));
    ASSERT_TRUE(gdof::io::write_image(dir.file("deep.exr"), set).is_ok());
    write_text(dir.file("field.json"), kThinLens);

    auto r = run_gdof(quote(dir.file("deep.exr")) + " --blurfield " + quote(dir.file("field.json")) + " --eval-blur -o " +
                      quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto back = gdof::io::read_image(dir.file("out.exr"));
    ASSERT_TRUE(back.is_ok()) << back.message();
    ASSERT_TRUE(back->is_deep(0));
    const gdof::DeepImage& out = back->deep(0);
    const int b = out.channel_index("blur"), z = out.channel_index("Z");
    ASSERT_GE(b, 0);
    ASSERT_GE(z, 0);
    ASSERT_EQ(out.total_samples(), 12u);
    for (std::size_t s = 0; s < out.total_samples(); ++s)
        EXPECT_NEAR(out.samples(b)[s], coc_px(out.samples(z)[s]), 1e-4) << s;
}

TEST(cli_blur, ImageMapLoadsPaintedMaskAsData) {
    ScratchDir dir;
    // 8-bit mask over the whole display window, relative to the JSON file.
    {
        OIIO::ImageSpec spec(kFullW, kFullH, 1, OIIO::TypeDesc::UINT8);
        std::vector<unsigned char> px(std::size_t(kFullW * kFullH));
        for (int y = 0; y < kFullH; ++y)
            for (int x = 0; x < kFullW; ++x) px[std::size_t(y * kFullW + x)] = static_cast<unsigned char>(x * 7 + y);
        auto out = OIIO::ImageOutput::create(dir.file("mask.png"));
        ASSERT_TRUE(out && out->open(dir.file("mask.png"), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
        out->close();
    }
    write_text(dir.file("map.json"), R"({"blurfield": {"kind": "image_map", "image": "mask.png", "scale": 10}})");
    write_z_image(dir.file("in.exr"), false);
    auto r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("map.json")) + " --eval-blur -o " +
                      quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    auto px = read_pixels(dir.file("out.exr"), &s);
    const int b = s.channelindex("blur");
    ASSERT_GE(b, 0);
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) {
            const int x = s.x + i, y = s.y + j;
            EXPECT_NEAR(px[std::size_t((j * kW + i) * s.nchannels + b)], 10.0 * double(x * 7 + y) / 255.0, 1e-4)
                << x << "," << y;
        }

    // A missing map names the key and the file.
    write_text(dir.file("nomap.json"), R"({"blurfield": {"kind": "image_map", "image": "nothere.png"}})");
    r = run_gdof(quote(dir.file("in.exr")) + " --blurfield " + quote(dir.file("nomap.json")) + " --eval-blur -o " +
                 quote(dir.file("out2.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "nomap.json")) << r.output;
    EXPECT_TRUE(contains(r.output, "image")) << r.output;
    EXPECT_TRUE(contains(r.output, "nothere.png")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out2.exr")));
}
