// Colour module: the built-in sRGB/linear config against the IEC 61966-2-1
// formula, channel selection, OCIO configs from a file and from $OCIO, and
// the error messages.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <vector>

#include "gdof/deep.h"
#include "gdof/image.h"
#include "gdof/io/colour.h"
#include "test_support.h"

using namespace gdof;
using gdof::io::ColourConfig;

namespace {

// The IEC 61966-2-1 formulas, written out independently of the library.
double ref_srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }
double ref_linear_to_srgb(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; }

Image rgb_image(const std::vector<float>& values) {
    Image img = Image::with_channels({"R", "G", "B"}, Roi{0, 0, int(values.size()), 1});
    for (int x = 0; x < int(values.size()); ++x)
        for (int c = 0; c < 3; ++c) img.at(c, x, 0) = values[std::size_t(x)] * (c == 0 ? 1.f : 1.f);
    return img;
}

// Tiny OCIO v2 config: a linear reference, a pure 2.2 gamma space and a
// space that is the reference scaled per channel by a matrix.
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
    aliases: [linear_alias]
    encoding: scene-linear
    isdata: false

  - !<ColorSpace>
    name: gamma22
    encoding: sdr-video
    isdata: false
    to_scene_reference: !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1]}

  - !<ColorSpace>
    name: scaled
    isdata: false
    from_scene_reference: !<MatrixTransform> {matrix: [2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 4, 0, 0, 0, 0, 1]}
)";

std::string write_text(const gdof::test::ScratchDir& dir, const std::string& name, const std::string& text) {
    std::string path = dir.file(name);
    std::ofstream(path) << text;
    return path;
}

}  // namespace

TEST(colour, SrgbCurveMatchesFormula) {
    const std::vector<float> enc = {0.f, 0.02f, 0.04045f, 0.5f, 1.f, 1.5f};
    for (float v : enc) EXPECT_NEAR(io::srgb_to_linear(v), ref_srgb_to_linear(v), 1e-7 * std::max(1.0, double(v)));
    // Boundary: both segments agree at the knee (continuity to ~1e-8).
    EXPECT_NEAR(io::srgb_to_linear(0.04045f), 0.04045 / 12.92, 1e-8);
    EXPECT_FLOAT_EQ(io::srgb_to_linear(0.5f), float(std::pow((0.5 + 0.055) / 1.055, 2.4)));
    EXPECT_FLOAT_EQ(io::srgb_to_linear(1.f), 1.f);
    EXPECT_GT(io::srgb_to_linear(2.f), 1.f);  // extended past 1 by the power segment

    const auto config = ColourConfig::builtin();
    Image img = rgb_image(enc);
    ASSERT_TRUE(config->convert(img, "sRGB", "linear").is_ok());
    for (int x = 0; x < int(enc.size()); ++x)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(img.at(c, x, 0), ref_srgb_to_linear(enc[std::size_t(x)]), 1e-6) << "x=" << x << " c=" << c;

    const std::vector<float> lin = {0.f, 0.001f, 0.0031308f, 0.18f, 0.5f, 1.f, 4.f};
    Image img2 = rgb_image(lin);
    ASSERT_TRUE(config->convert(img2, "linear", "sRGB").is_ok());
    for (int x = 0; x < int(lin.size()); ++x)
        EXPECT_NEAR(img2.at(1, x, 0), ref_linear_to_srgb(lin[std::size_t(x)]), 1e-6) << "x=" << x;
    EXPECT_NEAR(io::linear_to_srgb(1.f), 1.f, 1e-6);
}

TEST(colour, RoundTripIsIdentity) {
    const auto config = ColourConfig::builtin();
    std::vector<float> values;
    for (int i = -10; i <= 300; ++i) values.push_back(float(i) / 200.f);
    Image img = rgb_image(values);
    ASSERT_TRUE(config->convert(img, "linear", "sRGB").is_ok());
    ASSERT_TRUE(config->convert(img, "sRGB", "linear").is_ok());
    for (int x = 0; x < int(values.size()); ++x)
        EXPECT_NEAR(img.at(0, x, 0), values[std::size_t(x)], 2e-6 * std::max(1.f, std::fabs(values[std::size_t(x)])));
}

