// "gdof Defocus" through the test host against `gdof --diffuse` on the same
// generated plate (written to EXR) and the same blur field, and the host
// behaviours: tiles equal the whole render, render scale 0.5 equals the full
// render reduced, regions of definition and interest, premultiplication,
// RGB, the mask, abort.
#include <algorithm>
#include <chrono>

#include "gdof/defocus.h"
#include "ofx/ofx_defocus_fixture.h"

using namespace gdof::test;
using namespace gdof::test::defocus_fixture;

TEST(ofx_defocus, FocalPlanesEqualCliDiffuseTo1e5) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const Rendered r = f.s.fx->render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(r.bounds.x1, 0);
    EXPECT_EQ(r.bounds.x2, W);
    EXPECT_EQ(r.bounds.y2, H) << "a full-frame plate keeps its frame";
    const std::string out = f.cli(kPlanesJson);
    const double d = max_diff_to_file(r, out, 4, H);
    std::printf("OFX vs CLI (focal planes): max |diff| = %.3g\n", d);
    EXPECT_LE(d, 1e-5);
    // Not trivially equal: the plate is visibly blurred, and stays opaque.
    const ClipFrame src = plate_clip(f.plate, "rgba");
    double changed = 0, min_alpha = 1;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) changed = std::max(changed, double(std::abs(r.at(x, y, c) - src.at(x, y, c))));
            min_alpha = std::min(min_alpha, double(r.at(x, y, 3)));
        }
    EXPECT_GT(changed, 0.2);
    EXPECT_GT(min_alpha, 0.999);
    EXPECT_FALSE(r.wrote_outside);
    EXPECT_EQ(f.s.host.live_images(), 0) << "every image fetched is released";
    EXPECT_TRUE(f.s.fx->persistent_message().empty());
    EXPECT_EQ(f.s.fx->destroy(), kOfxStatOK);
}

// "Cut Layers by Blur" (on by default) is the CLI's default --layers auto,
// off its auto:gaps: equal to each, and different from each other (the
// plate's depth is continuous, and the cuts its blurred silhouettes need
// add layers).
TEST(ofx_defocus, CutByBlurEqualsCliAutoBlur) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const Rendered r = f.s.fx->render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    f.s.fx->set_bool("cut_by_blur", false);
    const Rendered gaps = f.s.fx->render(0, kFull);
    ASSERT_EQ(gaps.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double d = max_diff_to_file(r, f.cli(kPlanesJson, "--layers auto"), 4, H);
    const double dg = max_diff_to_file(gaps, f.cli(kPlanesJson, "--layers auto:gaps"), 4, H);
    const double from_gaps = max_diff(r, gaps);
    std::printf("OFX cut_by_blur vs CLI auto: max |diff| = %.3g; off vs auto:gaps %.3g; on vs off: %.3g\n", d, dg,
                from_gaps);
    EXPECT_LE(d, 1e-5);
    EXPECT_LE(dg, 1e-5);
    EXPECT_GT(from_gaps, 1e-3);
}

TEST(ofx_defocus, ThinLensEqualsCliWithTheSameLens) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    Instance& fx = *f.s.fx;
    fx.set_choice("kind", "thin_lens");
    fx.set("focal_length_mm", 50);
    fx.set("f_number", 1.4);
    fx.set("focus_distance", 6);
    fx.set("max_radius", 10);
    fx.set_int("layers", 4);
    fx.set_choice("solver", "explicit");
    const Rendered r = fx.render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << fx.persistent_message();
    const std::string out =
        f.cli(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 1.4, "focus_distance": 6,
                                "sensor_width_mm": 36}, "max_radius": 10})",
              "--layers 4 --solver explicit");
    const double d = max_diff_to_file(r, out, 4, H);
    std::printf("OFX vs CLI (thin lens, 4 layers, explicit): max |diff| = %.3g\n", d);
    EXPECT_LE(d, 1e-5);
}

