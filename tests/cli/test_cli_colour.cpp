// gdof CLI: colour conversion at the edges (--colorconvert, PNG output,
// --iscolorspace, --ocolorspace, --colorconfig and $OCIO).
#include <cmath>

#include "cli/cli_test_helpers.h"

using namespace gdof::test;

namespace {

double srgb_encode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; }
double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// 16x4 linear ramp in 0..1, different per channel; Z and P.x are data.
float ramp(int x, int y, int c) { return float(x + 16 * y) / 63.f * (c == 0 ? 1.f : c == 1 ? 0.5f : 0.25f); }

void write_ramp(const std::string& path) {
    write_exr(path, 16, 4, {"R", "G", "B", "Z", "P.x"}, [](int x, int y, int c) {
        return c < 3 ? ramp(x, y, c) : 0.5f;
    });
}

const char* kTinyConfig = R"(ocio_profile_version: 2
roles:
  default: lin
  scene_linear: lin
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  monitor:
    - !<View> {name: Raw, colorspace: lin}
colorspaces:
  - !<ColorSpace>
    name: lin
    encoding: scene-linear
  - !<ColorSpace>
    name: gamma2
    to_scene_reference: !<ExponentTransform> {value: [2, 2, 2, 1]}
)";

std::vector<unsigned char> read_u8(const std::string& path, OIIO::ImageSpec* spec) {
    std::vector<unsigned char> px;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path;
        return px;
    }
    *spec = in->spec();
    px.resize(std::size_t(spec->width * spec->height * spec->nchannels));
    EXPECT_TRUE(in->read_image(0, 0, 0, spec->nchannels, OIIO::TypeDesc::UINT8, px.data()));
    return px;
}

}  // namespace

TEST(cli_colour, PngOutputIsSrgbOfLinearInput) {
    ScratchDir dir;
    write_exr(dir.file("in.exr"), 16, 4, {"R", "G", "B"}, ramp);
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(dir.file("out.png")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    auto px = read_u8(dir.file("out.png"), &s);
    ASSERT_EQ(s.nchannels, 3);
    EXPECT_EQ(s.format, OIIO::TypeDesc::UINT8);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c) {
                const double expect = 255.0 * srgb_encode(ramp(x, y, c));
                EXPECT_NEAR(px[std::size_t((y * 16 + x) * 3 + c)], expect, 0.51 + 1e-3) << x << "," << y << "," << c;
            }
}

TEST(cli_colour, ColorconvertChangesOnlyColourChannels) {
    ScratchDir dir;
    write_ramp(dir.file("in.exr"));
    auto r = run_gdof(quote(dir.file("in.exr")) + " --colorconvert linear sRGB -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    auto px = read_pixels(dir.file("out.exr"), &s);
    const int cr = s.channelindex("R"), cz = s.channelindex("Z"), cp = s.channelindex("P.x");
    ASSERT_GE(cr, 0);
    ASSERT_GE(cz, 0);
    ASSERT_GE(cp, 0);
    for (int i = 0; i < 64; ++i) {
        const int x = i % 16, y = i / 16;
        EXPECT_NEAR(px[std::size_t(i * s.nchannels + cr)], srgb_encode(ramp(x, y, 0)), 1e-5) << i;
        EXPECT_EQ(px[std::size_t(i * s.nchannels + cz)], 0.5f);
        EXPECT_EQ(px[std::size_t(i * s.nchannels + cp)], 0.5f);
    }
}

TEST(cli_colour, ColorconvertThenPngIsNotConvertedTwice) {
    ScratchDir dir;
    write_exr(dir.file("in.exr"), 16, 4, {"R", "G", "B"}, ramp);
    auto a = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(dir.file("direct.png")));
    auto b = run_gdof(quote(dir.file("in.exr")) + " --colorconvert linear sRGB -o " + quote(dir.file("converted.png")));
    ASSERT_EQ(a.exit_code, 0) << a.output;
    ASSERT_EQ(b.exit_code, 0) << b.output;
    OIIO::ImageSpec sa, sb;
    EXPECT_EQ(read_u8(dir.file("direct.png"), &sa), read_u8(dir.file("converted.png"), &sb));
}