TEST(colour, BuiltinAliases) {
    const auto config = ColourConfig::builtin();
    for (const char* n : {"linear", "scene_linear", "Linear", "lin_rec709"}) EXPECT_EQ(config->resolve(n), "linear") << n;
    for (const char* n : {"sRGB", "srgb", "sRGB - Texture", "srgb_texture", "Utility - sRGB - Texture"})
        EXPECT_EQ(config->resolve(n), "sRGB") << n;
    EXPECT_EQ(config->resolve("raw"), "raw");
    EXPECT_EQ(config->resolve("ACEScg"), "");
    EXPECT_TRUE(config->is_linear("linear"));
    EXPECT_FALSE(config->is_linear("sRGB"));

    // raw is no conversion either way.
    Image img = rgb_image({0.5f});
    ASSERT_TRUE(config->convert(img, "raw", "sRGB").is_ok());
    EXPECT_EQ(img.at(0, 0, 0), 0.5f);
    ASSERT_TRUE(config->convert(img, "sRGB - Texture", "srgb").is_ok());
    EXPECT_EQ(img.at(0, 0, 0), 0.5f);
}

TEST(colour, OnlyColourChannelsAreConverted) {
    Image img({{"R", PixelType::Half},
               {"G", PixelType::Half},
               {"B", PixelType::Half},
               {"A", PixelType::Half},
               {"Z", PixelType::Float},
               {"P.R", PixelType::Float},
               {"P.G", PixelType::Float},
               {"P.B", PixelType::Float},
               {"N.x", PixelType::Float},
               {"N.y", PixelType::Float},
               {"N.z", PixelType::Float},
               {"Pworld.R", PixelType::Float},
               {"Pworld.G", PixelType::Float},
               {"Pworld.B", PixelType::Float},
               {"diffuse.R", PixelType::Float},
               {"diffuse.G", PixelType::Float},
               {"diffuse.B", PixelType::Float},
               {"spec.r", PixelType::Float},
               {"spec.g", PixelType::Float},
               {"spec.b", PixelType::Float},
               {"albedo.red", PixelType::Float},
               {"albedo.green", PixelType::Float},
               {"albedo.blue", PixelType::Float},
               {"mask.R", PixelType::Float},  // incomplete triple: left alone
               {"id", PixelType::UInt}},
              Roi{-2, -1, 2, 1});
    for (int c = 0; c < img.nchannels(); ++c) {
        if (img.channel(c).type == PixelType::UInt) {
            for (std::size_t i = 0; i < img.npixels(); ++i) img.uplane(c)[i] = 7u;
            continue;
        }
        for (std::size_t i = 0; i < img.npixels(); ++i) img.plane(c)[i] = 0.5f;
    }
    ASSERT_TRUE(ColourConfig::builtin()->convert(img, "sRGB", "linear").is_ok());
    const float lin = float(ref_srgb_to_linear(0.5));
    const std::vector<std::string> converted = {"R",      "G",      "B",      "diffuse.R",  "diffuse.G",
                                                "diffuse.B", "spec.r", "spec.g", "spec.b", "albedo.red",
                                                "albedo.green", "albedo.blue"};
    for (int c = 0; c < img.nchannels(); ++c) {
        const std::string& name = img.channel(c).name;
        const bool conv = std::find(converted.begin(), converted.end(), name) != converted.end();
        for (std::size_t i = 0; i < img.npixels(); ++i) {
            if (img.channel(c).type == PixelType::UInt) {
                EXPECT_EQ(img.uplane(c)[i], 7u);
                continue;
            }
            EXPECT_NEAR(img.plane(c)[i], conv ? lin : 0.5f, 1e-6) << name;
        }
    }
    EXPECT_EQ(io::colour_channels(img.channels()).size(), 4u);
    EXPECT_TRUE(io::is_data_layer("P"));
    EXPECT_TRUE(io::is_data_layer("left.Pworld"));
    EXPECT_FALSE(io::is_data_layer("diffuse"));
}