// Filter "bokeh" with a rounded hexagon is the CLI's --bokeh with the same
// --aperture; and it is not the diffusion result.
TEST(ofx_defocus, BokehFilterEqualsCliBokeh) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const Rendered diffused = f.s.fx->render(0, kFull);
    ASSERT_EQ(diffused.status, kOfxStatOK) << f.s.fx->persistent_message();
    f.s.fx->set_choice("filter", "bokeh");
    f.s.fx->set_choice("aperture", "polygon");
    f.s.fx->set_int("blades", 6);
    f.s.fx->set("rotation", 15);
    f.s.fx->set("roundness", 0.2);
    const Rendered r = f.s.fx->render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double d = max_diff_to_file(r, f.cli(kPlanesJson, "--aperture polygon:6:15,roundness=0.2", false, "--bokeh"), 4, H);
    const double from_diffusion = max_diff(r, diffused);
    std::printf("OFX bokeh vs CLI --bokeh: max |diff| = %.3g; vs diffusion %.3g\n", d, from_diffusion);
    EXPECT_LE(d, 1e-5);
    EXPECT_GT(from_diffusion, 1e-2);
}

// Aperture "image" takes the Aperture clip as the kernel: the CLI's
// --aperture image:FILE with the same pixels written to a file.
TEST(ofx_defocus, ApertureClipIsTheImageKernel) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const int kw = 16, kh = 12;
    auto kernel = [](int x, int y, int c) {  // rows top-down: an asymmetric colour pattern
        return c == 0 ? float(x < 6) : c == 1 ? float(y > 7) : float((x + y) % 5 == 0);
    };
    ClipFrame clip = ClipFrame::make(kw, kh, kOfxImageComponentRGB);
    for (int oy = 0; oy < kh; ++oy)
        for (int x = 0; x < kw; ++x)
            for (int c = 0; c < 3; ++c) clip.at(x, oy, c) = kernel(x, kh - 1 - oy, c);
    f.s.fx->connect("Aperture", clip);
    f.s.fx->set_choice("filter", "bokeh");
    f.s.fx->set_choice("aperture", "image");
    const Rendered r = f.s.fx->render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    const std::string kfile = f.dir.file("kernel.exr");
    write_exr(kfile, kw, kh, {"R", "G", "B"}, kernel);
    const double d = max_diff_to_file(r, f.cli(kPlanesJson, "--aperture image:" + quote(kfile), false, "--bokeh"), 4, H);
    std::printf("OFX bokeh (Aperture clip) vs CLI --aperture image: max |diff| = %.3g\n", d);
    EXPECT_LE(d, 1e-5);
}

// "Focus at Point" is the CLI's --focus-at: the same pixel (canonical y is
// bottom-up), the same median depth, the same result; and it refocuses.
TEST(ofx_defocus, FocusAtEqualsCliFocusAt) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    Instance& fx = *f.s.fx;
    fx.set_choice("kind", "thin_lens");
    fx.set("focal_length_mm", 50);
    fx.set("f_number", 1.4);
    fx.set("focus_distance", 6);
    fx.set("max_radius", 10);
    const Rendered at6 = fx.render(0, kFull);
    ASSERT_EQ(at6.status, kOfxStatOK) << fx.persistent_message();
    const int px = W / 4, py = H / 2;
    fx.set_bool("use_focus_at", true);
    fx.set2("focus_at", px + 0.5, H - py - 0.5);
    const Rendered r = fx.render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << fx.persistent_message();
    const std::string out =
        f.cli(R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 1.4, "focus_distance": 6,
                                "sensor_width_mm": 36}, "max_radius": 10})",
              "--f-number 1.4 --focus-distance 6 --focus-at " + std::to_string(px) + "," + std::to_string(py));
    const double d = max_diff_to_file(r, out, 4, H);
    std::printf("OFX focus_at vs CLI --focus-at: max |diff| = %.3g; vs focus 6: %.3g\n", d, max_diff(r, at6));
    EXPECT_LE(d, 1e-5);
    EXPECT_GT(max_diff(r, at6), 1e-3);
}

