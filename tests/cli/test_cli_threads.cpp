// The CLI's threaded operations give the same frame whatever the number of
// threads: --diffuse, --bokeh and --vibrate on a small plate with depth, and
// --render of a small scene, each run with --threads 1 and --threads 4 (more
// threads than this machine's cores, so work is interleaved). Under
// ThreadSanitizer (`.ci/sanitize tsan`) the 4-thread runs are the race check
// of the CLI's paths.
#include <cstring>

#include "cli_test_helpers.h"

using namespace gdof::test;

namespace {

// The frame `args` makes with `threads` threads (the test fails on an error).
std::vector<float> frame_with_threads(const ScratchDir& dir, const std::string& args, int threads) {
    const std::string out = dir.file("out_" + std::to_string(threads) + ".exr");
    auto r = run_gdof(args + " --threads " + std::to_string(threads) + " -o " + quote(out));
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    return r.exit_code == 0 ? read_pixels(out) : std::vector<float>();
}

// A plate with bright specks and a near square in front of a far wall.
std::string write_plate(const ScratchDir& dir) {
    const std::string plate = dir.file("plate.exr");
    write_exr(plate, 48, 36, {"R", "G", "B", "A", "Z"}, [](int x, int y, int c) {
        if (c == 3) return 1.0f;
        if (c == 4) return x > 16 && x < 32 && y > 10 && y < 26 ? 1.5f : 9.0f;
        return (x * 5 + y * 3) % 17 == 0 ? 20.0f : 0.1f + 0.1f * float(c);
    });
    return quote(plate) + " --focal-length-mm 50 --sensor-width-mm 36 --f-number 1.4 --focus-distance 9";
}

void expect_same_with_1_and_4_threads(const ScratchDir& dir, const std::string& args) {
    const std::vector<float> one = frame_with_threads(dir, args, 1);
    const std::vector<float> four = frame_with_threads(dir, args, 4);
    ASSERT_FALSE(one.empty());
    // Bit for bit (NaN channels too: a renderer's AOVs hold NaN where no surface is).
    ASSERT_EQ(one.size(), four.size()) << args;
    EXPECT_EQ(std::memcmp(one.data(), four.data(), one.size() * sizeof(float)), 0) << args;
}

}  // namespace

TEST(cli_threads, diffuse_is_the_same_with_1_and_4_threads) {
    ScratchDir dir;
    expect_same_with_1_and_4_threads(dir, write_plate(dir) + " --diffuse");
}

TEST(cli_threads, bokeh_is_the_same_with_1_and_4_threads) {
    ScratchDir dir;
    expect_same_with_1_and_4_threads(dir, write_plate(dir) + " --aperture polygon:6 --bokeh");
}

TEST(cli_threads, vibrate_is_the_same_with_1_and_4_threads) {
    ScratchDir dir;
    expect_same_with_1_and_4_threads(dir, write_plate(dir) + " --psf-samples 16 --vibrate");
}

TEST(cli_threads, render_is_the_same_with_1_and_4_threads) {
    ScratchDir dir;
    write_text(dir.file("quad.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write_text(dir.file("scene.json"), R"({
  "camera": {"position": [0.3, 0.2, 4], "look_at": [0, 0, 0], "focal_length_mm": 35, "sensor_width_mm": 36,
             "resolution": [40, 30], "f_number": 2, "focus_distance": 2},
  "lights": [{"type": "point", "position": [2, 3, 4], "intensity": [5, 5, 5]}],
  "meshes": [{"file": "quad.obj"}]
})");
    const std::string args = "--render " + quote(dir.file("scene.json")) + " --spp 8 --adaptive-threshold 0";
    auto probe = run_gdof(args + " --threads 1 -o " + quote(dir.file("probe.exr")));
    if (contains(probe.output, "without Embree")) GDOF_SKIP_OR_FAIL(probe.output);
    expect_same_with_1_and_4_threads(dir, args);
}