TEST(colour, DeepSamplesAreConverted) {
    DeepImage deep({{"R", PixelType::Half}, {"G", PixelType::Half}, {"B", PixelType::Half}, {"A", PixelType::Half},
                    {"Z", PixelType::Float}},
                   Roi{0, 0, 2, 1}, Roi{0, 0, 2, 1});
    EXPECT_TRUE(deep.set_sample_counts({2, 1}));
    for (int c = 0; c < 5; ++c)
        for (std::size_t s = 0; s < deep.total_samples(); ++s) deep.samples(c)[s] = 0.25f;
    ASSERT_TRUE(ColourConfig::builtin()->convert(deep, "linear", "sRGB").is_ok());
    for (std::size_t s = 0; s < 3; ++s) {
        EXPECT_NEAR(deep.samples(0)[s], ref_linear_to_srgb(0.25), 1e-6);
        EXPECT_EQ(deep.samples(3)[s], 0.25f);
        EXPECT_EQ(deep.samples(4)[s], 0.25f);
    }
}

TEST(colour, UnknownColourSpaceNamesIt) {
    Image img = rgb_image({0.5f});
    Status s = ColourConfig::builtin()->convert(img, "linear", "NotASpace42");
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("NotASpace42"), std::string::npos) << s.message();
    EXPECT_EQ(img.at(0, 0, 0), 0.5f);  // untouched on error

    s = ColourConfig::builtin()->convert(img, "Bogus-From", "sRGB");
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("Bogus-From"), std::string::npos) << s.message();
}

TEST(colour, OcioConfigFileConvertsAsTheMathSays) {
    gdof::test::ScratchDir dir;
    const std::string path = write_text(dir, "tiny.ocio", kTinyConfig);
    auto loaded = ColourConfig::from_file(path);
    ASSERT_TRUE(loaded.is_ok()) << loaded.message();
    const ColourConfig& config = *loaded.value();
    EXPECT_EQ(config.resolve("linear_alias"), "lin");
    EXPECT_EQ(config.resolve("scene_linear"), "lin");  // role
    EXPECT_EQ(config.resolve("gamma22"), "gamma22");
    EXPECT_EQ(config.resolve("sRGB"), "");
    EXPECT_TRUE(config.is_linear("lin"));
    EXPECT_FALSE(config.is_linear("gamma22"));
    EXPECT_TRUE(config.is_linear("scaled"));  // a matrix away from the reference
    EXPECT_EQ(config.colour_spaces().size(), 3u);
    EXPECT_NE(config.description().find("tiny.ocio"), std::string::npos);

    // gamma22 -> lin: v^2.2
    Image img = rgb_image({0.f, 0.25f, 0.5f, 1.f});
    Image orig = img;
    ASSERT_TRUE(config.convert(img, "gamma22", "lin").is_ok());
    for (int x = 0; x < 4; ++x)
        EXPECT_NEAR(img.at(0, x, 0), std::pow(orig.at(0, x, 0), 2.2), 1e-5) << x;
    // and back
    ASSERT_TRUE(config.convert(img, "lin", "gamma22").is_ok());
    for (int x = 0; x < 4; ++x) EXPECT_NEAR(img.at(2, x, 0), orig.at(2, x, 0), 1e-5) << x;

    // lin -> scaled multiplies R,G,B by 2,3,4; scaled -> gamma22 chains inverse matrix then 1/2.2.
    Image m = rgb_image({0.5f});
    ASSERT_TRUE(config.convert(m, "lin", "scaled").is_ok());
    EXPECT_NEAR(m.at(0, 0, 0), 1.0f, 1e-6);
    EXPECT_NEAR(m.at(1, 0, 0), 1.5f, 1e-6);
    EXPECT_NEAR(m.at(2, 0, 0), 2.0f, 1e-6);
    ASSERT_TRUE(config.convert(m, "scaled", "gamma22").is_ok());
    EXPECT_NEAR(m.at(1, 0, 0), std::pow(0.5, 1 / 2.2), 1e-5);

    // Unknown names in an OCIO config name the space.
    Status s = config.convert(m, "lin", "ACES2065-1");
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find("ACES2065-1"), std::string::npos) << s.message();
}