TEST(ofx_defocus, RegionOfFocusFromAPositionPassEqualsCli) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    Instance& fx = *f.s.fx;
    fx.connect("Depth", plate_clip(f.plate, "position"));
    fx.set_choice("depth_pass", "position");
    fx.set_choice("kind", "region");
    fx.set_choice("shape", "sphere");
    fx.set3("center", 0.8, 0.2, 6);
    fx.set("radius", 1.0);
    fx.set("blur", 5);
    fx.set("falloff", 2);
    fx.set("max_radius", 8);
    const Rendered r = fx.render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << fx.persistent_message();
    const std::string out = f.cli(R"({"blurfield": {"kind": "region", "shape": "sphere", "mode": "focus",
        "center": [0.8, 0.2, 6], "radius": 1, "blur": 5, "falloff": 2, "interpolation": "smooth"}, "max_radius": 8})",
                                  "", true);
    const double d = max_diff_to_file(r, out, 4, H);
    std::printf("OFX vs CLI (sphere of focus, position pass): max |diff| = %.3g\n", d);
    EXPECT_LE(d, 1e-5);
}

TEST(ofx_defocus, DepthChannelIsChosenByParameter) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const Rendered alpha = f.s.fx->render(0, kFull);
    f.s.fx->connect("Depth", plate_clip(f.plate, "depth_rgb"));  // depth in B, nonsense in R and G
    f.s.fx->set_choice("depth_channel", "B");
    const Rendered blue = f.s.fx->render(0, kFull);
    ASSERT_EQ(blue.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(max_diff(alpha, blue), 0.0);
}

TEST(ofx_defocus, FourTilesEqualTheWholeRender) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const auto [whole, tiled, concurrent] = render_tiled(*f.s.fx);
    const double d = max_diff(whole, tiled);
    std::printf("4 tiles vs whole: max |diff| = %.3g (concurrent tiles: %.3g)\n", d, max_diff(whole, concurrent));
    // The library's documented bound for a sub-region (docs/diffusion.md): 1e-4 of the peak (1 here).
    EXPECT_LE(d, 1e-4);
    EXPECT_EQ(max_diff(tiled, concurrent), 0.0) << "concurrent tiles give the same result";
    EXPECT_FALSE(tiled.wrote_outside);
    EXPECT_EQ(f.s.host.live_images(), 0);
}

TEST(ofx_defocus, RegionAnalysisAsksOnlyForTheBlurMarginAndStaysClose) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    f.s.fx->set_choice("analysis", "region");
    f.s.fx->set_int("layers", 3);
    const OfxRectD tile{10, 12, 40, 30};
    std::map<std::string, OfxRectD> roi;
    ASSERT_EQ(f.s.fx->regions_of_interest(0, kFull, tile, roi), kOfxStatOK);
    const int m = gdof::defocus_margin(8);  // max_radius 8 px
    EXPECT_EQ(m, 13);
    for (const char* c : {"Source", "Depth"}) {
        EXPECT_DOUBLE_EQ(roi[c].x1, 10 - m) << c;
        EXPECT_DOUBLE_EQ(roi[c].y1, 12 - m) << c;
        EXPECT_DOUBLE_EQ(roi[c].x2, 40 + m) << c;
        EXPECT_DOUBLE_EQ(roi[c].y2, 30 + m) << c;
    }
    EXPECT_DOUBLE_EQ(roi["Mask"].x2, 40) << "the mask is needed only under the output";
    const Rendered whole = f.s.fx->render(0, kFull);
    const Rendered tiled = f.s.fx->render(0, kFull, quadrants(whole.bounds));
    ASSERT_EQ(tiled.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double d = max_diff(whole, tiled);
    double sum = 0;
    for (std::size_t i = 0; i < whole.px.size(); ++i) sum += std::abs(whole.px[i] - tiled.px[i]);
    std::printf("4 tiles vs whole, analysis = region (3 layers): max |diff| = %.3g, mean %.3g\n", d, sum / whole.px.size());
    // Layers and extrapolated radii come from what each tile reads: close, not equal (docs/ofx.md).
    EXPECT_LE(sum / whole.px.size(), 0.005);
    EXPECT_LE(d, 0.15);
}

