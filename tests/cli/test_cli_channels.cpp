// --ch and --mulc end to end: a PNG preview of a data channel.
#include "cli_test_helpers.h"

using namespace gdof::test;

TEST(cli_channels, ChannelSelectionScaleAndPreview) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr"), out = dir.file("out.exr"), png = dir.file("blur.png");
    write_exr(in, 4, 2, {"R", "G", "B", "A", "blur"}, [](int x, int y, int c) { return c == 4 ? float(x * 5) : 0.25f; });
    auto r = run_gdof(quote(in) + " --ch Y=blur,A=1 --mulc 0.1 -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec spec;
    auto px = read_pixels(out, &spec);
    ASSERT_EQ(spec.nchannels, 2);
    EXPECT_EQ(spec.channelnames[0], "Y");
    EXPECT_FLOAT_EQ(px[(1 * 4 + 3) * 2 + 0], 1.5f);  // 15 * 0.1
    EXPECT_FLOAT_EQ(px[(1 * 4 + 3) * 2 + 1], 0.1f);  // A=1 scaled too
    // A linear-encoded PNG preview: values map straight to 8 bits.
    r = run_gdof(quote(in) + " --ch R=blur,G=blur,B=blur --mulc 0.05 --ocolorspace linear -o " + quote(png));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto p = read_pixels(png, &spec);
    ASSERT_EQ(spec.nchannels, 3);
    EXPECT_NEAR(p[(0 * 4 + 2) * 3], 0.5f, 1.0f / 255);  // 10 * 0.05
}

TEST(cli_channels, MissingChannelIsNamed) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr"), out = dir.file("out.exr");
    write_exr(in, 2, 2, {"R", "G", "B"}, [](int, int, int) { return 1.f; });
    auto r = run_gdof(quote(in) + " --ch R,Zdepth -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "Zdepth")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    r = run_gdof(quote(in) + " --mulc x -o " + quote(out));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(contains(r.output, "--mulc")) << r.output;
    EXPECT_FALSE(fs::exists(out));
}
