// "gdof Focal Stack" through the test host against `gdof --composite` on the
// same stack and desired focus: the stack as frames of the Source clip (lens
// table or manifest) or as the manifest's files; near/far from control-point
// parameters, a surfaces file or Near / Far clips; tiles, render scale,
// frames needed, and errors.
#include <set>

#include "gdof/camera.h"
#include "ofx/ofx_test_support.h"

using namespace gdof::test;

namespace {

constexpr int W = 80, H = 48, N = 5;
constexpr OfxPointD kFull{1, 1};
const double kFocus[N] = {1, 1.5, 2.5, 4, 8};

float ref_value(int i, int x, int y, int c) {
    if (c == 3) return 1.0f;
    if (c == 0) return 0.2f * float(i) + 0.005f * float(x);
    if (c == 1) return ((x / 4 + y / 4 + i) % 2) ? 0.8f : 0.3f;
    return 0.01f * float(y);
}

// A clip frame of reference i (bottom row first).
ClipFrame ref_clip(int i) {
    ClipFrame f = ClipFrame::make(W, H, kOfxImageComponentRGBA);
    for (int oy = 0; oy < H; ++oy)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 4; ++c) f.at(x, oy, c) = ref_value(i, x, H - 1 - oy, c);
    return f;
}

const char* kTable = "frame,focus_distance,f_number\n# five focus distances at f/2\n1,1,2\n2,1.5,2\n3,2.5,2\n4,4,2\n5,8,2\n";
const double kNear[9] = {0.9, 1.3, 2.0, 0.9, 1.3, 2.0, 0.9, 1.3, 2.0};
const double kFar[9] = {1.2, 2.0, 4.0, 1.2, 2.0, 6.0, 1.2, 2.0, 9.0};

std::string grid_json(const double* v) {
    std::string s = "[";
    for (int r = 0; r < 3; ++r) {
        s += r ? ",[" : "[";
        for (int c = 0; c < 3; ++c) s += (c ? "," : "") + std::to_string(v[r * 3 + c]);
        s += "]";
    }
    return s + "]";
}

struct Fixture {
    ScratchDir dir;
    Session s{kFocalStackId, W, H};
    std::string manifest, surfaces;
    Fixture() {
        // The stack on disk for the CLI (and the files mode).
        std::string refs;
        for (int i = 0; i < N; ++i) {
            const std::string name = "ref." + std::to_string(i + 1) + ".exr";
            write_exr(dir.file(name), W, H, {"R", "G", "B", "A"}, [i](int x, int y, int c) { return ref_value(i, x, y, c); });
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s{\"file\": \"%s\", \"focus_distance\": %g, \"f_number\": 2}", i ? ", " : "",
                          name.c_str(), kFocus[i]);
            refs += buf;
        }
        manifest = dir.file("manifest.json");
        write_text(manifest, "{\"gdof_stack\": 1, \"coc_px\": 1, \"focal_length_mm\": 100, \"sensor_width_mm\": 36, "
                             "\"width\": 80, \"height\": 48, \"references\": [" + refs + "]}");
        surfaces = dir.file("surfaces.json");
        write_text(surfaces, "{\"gdof_surfaces\": 1, \"near\": {\"grid\": " + grid_json(kNear) + "}, \"far\": {\"grid\": " +
                                 grid_json(kFar) + "}}");
        if (!s.ok()) return;
        Instance& fx = *s.fx;
        for (int i = 0; i < N; ++i) fx.connect("Source", ref_clip(i), i + 1);
        fx.set_string("lens_table", kTable);
        fx.set("focal_length_mm", 100);
        fx.set("sensor_width_mm", 36);
        fx.set("coc_px", 1);
        fx.set_choice("grid", "3x3");
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                fx.set("near_" + std::to_string(r) + std::to_string(c), kNear[r * 3 + c]);
                fx.set("far_" + std::to_string(r) + std::to_string(c), kFar[r * 3 + c]);
            }
    }
    std::string cli(const std::string& args) {
        const std::string out = dir.file("cli_" + std::to_string(++runs) + ".exr");
        auto r = run_gdof("--composite " + quote(manifest) + " " + args + " -o " + quote(out));
        EXPECT_EQ(r.exit_code, 0) << r.output;
        return out;
    }
    int runs = 0;
};

}  // namespace

