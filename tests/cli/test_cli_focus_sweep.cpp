// gdof --depth-from-focus SWEEP [--aligned-stack PATTERN]: a sweep given as
// a frame pattern or a manifest; its depth against the ray tracer's; the
// aligned stack and its manifest; a generalized depth of field composited
// from it; bad sweeps refused with nothing written.
#include <cmath>
#include <cstdio>
#include <limits>

#include "../unit/focus_sweep/sweep_test_helpers.h"
#include "cli_test_helpers.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "test_support.h"

using namespace gdof::test;

namespace {

bool built_without_embree(const CommandResult& r) { return contains(r.output, "without Embree"); }

// The analytic sweep's frames as EXRs: dir/f.0001.exr ...
void write_sweep(const sweep_test::Sweep& s, const std::string& dir) {
    for (std::size_t k = 0; k < s.focus.size(); ++k) {
        gdof::ImageSet set;
        set.parts.push_back(s.frame(k));
        char name[32];
        std::snprintf(name, sizeof name, "/f.%04d.exr", int(k) + 1);
        ASSERT_TRUE(gdof::io::write_image(dir + name, set));
    }
}

float channel_at(const gdof::Image& img, const std::string& name, int x, int y) {
    const int c = img.channel_index(name);
    EXPECT_GE(c, 0) << name;
    return c < 0 ? NAN : img.at(c, x, y);
}

}  // namespace