TEST(ofx_defocus, FrameAnalysisAsksForTheWholeSource) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    std::map<std::string, OfxRectD> roi;
    ASSERT_EQ(f.s.fx->regions_of_interest(0, kFull, {10, 12, 40, 30}, roi), kOfxStatOK);
    for (const char* c : {"Source", "Depth"}) {
        EXPECT_DOUBLE_EQ(roi[c].x1, 0) << c;
        EXPECT_DOUBLE_EQ(roi[c].y1, 0) << c;
        EXPECT_DOUBLE_EQ(roi[c].x2, W) << c;
        EXPECT_DOUBLE_EQ(roi[c].y2, H) << c;
    }
}

TEST(ofx_defocus, RegionOfDefinitionGrowsByTheLargestBlurWithinTheFrame) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    // An element smaller than the frame: its blur spreads around it (margin of 8 px: 13 px).
    ClipFrame src = plate_clip(f.plate, "rgba"), depth = plate_clip(f.plate, "depth");
    auto crop = [](const ClipFrame& in, OfxRectI b) {
        ClipFrame out = ClipFrame::make(b.x2 - b.x1, b.y2 - b.y1, in.components);
        out.bounds = b;
        for (int y = b.y1; y < b.y2; ++y)
            for (int x = b.x1; x < b.x2; ++x)
                for (int c = 0; c < in.ncomp(); ++c) out.at(x, y, c) = in.at(x, y, c);
        return out;
    };
    f.s.fx->connect("Source", crop(src, {20, 20, 50, 40}));
    f.s.fx->connect("Depth", crop(depth, {20, 20, 50, 40}));
    OfxRectD rod{};
    ASSERT_EQ(f.s.fx->region_of_definition(0, kFull, rod), kOfxStatOK);
    EXPECT_DOUBLE_EQ(rod.x1, 20 - 13);
    EXPECT_DOUBLE_EQ(rod.y1, 20 - 13);
    EXPECT_DOUBLE_EQ(rod.x2, 50 + 13);
    EXPECT_DOUBLE_EQ(rod.y2, 40 + 13);
    // At render scale 0.5 the blur is 4 px: margin 7 px, in canonical coordinates 14.
    ASSERT_EQ(f.s.fx->region_of_definition(0, {0.5, 0.5}, rod), kOfxStatOK);
    EXPECT_DOUBLE_EQ(rod.x1, 20 - 14);
    EXPECT_DOUBLE_EQ(rod.x2, 50 + 14);
    // Clipped to the frame (display window): a full-frame plate's RoD is the frame.
    f.s.fx->connect("Source", src);
    f.s.fx->connect("Depth", depth);
    ASSERT_EQ(f.s.fx->region_of_definition(0, kFull, rod), kOfxStatOK);
    EXPECT_DOUBLE_EQ(rod.x1, 0);
    EXPECT_DOUBLE_EQ(rod.x2, W);
    EXPECT_DOUBLE_EQ(rod.y2, H);
    // The element's render equals the library on the same element.
    f.s.fx->connect("Source", crop(src, {20, 20, 50, 40}));
    f.s.fx->connect("Depth", crop(depth, {20, 20, 50, 40}));
    const Rendered r = f.s.fx->render(0, kFull);
    ASSERT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(r.bounds.x1, 7);
    EXPECT_EQ(r.bounds.x2, 63);
    double edge_alpha = 0;
    for (int y = r.bounds.y1; y < r.bounds.y2; ++y) edge_alpha = std::max(edge_alpha, double(r.at(18, y, 3)));
    EXPECT_GT(edge_alpha, 0.01) << "blur spreads out of the element";
}