TEST(ofx_focal_stack, SourceFramesWithLensTableEqualCliComposite) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(r.bounds.x2, W);
    EXPECT_EQ(r.bounds.y2, H);
    const double d = max_diff_to_file(r, f.cli("--surfaces " + quote(f.surfaces)), 4, H);
    std::printf("OFX vs CLI (stack from Source frames, surfaces from parameters): max |diff| = %.3g\n", d);
    EXPECT_EQ(d, 0.0) << "a hard pick copies reference pixels";
    EXPECT_EQ(f.s.host.live_images(), 0);
    // Several references are used: the test exercises the selection.
    std::set<long> refs;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) refs.insert(std::lround((r.at(x, y, 0) - 0.005f * float(x)) / 0.2f));
    EXPECT_GE(refs.size(), 3u);
}

// The Source frames are read in place (views of the host's images, rows
// bottom-up and padded); a straight-alpha RGBA frame is premultiplied first:
// equal, bit for bit, to the CLI on the premultiplied files.
TEST(ofx_focal_stack, StraightAlphaFramesEqualCliOnPremultipliedFiles) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    auto alpha = [](int i, int x, int y) { return 0.25f * float((x + 2 * y + i) % 4 + 1); };
    std::string refs;
    f.s.fx->disconnect("Source");
    for (int i = 0; i < N; ++i) {
        const std::string name = "premult." + std::to_string(i + 1) + ".exr";
        write_exr(f.dir.file(name), W, H, {"R", "G", "B", "A"}, [&](int x, int y, int c) {
            return c == 3 ? alpha(i, x, y) : ref_value(i, x, y, c) * alpha(i, x, y);
        });
        refs += std::string(i ? ", " : "") + "{\"file\": \"" + name + "\", \"focus_distance\": " + std::to_string(kFocus[i]) +
                ", \"f_number\": 2}";
        ClipFrame straight = ref_clip(i);
        straight.premult = kOfxImageUnPreMultiplied;
        for (int oy = 0; oy < H; ++oy)
            for (int x = 0; x < W; ++x) straight.at(x, oy, 3) = alpha(i, x, H - 1 - oy);
        f.s.fx->connect("Source", straight, i + 1);
    }
    const std::string manifest = f.dir.file("premult.json");
    write_text(manifest, "{\"gdof_stack\": 1, \"coc_px\": 1, \"focal_length_mm\": 100, \"sensor_width_mm\": 36, "
                         "\"width\": 80, \"height\": 48, \"references\": [" + refs + "]}");
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    const std::string out = f.dir.file("premult_cli.exr");
    const auto cli = run_gdof("--composite " + quote(manifest) + " --surfaces " + quote(f.surfaces) + " -o " + quote(out));
    ASSERT_EQ(cli.exit_code, 0) << cli.output;
    EXPECT_EQ(max_diff_to_file(r, out, 4, H), 0.0);
    EXPECT_EQ(f.s.host.live_images(), 0);
}

TEST(ofx_focal_stack, RgbSourceFramesGiveRgbEqualToCliComposite) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->disconnect("Source");
    for (int i = 0; i < N; ++i) {
        ClipFrame rgb = ClipFrame::make(W, H, kOfxImageComponentRGB);
        for (int oy = 0; oy < H; ++oy)
            for (int x = 0; x < W; ++x)
                for (int c = 0; c < 3; ++c) rgb.at(x, oy, c) = ref_value(i, x, H - 1 - oy, c);
        f.s.fx->connect("Source", rgb, i + 1);
    }
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(r.ncomp, 3);
    EXPECT_EQ(max_diff_to_file(r, f.cli("--surfaces " + quote(f.surfaces)), 3, H), 0.0);
    EXPECT_FALSE(r.wrote_outside);
}

TEST(ofx_focal_stack, SoftBlendEqualsCliSoft) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_int("soft", 3);
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double d = max_diff_to_file(r, f.cli("--soft 3 --surfaces " + quote(f.surfaces)), 4, H);
    std::printf("OFX vs CLI (soft 3): max |diff| = %.3g\n", d);
    EXPECT_LE(d, 1e-6);
}

TEST(ofx_focal_stack, ManifestFilesEqualCliComposite) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("stack_source", "files");
    f.s.fx->set_string("manifest", f.manifest);
    f.s.fx->set_choice("focus_source", "surfaces_file");
    f.s.fx->set_string("surfaces", f.surfaces);
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(max_diff_to_file(r, f.cli("--surfaces " + quote(f.surfaces)), 4, H), 0.0);
}

TEST(ofx_focal_stack, SourceFramesWithAManifestEqualTheLensTable) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    const Rendered table = f.s.fx->render(1, kFull);
    f.s.fx->set_string("manifest", f.manifest);  // reference i = frame first_frame + i
    f.s.fx->set_int("first_frame", 1);
    const Rendered manifest = f.s.fx->render(1, kFull);
    ASSERT_EQ(manifest.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(max_diff(table, manifest), 0.0);
}

