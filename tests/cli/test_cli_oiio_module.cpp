// OpenImageIO is loaded only for a file in another format than EXR (the
// module gdof_oiio.so, lib/io/src/oiio): what the dynamic loader reports
// (LD_DEBUG=files), the same picture either way, and a clear error without
// output when the module cannot load.
#include "cli/cli_test_helpers.h"

using namespace gdof::test;

namespace {

void write_rgba(const std::string& path) {
    write_exr(path, 16, 8, {"R", "G", "B", "A"}, [](int x, int y, int c) { return c == 3 ? 1.0f : float(x + y + c) / 32.0f; });
}

// What the dynamic loader opened while the CLI ran `args`.
CommandResult traced(const std::string& args, const std::string& env = "") {
    return run_command(env + " LD_DEBUG=files '" + std::string(GDOF_CLI_PATH) + "' " + args);
}

bool loaded(const CommandResult& r, const std::string& lib) {
    return contains(r.output, "file=" + lib) || contains(r.output, "/" + lib);
}

// A sanitizer build links the module at start (lib/CMakeLists.txt: clang
// 14's LeakSanitizer and the TLS of dlopen'ed libraries).
bool linked_at_start() {
    return contains(run_command("ldd '" + std::string(GDOF_CLI_PATH) + "'").output, "gdof_oiio.so");
}

}  // namespace

TEST(cli_oiio_module, TheCliDoesNotLinkOpenImageIO) {
    if (linked_at_start()) GTEST_SKIP() << "a sanitizer build links gdof_oiio.so at start";
    const CommandResult ldd = run_command("ldd '" + std::string(GDOF_CLI_PATH) + "'");
    ASSERT_EQ(ldd.exit_code, 0) << ldd.output;
    EXPECT_FALSE(contains(ldd.output, "libOpenImageIO")) << ldd.output;
    EXPECT_TRUE(contains(ldd.output, "libOpenEXR")) << "EXR is read directly\n" << ldd.output;
}

TEST(cli_oiio_module, OpenImageIOLoadsOnlyForAnotherFormat) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr");
    write_rgba(in);
    const CommandResult exr = traced(quote(in) + " -o " + quote(dir.file("out.exr")));
    ASSERT_EQ(exr.exit_code, 0) << exr.output;
    if (!linked_at_start()) {
        EXPECT_FALSE(loaded(exr, "gdof_oiio.so")) << exr.output;
        EXPECT_FALSE(loaded(exr, "libOpenImageIO")) << exr.output;
    }

    const CommandResult png = traced(quote(in) + " -o " + quote(dir.file("out.png")));
    ASSERT_EQ(png.exit_code, 0) << png.output;
    EXPECT_TRUE(loaded(png, "gdof_oiio.so")) << png.output;
    EXPECT_TRUE(loaded(png, "libOpenImageIO")) << png.output;

    // The PNG holds the picture: read back (through the module) it equals the
    // EXR to 8 bits; and read by OIIO directly it is the sRGB encoding.
    const CommandResult back = run_gdof(quote(dir.file("out.png")) + " -o " + quote(dir.file("back.exr")));
    ASSERT_EQ(back.exit_code, 0) << back.output;
    const Pixels a = read_image_pixels(dir.file("out.exr")), b = read_image_pixels(dir.file("back.exr"));
    ASSERT_EQ(a.values.size(), b.values.size());
    double worst = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) worst = std::max(worst, double(std::abs(a.values[i] - b.values[i])));
    EXPECT_LT(worst, 0.01) << "an 8-bit sRGB round trip of values up to 0.8";
}

TEST(cli_oiio_module, AModuleThatCannotLoadIsAnErrorWithoutOutput) {
    ScratchDir dir;
    const std::string in = dir.file("in.exr");
    write_rgba(in);
    // Not there: the error names the module, where it looked and the input.
    const std::string missing = dir.file("nowhere/gdof_oiio.so");
    CommandResult r = run_command("GDOF_OIIO_MODULE=" + quote(missing) + " '" + std::string(GDOF_CLI_PATH) + "' " +
                                  quote(in) + " -o " + quote(dir.file("out.png")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "gdof_oiio.so")) << r.output;
    EXPECT_TRUE(contains(r.output, missing + "' (GDOF_OIIO_MODULE): not found")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.png")));
    // Not a shared object: the loader's reason.
    write_text(dir.file("fake.so"), "not a library");
    r = run_command("GDOF_OIIO_MODULE=" + quote(dir.file("fake.so")) + " '" + std::string(GDOF_CLI_PATH) + "' " +
                    quote(in) + " -o " + quote(dir.file("out.png")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "fake.so")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.png")));
    // Reading a PNG fails the same way, naming the file read.
    {
        OIIO::ImageBuf png(OIIO::ImageSpec(4, 4, 3, OIIO::TypeUInt8));
        ASSERT_TRUE(png.write(dir.file("in.png")));
    }
    r = run_command("GDOF_OIIO_MODULE=" + quote(missing) + " '" + std::string(GDOF_CLI_PATH) + "' " +
                    quote(dir.file("in.png")) + " -o " + quote(dir.file("x.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "in.png': gdof's OpenImageIO module")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("x.exr")));
    // EXR in and out never needs it.
    r = run_command("GDOF_OIIO_MODULE=" + quote(missing) + " '" + std::string(GDOF_CLI_PATH) + "' " + quote(in) +
                    " -o " + quote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir.file("out.exr")));
}