TEST(colour, OcioConfigIsThreadSafe) {
    gdof::test::ScratchDir dir;
    auto loaded = ColourConfig::from_file(write_text(dir, "tiny.ocio", kTinyConfig));
    ASSERT_TRUE(loaded.is_ok()) << loaded.message();
    auto config = loaded.value();
    Image ref = Image::with_channels({"R", "G", "B"}, Roi{0, 0, 300, 200});
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < ref.npixels(); ++i) ref.plane(c)[i] = float(i % 997) / 996.f;
    Image expected = ref;
    ASSERT_TRUE(config->convert(expected, "gamma22", "scaled").is_ok());
    std::vector<Image> imgs(4, ref);
    std::vector<std::thread> threads;
    std::vector<int> ok(4, 0);
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] { ok[std::size_t(t)] = config->convert(imgs[std::size_t(t)], "gamma22", "scaled").is_ok(); });
    for (auto& th : threads) th.join();
    for (int t = 0; t < 4; ++t) {
        ASSERT_TRUE(ok[std::size_t(t)]);
        for (int c = 0; c < 3; ++c)
            for (std::size_t i = 0; i < ref.npixels(); i += 101)
                ASSERT_EQ(imgs[std::size_t(t)].plane(c)[i], expected.plane(c)[i]);
    }
}

TEST(colour, OcioEnvironmentVariableIsHonoured) {
    gdof::test::ScratchDir dir;
    const std::string path = write_text(dir, "env.ocio", kTinyConfig);
    const char* old = std::getenv("OCIO");
    std::string saved = old ? old : "";
    ::setenv("OCIO", path.c_str(), 1);
    auto env = ColourConfig::from_environment();
    ASSERT_TRUE(env.is_ok()) << env.message();
    EXPECT_EQ(env.value()->resolve("gamma22"), "gamma22");
    EXPECT_NE(env.value()->description().find("env.ocio"), std::string::npos);

    ::setenv("OCIO", dir.file("missing.ocio").c_str(), 1);
    auto bad = ColourConfig::from_environment();
    ASSERT_FALSE(bad.is_ok());
    EXPECT_NE(bad.message().find("missing.ocio"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("OCIO"), std::string::npos) << bad.message();

    ::unsetenv("OCIO");
    auto none = ColourConfig::from_environment();
    ASSERT_TRUE(none.is_ok());
    EXPECT_EQ(none.value()->resolve("srgb"), "sRGB");  // the built-in fallback
    if (old) ::setenv("OCIO", saved.c_str(), 1);
}

TEST(colour, BadConfigPathIsAnErrorNamingTheFile) {
    gdof::test::ScratchDir dir;
    auto missing = ColourConfig::from_file(dir.file("nope/does_not_exist.ocio"));
    ASSERT_FALSE(missing.is_ok());
    EXPECT_NE(missing.message().find("does_not_exist.ocio"), std::string::npos) << missing.message();

    const std::string garbage = write_text(dir, "garbage.ocio", "this: [is not: an ocio config\n\x01\x02");
    auto bad = ColourConfig::from_file(garbage);
    ASSERT_FALSE(bad.is_ok());
    EXPECT_NE(bad.message().find("garbage.ocio"), std::string::npos) << bad.message();

    // Valid YAML, but a colour space refers to a transform that does not exist.
    const std::string broken = write_text(dir, "broken.ocio", std::string(kTinyConfig) +
                                                                  "  - !<ColorSpace>\n    name: x\n"
                                                                  "    to_scene_reference: !<NoSuchTransform> {}\n");
    auto bad2 = ColourConfig::from_file(broken);
    ASSERT_FALSE(bad2.is_ok());
    EXPECT_NE(bad2.message().find("broken.ocio"), std::string::npos) << bad2.message();
}