TEST(ofx_focal_stack, NearFarClipsEqualCliMaps) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    // Maps: the left half wants the near references, the right half the far ones.
    auto near = [](int x, int) { return x < W / 2 ? 1.0f : 3.0f; };
    auto far = [](int x, int y) { return x < W / 2 ? 1.3f : 5.0f + 0.05f * float(y); };
    write_exr(f.dir.file("near.exr"), W, H, {"Z"}, [&](int x, int y, int) { return near(x, y); });
    write_exr(f.dir.file("far.exr"), W, H, {"Z"}, [&](int x, int y, int) { return far(x, y); });
    ClipFrame n = ClipFrame::make(W, H, kOfxImageComponentAlpha), fa = ClipFrame::make(W, H, kOfxImageComponentAlpha);
    for (int oy = 0; oy < H; ++oy)
        for (int x = 0; x < W; ++x) {
            n.at(x, oy, 0) = near(x, H - 1 - oy);
            fa.at(x, oy, 0) = far(x, H - 1 - oy);
        }
    f.s.fx->connect("Near", n, 1);
    f.s.fx->connect("Far", fa, 1);
    f.s.fx->set_choice("focus_source", "maps");
    f.s.fx->set_choice("map_channel", "A");
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    const std::string out = f.cli("--near-map " + quote(f.dir.file("near.exr")) + " --far-map " + quote(f.dir.file("far.exr")));
    EXPECT_EQ(max_diff_to_file(r, out, 4, H), 0.0);
}

TEST(ofx_focal_stack, TilesEqualWholeAndFramesNeededListTheStack) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    const Rendered whole = f.s.fx->render(1, kFull);
    const Rendered tiled = f.s.fx->render(1, kFull, quadrants(whole.bounds), true);
    ASSERT_EQ(tiled.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(max_diff(whole, tiled), 0.0);
    EXPECT_FALSE(tiled.wrote_outside);
    std::map<std::string, std::vector<double>> ranges;
    ASSERT_EQ(f.s.fx->frames_needed(1, ranges), kOfxStatOK);
    EXPECT_EQ(ranges["Source"], (std::vector<double>{1, 5}));
    std::map<std::string, OfxRectD> roi;
    ASSERT_EQ(f.s.fx->regions_of_interest(1, kFull, {8, 8, 24, 16}, roi), kOfxStatOK);
    EXPECT_DOUBLE_EQ(roi["Source"].x1, 8) << "a per-pixel pick needs just the region";
    EXPECT_DOUBLE_EQ(roi["Source"].x2, 24);
}

TEST(ofx_focal_stack, OnlyTheChosenFramesAreFetched) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    // Everywhere exactly the interval of reference 2 (focus 2.5 at f/2): only frame 3 is needed.
    gdof::ThinLens lens;
    lens.focal_length_mm = 100;
    lens.f_number = 2;
    lens.focus_distance = 2.5;
    lens.sensor_width_mm = 36;
    lens.image_width_px = W;
    const auto lim = lens.dof_limits(1.0);
    Instance& fx = *f.s.fx;
    fx.set_choice("grid", "1x1");
    fx.set("near_00", lim.near);
    fx.set("far_00", lim.far);
    fx.disconnect("Source");
    fx.connect("Source", ref_clip(2), 3);
    const Rendered r = fx.render(3, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << fx.persistent_message();
    ASSERT_EQ(r.bounds.x2, W) << "the extent of the frames the clip has";
    ASSERT_EQ(r.bounds.y2, H);
    double d = 0;
    for (int oy = 0; oy < H; ++oy)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 4; ++c) d = std::max(d, double(std::abs(r.at(x, oy, c) - ref_value(2, x, H - 1 - oy, c))));
    EXPECT_EQ(d, 0.0);
}

TEST(ofx_focal_stack, ManifestFilesAtHalfScaleAreTheFullCompositeReduced) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("stack_source", "files");
    f.s.fx->set_string("manifest", f.manifest);
    const Rendered r = f.s.fx->render(1, {0.5, 0.5});
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    ASSERT_EQ(r.bounds.x2, W / 2);
    ASSERT_EQ(r.bounds.y2, H / 2);
    OIIO::ImageSpec spec;
    const std::vector<float> full = read_pixels(f.cli("--surfaces " + quote(f.surfaces)), &spec);
    ASSERT_EQ(spec.width, W);
    double d = 0;
    for (int oy = 0; oy < H / 2; ++oy)
        for (int x = 0; x < W / 2; ++x)
            for (int c = 0; c < 4; ++c) {
                double sum = 0;
                for (int v = 0; v < 2; ++v)
                    for (int u = 0; u < 2; ++u) {
                        const int fy = H - 1 - (2 * oy + v);  // file rows are top first
                        sum += full[(std::size_t(fy) * W + std::size_t(2 * x + u)) * 4 + std::size_t(c)];
                    }
                d = std::max(d, std::abs(r.at(x, oy, c) - sum / 4));
            }
    EXPECT_LE(d, 1e-6);
}