// Render scale 0.5 against the full render reduced by 2x2 means. The host
// reduces the Source by 2x2 means; the depth pass by averaging too (as a
// proxy resize does) or by taking one pixel of each block. Averaged depth
// puts pixels on object edges at depths neither object has, where they get
// another blur: that is where the largest differences are.
struct ScaleError {
    double mean = 0, p99 = 0, max = 0;
};

ScaleError half_scale_error(const std::string& depth_filter, const std::string& aperture = "") {
    Fixture f;
    if (!f.s.ok()) return {1e9, 1e9, 1e9};
    set_planes(*f.s.fx);
    if (!aperture.empty()) {  // the bokeh filter: the kernel scales with the blur
        f.s.fx->set_choice("filter", "bokeh");
        f.s.fx->set_choice("aperture", aperture);
    }
    f.s.fx->set_int("layers", 3);  // a split that does not depend on the resolution
    ClipFrame depth = plate_clip(f.plate, "depth");
    depth.filter = depth_filter;
    f.s.fx->connect("Depth", depth);
    const Rendered full = f.s.fx->render(0, kFull);
    const Rendered half = f.s.fx->render(0, {0.5, 0.5});
    EXPECT_EQ(half.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(half.bounds.x2, W / 2);
    EXPECT_EQ(half.bounds.y2, H / 2);
    std::vector<double> all;
    for (int y = 0; y < H / 2; ++y)
        for (int x = 0; x < W / 2; ++x)
            for (int c = 0; c < 4; ++c) {
                const double ref = 0.25 * (full.at(2 * x, 2 * y, c) + full.at(2 * x + 1, 2 * y, c) +
                                           full.at(2 * x, 2 * y + 1, c) + full.at(2 * x + 1, 2 * y + 1, c));
                all.push_back(std::abs(half.at(x, y, c) - ref));
            }
    std::sort(all.begin(), all.end());
    ScaleError e;
    for (double v : all) e.mean += v;
    e.mean /= double(all.size());
    e.p99 = all[all.size() * 99 / 100];
    e.max = all.back();
    std::printf("scale 0.5 vs full reduced 2x2 (depth reduced by %s%s): mean |diff| %.4f, 99th percentile %.4f, max %.4f\n",
                depth_filter.c_str(), aperture.empty() ? "" : (", bokeh " + aperture).c_str(), e.mean, e.p99, e.max);
    return e;
}

TEST(ofx_defocus, HalfScaleEqualsTheFullRenderReducedWithinTolerance) {
    // Documented tolerance (docs/ofx.md): mean 0.01, 99th percentile 0.15 of a
    // peak of 1; the largest single differences sit on depth edges.
    const ScaleError box = half_scale_error("box");
    EXPECT_LE(box.mean, 0.01);
    EXPECT_LE(box.p99, 0.15);
    EXPECT_LE(box.max, 0.45);
    const ScaleError nearest = half_scale_error("nearest");
    EXPECT_LE(nearest.mean, 0.01);
    EXPECT_LE(nearest.p99, 0.15);
    EXPECT_LE(nearest.max, 0.45);
    // The bokeh filter's aperture scales with the render scale too.
    const ScaleError hex = half_scale_error("box", "polygon");
    EXPECT_LE(hex.mean, 0.01);
    EXPECT_LE(hex.p99, 0.15);
    EXPECT_LE(hex.max, 0.45);
}

TEST(ofx_defocus, UnpremultipliedSourceIsPremultipliedAndOutputDeclaredPremultiplied) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    // Semi-transparent stripes: once straight, once premultiplied by the host.
    ClipFrame straight = plate_clip(f.plate, "rgba");
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) straight.at(x, y, 3) = 0.25f + (x % 4) / 4.0f;
    straight.premult = kOfxImageUnPreMultiplied;
    ClipFrame premult = straight;
    premult.premult = kOfxImagePreMultiplied;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) premult.at(x, y, c) *= premult.at(x, y, 3);
    f.s.fx->connect("Source", straight);
    const Rendered a = f.s.fx->render(0, kFull);
    ASSERT_EQ(a.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(f.s.fx->effect().clips.at("Output")->props.str(kOfxImageEffectPropPreMultiplication), kOfxImagePreMultiplied);
    f.s.fx->connect("Source", premult);
    const Rendered b = f.s.fx->render(0, kFull);
    EXPECT_EQ(max_diff(a, b), 0.0) << "a straight source is premultiplied before blurring";
}