TEST(cli_colour, OcolorspaceLinearWritesLinearPng) {
    ScratchDir dir;
    write_exr(dir.file("in.exr"), 16, 4, {"R", "G", "B"}, ramp);
    auto r = run_gdof(quote(dir.file("in.exr")) + " --ocolorspace linear -o " + quote(dir.file("out.png")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    auto px = read_u8(dir.file("out.png"), &s);
    for (int i = 0; i < 64; ++i)
        EXPECT_NEAR(px[std::size_t(i * 3)], 255.0 * ramp(i % 16, i / 16, 0), 0.51 + 1e-3) << i;
}

TEST(cli_colour, PngInputIsLinearisedAndIscolorspaceOverrides) {
    ScratchDir dir;
    {
        OIIO::ImageSpec spec(16, 1, 3, OIIO::TypeDesc::UINT8);
        std::vector<unsigned char> px(48);
        for (int i = 0; i < 48; ++i) px[std::size_t(i)] = static_cast<unsigned char>((i / 3) * 17);
        auto out = OIIO::ImageOutput::create(dir.file("in.png"));
        ASSERT_TRUE(out && out->open(dir.file("in.png"), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
        out->close();
    }
    auto r = run_gdof(quote(dir.file("in.png")) + " -o " + quote(dir.file("lin.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto lin = read_pixels(dir.file("lin.exr"));
    ASSERT_EQ(lin.size(), 48u);
    for (int x = 0; x < 16; ++x) EXPECT_NEAR(lin[std::size_t(x * 3)], srgb_decode(x * 17 / 255.0), 1e-5) << x;

    r = run_gdof("--iscolorspace linear " + quote(dir.file("in.png")) + " -o " + quote(dir.file("raw.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto raw = read_pixels(dir.file("raw.exr"));
    for (int x = 0; x < 16; ++x) EXPECT_NEAR(raw[std::size_t(x * 3)], x * 17 / 255.0, 1e-5) << x;

    // --iscolorspace on an EXR: decoded from sRGB on read.
    write_exr(dir.file("enc.exr"), 16, 4, {"R", "G", "B"}, ramp);
    r = run_gdof("--iscolorspace sRGB " + quote(dir.file("enc.exr")) + " -o " + quote(dir.file("dec.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto dec = read_pixels(dir.file("dec.exr"));
    for (int i = 0; i < 64; ++i) EXPECT_NEAR(dec[std::size_t(i * 3 + 1)], srgb_decode(ramp(i % 16, i / 16, 1)), 1e-5);
}

TEST(cli_colour, ColorconfigFileAndEnvironment) {
    ScratchDir dir;
    write_text(dir.file("tiny.ocio"), kTinyConfig);
    write_exr(dir.file("in.exr"), 16, 4, {"R", "G", "B"}, ramp);
    auto r = run_gdof("--colorconfig " + quote(dir.file("tiny.ocio")) + " " + quote(dir.file("in.exr")) +
                      " --colorconvert gamma2 lin -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto px = read_pixels(dir.file("out.exr"));
    for (int i = 0; i < 64; ++i) EXPECT_NEAR(px[std::size_t(i * 3)], std::pow(ramp(i % 16, i / 16, 0), 2.0), 1e-5);

    // $OCIO: same config through the environment.
    r = run_command("OCIO=" + quote(dir.file("tiny.ocio")) + " '" + GDOF_CLI_PATH + "' " + quote(dir.file("in.exr")) +
                    " --colorconvert lin gamma2 -o " + quote(dir.file("env.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    px = read_pixels(dir.file("env.exr"));
    for (int i = 0; i < 64; ++i) EXPECT_NEAR(px[std::size_t(i * 3)], std::sqrt(ramp(i % 16, i / 16, 0)), 1e-5);

    // A broken $OCIO is an error naming it.
    r = run_command("OCIO=" + quote(dir.file("gone.ocio")) + " '" + GDOF_CLI_PATH + "' " + quote(dir.file("in.exr")) +
                    " -o " + quote(dir.file("x.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "gone.ocio")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("x.exr")));
}

TEST(cli_colour, BadConfigAndUnknownSpaceAreNamed) {
    ScratchDir dir;
    write_exr(dir.file("in.exr"), 4, 4, {"R", "G", "B"}, ramp);
    auto r = run_gdof("--colorconfig " + quote(dir.file("missing.ocio")) + " " + quote(dir.file("in.exr")) + " -o " +
                      quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "missing.ocio")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));

    r = run_gdof(quote(dir.file("in.exr")) + " --colorconvert linear NotASpace -o " + quote(dir.file("out.exr")));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "NotASpace")) << r.output;
    EXPECT_TRUE(contains(r.output, "--colorconvert")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));

    r = run_gdof(quote(dir.file("in.exr")) + " --ocolorspace Bogus -o " + quote(dir.file("out.png")));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "Bogus")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.png")));
}