TEST(ofx_focal_stack, SourceFramesAtHalfScalePickReducedReferencePixels) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    const Rendered r = f.s.fx->render(1, {0.5, 0.5});
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    ASSERT_EQ(r.bounds.x2, W / 2);
    ASSERT_EQ(r.bounds.y2, H / 2);
    // The host reduces each frame by 2x2 means; a hard pick copies one of them per pixel.
    int used[N] = {};
    for (int oy = 0; oy < H / 2; ++oy)
        for (int x = 0; x < W / 2; ++x) {
            int match = -1;
            for (int i = 0; i < N && match < 0; ++i) {
                bool same = true;
                for (int c = 0; c < 4 && same; ++c) {
                    double sum = 0;
                    for (int v = 0; v < 2; ++v)
                        for (int u = 0; u < 2; ++u) sum += ref_value(i, 2 * x + u, H - 1 - (2 * oy + v), c);
                    same = std::abs(r.at(x, oy, c) - sum / 4) <= 1e-6;
                }
                if (same) match = i;
            }
            ASSERT_GE(match, 0) << "pixel " << x << "," << oy << " is no reference's";
            ++used[match];
        }
    int n_used = 0;
    for (int u : used) n_used += u > 0;
    EXPECT_GE(n_used, 3) << "the surfaces select several references at half scale too";
}

TEST(ofx_focal_stack, BadLensTableIsAPersistentErrorNamingTheColumn) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_string("lens_table", "frame,focus,f_number\n1,2,2\n");
    const Rendered r = f.s.fx->render(1, kFull);
    EXPECT_EQ(r.status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "lens_table")) << f.s.fx->persistent_message();
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "'focus'")) << f.s.fx->persistent_message();
}

TEST(ofx_focal_stack, LensTableIsReadAsTheCliReadsAManifestTable) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    // far "inf", the one spelling of infinity: a one-reference stack, every pixel from frame 1.
    f.s.fx->set_string("lens_table", "frame,focus_distance,f_number,far\n1,1,2,inf\n");
    const Rendered r = f.s.fx->render(1, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    for (int oy = 0; oy < H; oy += 7)
        for (int x = 0; x < W; x += 5)
            for (int c = 0; c < 4; ++c) ASSERT_EQ(r.at(x, oy, c), ref_value(0, x, H - 1 - oy, c)) << x << "," << oy;

    f.s.fx->set_string("lens_table", "frame,focus_distance,f_number,far\n1,1,2,infinity\n");
    EXPECT_EQ(f.s.fx->render(1, kFull).status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "parameter 'lens_table' line 2 column 'far': not a number: 'infinity'"))
        << f.s.fx->persistent_message();

    f.s.fx->set_string("lens_table", "frame,focus_distance,f_number\n1.5,1,2\n");
    EXPECT_EQ(f.s.fx->render(1, kFull).status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "parameter 'lens_table' line 2 column 'frame': not a whole number: 1.5"))
        << f.s.fx->persistent_message();
}

TEST(ofx_focal_stack, MissingStackFrameIsNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->disconnect("Source");
    for (int i = 0; i < N - 1; ++i) f.s.fx->connect("Source", ref_clip(i), i + 1);  // no frame 5
    f.s.fx->set_choice("grid", "1x1");
    f.s.fx->set("near_00", 5);
    f.s.fx->set_bool("far_infinite", true);  // only reference 4 (focus 8, beyond the hyperfocal distance) reaches infinity
    const Rendered r = f.s.fx->render(1, kFull);
    EXPECT_EQ(r.status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "frame 5")) << f.s.fx->persistent_message();
    EXPECT_EQ(f.s.host.live_images(), 0);
}

TEST(ofx_focal_stack, MissingManifestAndMapsAreNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("stack_source", "files");
    f.s.fx->set_string("manifest", f.dir.file("nope.json"));
    EXPECT_EQ(f.s.fx->render(1, kFull).status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "nope.json")) << f.s.fx->persistent_message();
    f.s.fx->set_choice("stack_source", "frames");
    f.s.fx->set_string("manifest", "");
    f.s.fx->set_choice("focus_source", "maps");
    EXPECT_EQ(f.s.fx->render(1, kFull).status, kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "Near clip is not connected")) << f.s.fx->persistent_message();
}