// A pattern: the depth is the frame index; the flat strip is a filled hole.
TEST(cli_focus_sweep, pattern_gives_the_frame_index_as_depth) {
    ScratchDir dir;
    const auto s = sweep_test::make_sweep(5);
    write_sweep(s, dir.path().string());
    auto r = run_gdof("--stats --depth-from-focus " + quote(dir.file("f.####.exr")) + " -o " + quote(dir.file("d.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "align: 5 frames to frame 3")) << r.output;
    EXPECT_TRUE(contains(r.output, "depth is the frame index")) << r.output;
    auto set = gdof::io::read_image(dir.file("d.exr"));
    ASSERT_TRUE(set) << set.message();
    const gdof::Image& p = set->flat(0);
    EXPECT_EQ(p.metadata.get_string("gdof:depthUnits").value_or(""), "sweep frame index");
    // The strip at 2 m, in the middle of the frame: focus index from the sweep's dioptres.
    const double d0 = 1.0 / s.focus.front(), d1 = 1.0 / s.focus.back();
    const double want = 1.0 + (d0 - 1.0 / 2.0) / (d0 - d1) * 4.0;
    const int x = int(2.5 * s.width / 6.0), y = s.height / 2;
    EXPECT_NEAR(channel_at(p, "Z", x, y), want, 0.2);
    EXPECT_EQ(channel_at(p, "Z", x, y), channel_at(p, "focus.index", x, y));
}

// A pattern with --focus-distances: Z in metres; the aligned stack's limits
// halfway to the neighbours in dioptres; method 2 with a plane of focus at
// 2 m takes the 2 m strip from a frame whose limits reach it.
TEST(cli_focus_sweep, focus_distances_give_a_pattern_metric_depth_and_limits) {
    ScratchDir dir;
    const auto s = sweep_test::make_sweep(5);  // focused at 0.9, 1.14, 1.57, 2.48, 6 m
    write_sweep(s, dir.path().string());
    std::string list;
    for (double d : s.focus) {
        char b[32];
        std::snprintf(b, sizeof b, "%.17g", d);
        list += (list.empty() ? "" : ",") + std::string(b);
    }
    auto r = run_gdof("--focus-distances " + list + " --aligned-stack " + quote(dir.file("al/ref.####.exr")) +
                      " --depth-from-focus " + quote(dir.file("f.####.exr")) + " -o " + quote(dir.file("d.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto plate = gdof::io::read_image(dir.file("d.exr"));
    ASSERT_TRUE(plate);
    const gdof::Image& p = plate->flat(0);
    EXPECT_EQ(p.metadata.get_string("gdof:depthUnits").value_or(""), "focus distance");
    const int x2 = int(2.5 * s.width / 6.0), y = s.height / 2;  // the strip at 2 m
    EXPECT_NEAR(1.0 / channel_at(p, "Z", x2, y), 0.5, 0.03);
    auto m = gdof::parse_stack_manifest(read_text(dir.file("al/manifest.json")), dir.file("al"));
    ASSERT_TRUE(m) << m.message();
    ASSERT_EQ(m->references.size(), 5u);
    for (std::size_t k = 0; k < 5; ++k) {
        const auto& ref = m->references[k];
        EXPECT_DOUBLE_EQ(ref.focus_distance, s.focus[k]);
        const double d = 1.0 / s.focus[k];
        if (k > 0) EXPECT_NEAR(1.0 / ref.near, 0.5 * (d + 1.0 / s.focus[k - 1]), 1e-9);
        if (k + 1 < 5) EXPECT_NEAR(1.0 / ref.far, 0.5 * (d + 1.0 / s.focus[k + 1]), 1e-9);
    }
    // The ends extend as far beyond as halfway to the neighbour: 6 m's far limit at 1/6 - (1/2.48 - 1/6) / 2 dioptres.
    EXPECT_NEAR(1.0 / m->references[4].far, 1.5 / s.focus[4] - 0.5 / s.focus[3], 1e-9);
    write_text(dir.file("plane.json"),
               R"({"blurfield": {"kind": "focal_planes", "depths": [2.0], "max_blur": 8, "slope": 8}})");
    r = run_gdof(quote(dir.file("d.exr")) + " --focal-length-mm 35 --blurfield " + quote(dir.file("plane.json")) +
                 " --composite " + quote(dir.file("al/manifest.json")) + " --aovs -o " + quote(dir.file("c.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The 2 m strip comes whole from one of the two references whose limits
    // meet at 1.92 m (by the paper's deviation, the one ending there), bit for bit.
    auto c = gdof::io::read_image(dir.file("c.exr"));
    ASSERT_TRUE(c);
    const float picked = channel_at(c->flat(0), "stack.index", x2, y);
    ASSERT_TRUE(picked == 2.0f || picked == 3.0f) << picked;
    auto ref = gdof::io::read_image(m->references[std::size_t(picked)].path);
    ASSERT_TRUE(ref);
    for (int yy = 40; yy < 140; yy += 7)
        for (int xx = x2 - 8; xx <= x2 + 8; xx += 4) {
            ASSERT_EQ(channel_at(c->flat(0), "stack.index", xx, yy), picked) << xx << "," << yy;
            ASSERT_EQ(channel_at(c->flat(0), "G", xx, yy), channel_at(ref->flat(0), "G", xx, yy)) << xx << "," << yy;
        }
    // A count that does not match the frames, and a manifest given focus twice.
    r = run_gdof("--focus-distances 1,2 --depth-from-focus " + quote(dir.file("f.####.exr")) + " -o " + quote(dir.file("e.exr")));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "2 distances for the 5 frames")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("e.exr")));
    r = run_gdof("--focus-distances 1,2,3,4,5 --depth-from-focus " + quote(dir.file("al/manifest.json")) + " -o " +
                 quote(dir.file("e.exr")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "give one or the other")) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("e.exr")));
}

// A ray-traced focus stack (the generated scene at f/0.4, eight focus
// distances): where the sweep measures a depth (confidence > 0), it is the
// ray tracer's Z to a fraction of the step between frames. The aligned
// stack's manifest keeps each reference's lens, and method 2 composites a
// generalized depth of field from it with the plate as its depth.
TEST(cli_focus_sweep, rendered_sweep_depth_matches_the_ray_tracer) {
    ScratchDir dir;
    const std::string src = std::string(GDOF_SOURCE_DIR) + "/examples/render/";
    for (const char* f : {"generated.obj", "generated.mtl"}) fs::copy_file(src + f, dir.file(f));
    std::string scene = read_text(src + "generated.json");
    const auto at = scene.find("[640, 360]");
    ASSERT_NE(at, std::string::npos);
    scene.replace(at, 10, "[320, 180]");
    write_text(dir.file("scene.json"), scene);
    write_text(dir.file("stack.json"), R"({"focus_range": {"near": 3, "far": 14, "count": 8}, "f_numbers": [0.4]})");
    auto r = run_gdof("--render " + quote(dir.file("scene.json")) + " --spp 24 --stack " + quote(dir.file("stack.json")) +
                      " -o " + quote(dir.file("st/ref.####.exr")));
    if (built_without_embree(r)) GDOF_SKIP_OR_FAIL(r.output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--render " + quote(dir.file("scene.json")) + " --pinhole --spp 4 --aovs=Z -o " + quote(dir.file("pin.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof("--stats --aligned-stack " + quote(dir.file("al/ref.####.exr")) + " --depth-from-focus " +
                 quote(dir.file("st/manifest.json")) + " -o " + quote(dir.file("d.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;

    auto plate = gdof::io::read_image(dir.file("d.exr"));
    auto pin = gdof::io::read_image(dir.file("pin.exr"));
    ASSERT_TRUE(plate && pin);
    const gdof::Image& p = plate->flat(0);
    const gdof::Image& t = pin->flat(0);
    EXPECT_EQ(p.metadata.get_string("gdof:depthUnits").value_or(""), "focus distance");
    const double step = (1.0 / 3.0 - 1.0 / 14.0) / 7.0;  // dioptres between frames
    std::vector<double> err;
    for (int y = 0; y < 180; ++y)
        for (int x = 0; x < 320; ++x) {
            const float zt = channel_at(t, "Z", x, y);
            if (!(zt < 1e6f) || channel_at(p, "focus.confidence", x, y) <= 0) continue;
            err.push_back(std::abs(1.0 / channel_at(p, "Z", x, y) - 1.0 / zt) / step);
        }
    ASSERT_GT(err.size(), std::size_t(320 * 180 / 20)) << "the sweep measured too few pixels";
    std::sort(err.begin(), err.end());
    const double median = err[err.size() / 2], p80 = err[err.size() * 8 / 10];
    std::printf("[ measured ] %zu pixels measured, error in frame steps: median %.3f, 80th percentile %.3f\n", err.size(),
                median, p80);
    EXPECT_LT(median, 0.25);
    EXPECT_LT(p80, 0.5);

    // The aligned stack: eight files and the input's lens per reference.
    auto in = gdof::parse_stack_manifest(read_text(dir.file("st/manifest.json")), dir.file("st"));
    auto out = gdof::parse_stack_manifest(read_text(dir.file("al/manifest.json")), dir.file("al"));
    ASSERT_TRUE(in && out) << out.message();
    ASSERT_EQ(out->references.size(), 8u);
    for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_TRUE(fs::exists(out->references[k].path));
        EXPECT_EQ(out->references[k].focus_distance, in->references[k].focus_distance);
        EXPECT_EQ(out->references[k].near, in->references[k].near);
    }
    // Method 2 from the aligned sweep, the plate supplying depth and camera:
    // a thin lens focused on the nearest reference's distance is that reference.
    r = run_gdof(quote(dir.file("d.exr")) + " --focus-distance 3 --composite " + quote(dir.file("al/manifest.json")) +
                 " -o " + quote(dir.file("c.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto c = gdof::io::read_image(dir.file("c.exr"));
    auto ref = gdof::io::read_image(out->references[0].path);
    ASSERT_TRUE(c && ref);
    double worst = 0;
    for (const char* ch : {"R", "G", "B", "A"})
        for (int y = 0; y < 180; ++y)
            for (int x = 0; x < 320; ++x)
                worst = std::max(worst, double(std::abs(channel_at(c->flat(0), ch, x, y) - channel_at(ref->flat(0), ch, x, y))));
    EXPECT_LT(worst, 1e-6);
}

// Each bad sweep: a clear message naming the culprit, a non-zero exit, no output.
TEST(cli_focus_sweep, bad_sweeps_write_nothing) {
    ScratchDir dir;
    const auto s = sweep_test::make_sweep(3);
    write_sweep(s, dir.path().string());
    const std::string out = quote(dir.file("o.exr"));
    auto expect_refused = [&](const std::string& args, int code, const std::string& says) {
        auto r = run_gdof(args + " -o " + out);
        EXPECT_EQ(r.exit_code, code) << args << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, says)) << args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(dir.file("o.exr"))) << args;
        EXPECT_FALSE(fs::exists(dir.file("al"))) << args;
    };
    expect_refused("--depth-from-focus " + quote(dir.file("f.0001.exr")), 2, "give a frame pattern");
    expect_refused("--depth-from-focus " + quote(dir.file("g.####.exr")), 1, "g.####.exr");
    expect_refused("--aligned-stack " + quote(dir.file("al/r.####.exr")) + " " + quote(dir.file("f.0001.exr")), 2,
                   "no --depth-from-focus follows it");
    expect_refused("--dff-min-peak-ratio 0.5 --depth-from-focus " + quote(dir.file("f.####.exr")), 1, "min_peak_ratio");
    expect_refused("--aligned-stack " + quote(dir.file("al/one.exr")) + " --depth-from-focus " + quote(dir.file("f.####.exr")),
                   2, "give a frame pattern");
    // One frame of another size, named.
    {
        gdof::ImageSet small;
        small.parts.push_back(gdof::Image::with_channels({"R", "G", "B"}, gdof::Roi{0, 0, 50, 40}));
        ASSERT_TRUE(gdof::io::write_image(dir.file("f.0004.exr"), small));
        expect_refused("--aligned-stack " + quote(dir.file("al/r.####.exr")) + " --depth-from-focus " +
                           quote(dir.file("f.####.exr")),
                       1, "f.0004.exr");
        fs::remove(dir.file("f.0004.exr"));
    }
    // A NaN pixel, named with its frame.
    {
        gdof::Image bad = s.frame(1);
        bad.at(0, 12, 7) = NAN;
        gdof::ImageSet set;
        set.parts.push_back(std::move(bad));
        ASSERT_TRUE(gdof::io::write_image(dir.file("f.0002.exr"), set));
        expect_refused("--aligned-stack " + quote(dir.file("al/r.####.exr")) + " --depth-from-focus " +
                           quote(dir.file("f.####.exr")),
                       1, "frame 2");
    }
    // A single frame is no sweep.
    fs::create_directories(dir.file("one"));
    fs::copy_file(dir.file("f.0001.exr"), dir.file("one/f.0001.exr"));
    expect_refused("--depth-from-focus " + quote(dir.file("one/f.####.exr")), 1, "at least 2 frames");
}

// The real handheld sweep in one command.
TEST(cli_focus_sweep, real_keyboard_sweep_in_one_command) {
    GDOF_REQUIRE_SHARED(first, "focalstack/keyboard/00.jpg");
    ScratchDir dir;
    const std::string pattern = fs::path(first).parent_path().string() + "/##.jpg";
    auto r = run_gdof("--stats --depth-from-focus " + quote(pattern) + " -o " + quote(dir.file("k.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "align: 32 frames to frame 16")) << r.output;
    auto set = gdof::io::read_image(dir.file("k.exr"));
    ASSERT_TRUE(set) << set.message();
    for (const char* c : {"R", "G", "B", "A", "Z", "focus.index", "focus.confidence"})
        EXPECT_GE(set->flat(0).channel_index(c), 0) << c;
}
