// gdof CLI: help, version, usage errors, input errors, round trip.
#include <algorithm>
#include <sstream>

#include "cli/cli_test_helpers.h"
#include "cli.h"
#include "gdof/io/image_io.h"

using namespace gdof::test;

namespace {

void write_rgba(const std::string& path) {
    write_exr(path, 8, 6, {"R", "G", "B", "A", "Z"}, [](int x, int y, int c) { return float(x + 10 * y + 100 * c); });
}

}  // namespace

// Generated from the command table: every row has a line of its own in
// --help (all its names, its arguments, its help text).
TEST(cli_basics, HelpListsEveryCommand) {
    auto r = run_gdof("--help");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "usage: gdof"));
    EXPECT_EQ(r.output, gdof::cli::usage_text()) << "the binary prints the table the library holds";
    for (const gdof::cli::Command& c : gdof::cli::command_table()) {
        std::string head = "\n  " + c.names.front();
        for (std::size_t k = 1; k < c.names.size(); ++k) head += ", " + c.names[k];
        if (!c.args.empty()) head += " " + c.args;
        std::size_t at = r.output.find(head + " ");
        if (at == std::string::npos) at = r.output.find(head + "\n");  // a long head: help on the next line
        ASSERT_NE(at, std::string::npos) << head << "\n" << r.output;
        // The row runs to the next row or section; its help is wrapped, so compare words.
        const std::size_t end = std::min(r.output.find("\n  -", at + 1), r.output.find("\n\n", at + 1));
        std::istringstream words(r.output.substr(at + head.size(), end - at - head.size()));
        std::string word, row;
        while (words >> word) row += (row.empty() ? "" : " ") + word;
        EXPECT_EQ(row, c.help) << c.names.front();
    }
    EXPECT_EQ(run_gdof("-h").output, r.output);
}

TEST(cli_basics, Version) {
    auto r = run_gdof("--version");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.output.rfind("gdof ", 0), 0u) << r.output;
    EXPECT_TRUE(contains(r.output, GDOF_VERSION_STRING)) << r.output;
}

TEST(cli_basics, NoArgumentsIsShortUsageExit2) {
    auto r = run_gdof("");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(contains(r.output, "usage: gdof")) << r.output;
}

TEST(cli_basics, UnknownFlagIsUsageErrorNamingIt) {
    ScratchDir dir;
    auto r = run_gdof("--frobnicate " + quote(dir.file("a.exr")) + " -o " + quote(dir.file("b.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof: error:")) << r.output;
    EXPECT_TRUE(contains(r.output, "--frobnicate")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("b.exr")));
}