TEST(ofx_defocus, RgbSourceGivesOpaqueRgbOutput) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    f.s.fx->connect("Source", plate_clip(f.plate, "rgb"));
    const Rendered rgb = f.s.fx->render(0, kFull);
    ASSERT_EQ(rgb.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_EQ(rgb.ncomp, 3);
    EXPECT_EQ(f.s.fx->effect().clips.at("Output")->props.str(kOfxImageEffectPropPreMultiplication), kOfxImageOpaque);
    f.s.fx->connect("Source", plate_clip(f.plate, "rgba"));
    const Rendered rgba = f.s.fx->render(0, kFull);
    double d = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) d = std::max(d, double(std::abs(rgb.at(x, y, c) - rgba.at(x, y, c))));
    EXPECT_LE(d, 1e-6) << "RGB is the opaque RGBA result without alpha";
}

TEST(ofx_defocus, MaskMixesSourceAndResult) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const Rendered full = f.s.fx->render(0, kFull);
    ClipFrame mask = ClipFrame::make(W, H, kOfxImageComponentAlpha);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) mask.at(x, y, 0) = x < W / 2 ? 0.0f : 1.0f;
    f.s.fx->connect("Mask", mask);
    const Rendered masked = f.s.fx->render(0, kFull);
    ASSERT_EQ(masked.status, kOfxStatOK) << f.s.fx->persistent_message();
    const ClipFrame src = plate_clip(f.plate, "rgba");
    double left = 0, right = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 4; ++c) {
                if (x < W / 2) left = std::max(left, double(std::abs(masked.at(x, y, c) - src.at(x, y, c))));
                else right = std::max(right, double(std::abs(masked.at(x, y, c) - full.at(x, y, c))));
            }
    EXPECT_EQ(left, 0.0) << "mask 0: the source";
    EXPECT_EQ(right, 0.0) << "mask 1: the defocused result";
}

TEST(ofx_defocus, AbortStopsTheRenderWithoutAnError) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    f.s.fx->set_choice("solver", "explicit");
    f.s.fx->effect().abort_after = 1;  // the host wants out at the first poll
    const auto t0 = std::chrono::steady_clock::now();
    const Rendered r = f.s.fx->render(0, kFull);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, kOfxStatOK);
    EXPECT_TRUE(f.s.fx->persistent_message().empty()) << f.s.fx->persistent_message();
    EXPECT_GE(f.s.fx->effect().abort_polls.load(), 1) << "the plugin polls abort()";
    EXPECT_LT(secs, 5.0);
    EXPECT_EQ(f.s.host.live_images(), 0);
}

TEST(ofx_defocus, FilterContextRendersTheSame) {
    const Plate plate = make_plate(W, H);
    Session s(kDefocusId, W, H, kOfxImageEffectContextFilter);
    ASSERT_TRUE(s.ok());
    auto general = s.host.create_instance(kDefocusId, kOfxImageEffectContextGeneral, W, H);
    ASSERT_TRUE(general);
    Rendered r[2];
    int i = 0;
    for (Instance* fx : {s.fx.get(), general.get()}) {
        fx->connect("Source", plate_clip(plate, "rgba"));
        fx->connect("Depth", plate_clip(plate, "depth"));
        fx->set_choice("depth_channel", "A");
        set_planes(*fx);
        r[i++] = fx->render(0, kFull);
    }
    ASSERT_EQ(r[0].status, kOfxStatOK);
    EXPECT_EQ(max_diff(r[0], r[1]), 0.0);
}