TEST(cli_basics, MissingArgumentIsUsageError) {
    ScratchDir dir;
    write_rgba(dir.file("in.exr"));
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "-o")) << r.output;
    EXPECT_TRUE(contains(r.output, "missing argument")) << r.output;

    r = run_gdof(quote(dir.file("in.exr")) + " --colorconvert linear");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--colorconvert")) << r.output;

    r = run_gdof("--threads abc " + quote(dir.file("in.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "--threads")) << r.output;

    r = run_gdof(quote(dir.file("in.exr")) + " -d int8 -o " + quote(dir.file("o.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "int8")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("o.exr")));
}

TEST(cli_basics, OperationWithoutImageIsUsageError) {
    ScratchDir dir;
    auto r = run_gdof("-o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "-o")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

TEST(cli_basics, MissingInputNamesItAndWritesNothing) {
    ScratchDir dir;
    const std::string in = dir.file("does_not_exist.exr"), out = dir.file("out.exr");
    auto r = run_gdof(quote(in) + " -o " + quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof: error:")) << r.output;
    EXPECT_TRUE(contains(r.output, "does_not_exist.exr")) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(list_dir(dir.path().string()).size(), 0u);
}

TEST(cli_basics, CorruptInputNamesItAndWritesNothing) {
    ScratchDir dir;
    write_rgba(dir.file("good.exr"));
    const std::string bytes = read_text(dir.file("good.exr"));
    // Truncated: header and part of the pixel data.
    {
        std::ofstream(dir.file("truncated.exr"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    // Garbage with an EXR extension, an empty file, a PNG cut after its header,
    // an EXR magic number followed by garbage.
    write_text(dir.file("garbage.exr"), "this is not an image file at all");
    write_text(dir.file("empty.exr"), "");
    write_text(dir.file("header_only.png"), std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
    write_text(dir.file("magic.exr"), std::string("\x76\x2f\x31\x01\x02\0\0\0garbage\0\xff\xff", 18));
    for (const char* name : {"truncated.exr", "garbage.exr", "empty.exr", "header_only.png", "magic.exr"}) {
        const std::string out = dir.file(std::string("out_") + name);
        auto r = run_gdof(quote(dir.file(name)) + " -o " + quote(out));
        EXPECT_NE(r.exit_code, 0) << name << "\n" << r.output;
        EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
        EXPECT_TRUE(contains(r.output, name)) << r.output;
        EXPECT_TRUE(contains(r.output, "gdof: error:")) << r.output;
        EXPECT_FALSE(fs::exists(out)) << out;
    }
}

TEST(cli_basics, RoundTripKeepsChannelsWindowsAttributes) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr"), out = dir.file("out.exr");
    write_exr(in, 6, 4, {"R", "G", "B", "A", "diffuse.R", "diffuse.G", "diffuse.B", "Z"},
              [](int x, int y, int c) { return float(x) * 0.25f + float(y) + float(c) * 10.f; },
              [](OIIO::ImageSpec& s) {
                  s.x = -2;
                  s.y = 3;
                  s.full_x = 0;
                  s.full_y = 0;
                  s.full_width = 10;
                  s.full_height = 8;
                  s.attribute("focalLength", 35.0f);
                  s.attribute("gdofTestNote", "hello");
                  const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1};
                  s.attribute("worldToCamera", OIIO::TypeMatrix, m);
              });
    auto r = run_gdof(quote(in) + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec a, b;
    auto pa = read_pixels(in, &a);
    auto pb = read_pixels(out, &b);
    EXPECT_EQ(b.x, -2);
    EXPECT_EQ(b.y, 3);
    EXPECT_EQ(b.width, 6);
    EXPECT_EQ(b.full_width, 10);
    EXPECT_EQ(b.full_height, 8);
    EXPECT_EQ(a.channelnames, b.channelnames);
    EXPECT_NEAR(b.get_float_attribute("focalLength"), 35.0f, 1e-6);
    EXPECT_EQ(b.get_string_attribute("gdofTestNote"), "hello");
    const OIIO::ParamValue* m = b.find_attribute("worldToCamera", OIIO::TypeMatrix);
    ASSERT_NE(m, nullptr);
    EXPECT_FLOAT_EQ(static_cast<const float*>(m->data())[13], 2.0f);
    ASSERT_EQ(pa.size(), pb.size());
    // Channel order may be canonicalised by the writer: compare by name.
    for (int c = 0; c < a.nchannels; ++c) {
        int cb = b.channelindex(a.channelnames[std::size_t(c)]);
        ASSERT_GE(cb, 0);
        for (std::size_t p = 0; p < std::size_t(a.width * a.height); ++p)
            ASSERT_EQ(pa[p * std::size_t(a.nchannels) + std::size_t(c)], pb[p * std::size_t(b.nchannels) + std::size_t(cb)]);
    }
}

TEST(cli_basics, PixelTypeAndCompressionFlags) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr"), out = dir.file("out.exr");
    write_rgba(in);
    auto r = run_gdof(quote(in) + " -d half --compression piz -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageSpec s;
    read_pixels(out, &s);
    EXPECT_EQ(s.format, OIIO::TypeDesc::HALF);
    EXPECT_EQ(s.get_string_attribute("compression"), "piz");
}

TEST(cli_basics, InfoDescribesFiles) {
    ScratchDir dir;
    write_rgba(dir.file("a.exr"));
    write_rgba(dir.file("b.exr"));
    auto r = run_gdof("--info " + quote(dir.file("a.exr")) + " " + quote(dir.file("b.exr")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "a.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "b.exr")) << r.output;
    // Top-of-stack form.
    r = run_gdof(quote(dir.file("a.exr")) + " --info -v");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "a.exr")) << r.output;
}

TEST(cli_basics, StatsPrintsStages) {
    ScratchDir dir;
    write_rgba(dir.file("a.exr"));
    auto r = run_gdof("--stats " + quote(dir.file("a.exr")) + " -o " + quote(dir.file("b.exr")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "read")) << r.output;
    EXPECT_TRUE(contains(r.output, "write")) << r.output;
    EXPECT_TRUE(contains(r.output, "total")) << r.output;
}

TEST(cli_basics, RoundTripKeepsParts) {
    ScratchDir dir;
    gdof::ImageSet set;
    gdof::Image a = gdof::Image::with_channels({"R", "G", "B", "A"}, gdof::Roi{0, 0, 4, 4});
    a.name = "beauty";
    a.plane(0)[5] = 0.25f;
    gdof::Image b({{"Z", gdof::PixelType::Float}, {"id", gdof::PixelType::UInt}}, gdof::Roi{-2, -1, 3, 3},
                  gdof::Roi{0, 0, 4, 4});
    b.name = "data";
    b.uplane(1)[3] = 4000000000u;
    b.metadata.set_float("focalLength", 24.0);
    set.parts.push_back(std::move(a));
    set.parts.push_back(std::move(b));
    ASSERT_TRUE(gdof::io::write_image(dir.file("in.exr"), set).is_ok());
    auto r = run_gdof(quote(dir.file("in.exr")) + " -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto back = gdof::io::read_image(dir.file("out.exr"));
    ASSERT_TRUE(back.is_ok()) << back.message();
    ASSERT_EQ(back->size(), 2u);
    EXPECT_EQ(back->flat(0).name, "beauty");
    EXPECT_EQ(back->flat(1).name, "data");
    EXPECT_EQ(back->flat(0).plane(0)[5], 0.25f);
    EXPECT_EQ(back->flat(1).data_window(), (gdof::Roi{-2, -1, 3, 3}));
    const int id = back->flat(1).channel_index("id");
    ASSERT_GE(id, 0);
    EXPECT_EQ(back->flat(1).uplane(id)[3], 4000000000u);
    EXPECT_EQ(back->flat(1).metadata.get_float("focalLength").value_or(0), 24.0);
}

TEST(cli_basics, RealMultipartRoundTrip) {
    GDOF_REQUIRE_SHARED(path, "exr/beachball_multipart.0001.exr");
    ScratchDir dir;
    auto r = run_gdof(quote(path) + " -o " + quote(dir.file("bb.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto in = gdof::io::read_image(path);
    auto out = gdof::io::read_image(dir.file("bb.exr"));
    ASSERT_TRUE(in.is_ok() && out.is_ok());
    ASSERT_EQ(in->size(), out->size());
    for (std::size_t i = 0; i < in->size(); ++i) {
        EXPECT_EQ(in->part_name(i), out->part_name(i));
        EXPECT_EQ(in->flat(i).channels(), out->flat(i).channels());
        EXPECT_EQ(in->flat(i).data_window(), out->flat(i).data_window());
    }
    r = run_gdof("--info " + quote(path));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(contains(r.output, "beachball_multipart")) << r.output;
}
