// Light fields from files: row/column patterns, Stanford-archive folders,
// lf.json / stack.json, errors naming files and keys, and the real Lytro views.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "gdof/io/lightfield_io.h"
#include "gdof/lightfield.h"
#include "test_support.h"

using namespace gdof;
using gdof::test::ScratchDir;

namespace {

// An 8-bit RGB PNG whose pixels are value(x, y, c) (0..255).
void write_png(const std::string& path, int w, int h, const std::function<int(int, int, int)>& value) {
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> px(std::size_t(w) * std::size_t(h) * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) px[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3 + std::size_t(c)] =
                (unsigned char)value(x, y, c);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
}

std::string name_of(const std::string& dir, const char* fmt, int r, int c) {
    char b[256];
    std::snprintf(b, sizeof b, fmt, r, c);
    return dir + "/" + b;
}

// rows x cols views named by fmt from (r0, c0); R = 10 * row index, G = 10 * column index.
void write_grid(const std::string& dir, const char* fmt, int r0, int c0, int rows, int cols, int w = 12, int h = 8) {
    for (int r = r0; r < r0 + rows; ++r)
        for (int c = c0; c < c0 + cols; ++c)
            write_png(name_of(dir, fmt, r, c), w, h, [&](int x, int, int ch) { return ch == 0 ? 10 * r : ch == 1 ? 10 * c : x; });
}

double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

}  // namespace

TEST(lightfield, pattern_views_load_as_a_grid_rows_first_and_linearised) {
    ScratchDir dir;
    write_grid(dir.path().string(), "lf_%02d_%02d.png", 3, 5, 3, 4);
    auto lf = io::load_lightfield(dir.file("lf_%02d_%02d.png"));
    ASSERT_TRUE(lf) << lf.message();
    EXPECT_EQ(lf->rows, 3);
    EXPECT_EQ(lf->cols, 4);
    EXPECT_EQ(lf->center_row, 1);  // file row 4
    EXPECT_EQ(lf->center_col, 1);  // file column 6 (middle rounded down)
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            const Image& v = lf->view(r, c);
            EXPECT_NEAR(v.at(0, 0, 0), srgb_to_linear(10 * (r + 3) / 255.0), 2e-4) << r << "," << c;
            EXPECT_NEAR(v.at(1, 0, 0), srgb_to_linear(10 * (c + 5) / 255.0), 2e-4) << r << "," << c;
            EXPECT_EQ(lf->sources[std::size_t(r * 4 + c)], name_of(dir.path().string(), "lf_%02d_%02d.png", r + 3, c + 5));
        }
    // sRGB 128 -> linear 0.2158.
    write_png(dir.file("grey_00_00.png"), 4, 4, [](int, int, int) { return 128; });
    auto grey = io::load_lightfield(dir.file("grey_%02d_%02d.png"));
    ASSERT_TRUE(grey) << grey.message();
    EXPECT_NEAR(grey->central().at(0, 1, 1), 0.2158, 1e-3);
}

TEST(lightfield, missing_view_is_an_error_naming_the_expected_file) {
    ScratchDir dir;
    write_grid(dir.path().string(), "v_%02d_%02d.png", 0, 0, 3, 3);
    std::filesystem::remove(dir.file("v_01_02.png"));
    auto lf = io::load_lightfield(dir.file("v_%02d_%02d.png"));
    ASSERT_FALSE(lf);
    EXPECT_NE(lf.message().find(dir.file("v_01_02.png")), std::string::npos) << lf.message();
    EXPECT_NE(lf.message().find("missing view"), std::string::npos) << lf.message();
    // Unpadded names do not stand in for padded ones.
    write_png(dir.file("v_1_2.png"), 12, 8, [](int, int, int) { return 0; });
    EXPECT_FALSE(io::load_lightfield(dir.file("v_%02d_%02d.png")));
    // No matching file at all, and a pattern without two fields.
    auto none = io::load_lightfield(dir.file("w_%02d_%02d.png"));
    ASSERT_FALSE(none);
    EXPECT_NE(none.message().find("no files"), std::string::npos) << none.message();
    auto one = io::load_lightfield(dir.file("v_%02d.png"));
    ASSERT_FALSE(one);
    EXPECT_NE(one.message().find("two integer fields"), std::string::npos) << one.message();
}

TEST(lightfield, mismatched_view_sizes_are_an_error_naming_the_file) {
    ScratchDir dir;
    write_grid(dir.path().string(), "v_%d_%d.png", 0, 0, 2, 2);
    write_png(dir.file("v_1_0.png"), 13, 8, [](int, int, int) { return 0; });
    auto lf = io::load_lightfield(dir.file("v_%d_%d.png"));
    ASSERT_FALSE(lf);
    EXPECT_NE(lf.message().find(dir.file("v_1_0.png")), std::string::npos) << lf.message();
    EXPECT_NE(lf.message().find("13x8"), std::string::npos) << lf.message();
}

TEST(lightfield, stanford_archive_folder_loads_by_row_and_column) {
    ScratchDir dir;
    const std::string d = dir.path().string();
    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 3; ++c) {
            char b[128];
            std::snprintf(b, sizeof b, "out_%02d_%02d_%.6f_%.6f_.png", r, c, -10.5 * r, 900.25 - 8.0 * c);
            write_png(d + "/" + b, 6, 4, [&](int, int, int ch) { return ch == 0 ? 10 * r : 10 * c; });
        }
    auto lf = io::load_lightfield(d);
    ASSERT_TRUE(lf) << lf.message();
    EXPECT_EQ(lf->rows, 2);
    EXPECT_EQ(lf->cols, 3);
    EXPECT_NEAR(lf->view(1, 2).at(0, 0, 0), srgb_to_linear(10 / 255.0), 2e-4);
    EXPECT_NEAR(lf->view(1, 2).at(1, 0, 0), srgb_to_linear(20 / 255.0), 2e-4);

    for (const auto& e : std::filesystem::directory_iterator(d))
        if (e.path().filename().string().rfind("out_01_01_", 0) == 0) std::filesystem::remove(e.path());
    auto missing = io::load_lightfield(d);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("out_01_01_*"), std::string::npos) << missing.message();

    ScratchDir empty;
    auto none = io::load_lightfield(empty.path().string());
    ASSERT_FALSE(none);
    EXPECT_NE(none.message().find("Stanford"), std::string::npos) << none.message();
}

TEST(lightfield, config_sets_geometry_center_and_crop) {
    ScratchDir dir;
    write_grid(dir.path().string(), "v_%02d_%02d.png", 1, 1, 3, 3, 20, 10);
    auto cfg = io::parse_lightfield_config(R"({
        "disparity_at_infinity": -0.25, "baseline": 0.002, "focal_length_mm": 10, "sensor_width_mm": 5,
        "center": [1, 2], "crop": {"x": 2, "y": 1, "width": 15, "height": 8}, "scene_unit_mm": 1000 })");
    ASSERT_TRUE(cfg) << cfg.message();
    auto lf = io::load_lightfield(dir.file("v_%02d_%02d.png"), *cfg);
    ASSERT_TRUE(lf) << lf.message();
    EXPECT_EQ(lf->center_row, 0);
    EXPECT_EQ(lf->center_col, 1);
    EXPECT_EQ(lf->central().data_window(), (Roi{0, 0, 15, 8}));
    // Cropped pixel (0, 0) is view pixel (2, 1): B = x = 2.
    EXPECT_NEAR(lf->central().at(2, 0, 0), srgb_to_linear(2 / 255.0), 1e-5);
    // focal length in px = 10 / 5 * 20 (the full width) = 40; x 0.002.
    EXPECT_DOUBLE_EQ(lf->geometry.focal_baseline, 0.08);
    EXPECT_DOUBLE_EQ(lf->geometry.disparity_at_infinity, -0.25);
    EXPECT_TRUE(lf->geometry.depth_known);

    auto outside = io::parse_lightfield_config(R"({"center": [9, 9]})");
    ASSERT_TRUE(outside);
    auto bad = io::load_lightfield(dir.file("v_%02d_%02d.png"), *outside);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("center"), std::string::npos) << bad.message();

    auto big = io::parse_lightfield_config(R"({"crop": {"x": 10, "y": 0, "width": 15, "height": 8}})");
    ASSERT_TRUE(big);
    auto bc = io::load_lightfield(dir.file("v_%02d_%02d.png"), *big);
    ASSERT_FALSE(bc);
    EXPECT_NE(bc.message().find("crop"), std::string::npos) << bc.message();
}

TEST(lightfield, config_errors_name_the_key) {
    auto expect_error = [](const std::string& json, const std::string& key) {
        auto r = io::parse_lightfield_config(json, "lf.json");
        ASSERT_FALSE(r) << json;
        EXPECT_NE(r.message().find(key), std::string::npos) << r.message();
        EXPECT_NE(r.message().find("lf.json"), std::string::npos) << r.message();
    };
    expect_error(R"({"disparity_at_infinty": 1})", "disparity_at_infinty");
    expect_error(R"({"focal_baseline": 0})", "focal_baseline");
    expect_error(R"({"focal_baseline": 1, "baseline": 2})", "baseline");
    expect_error(R"({"baseline": 0.1, "focal_length_mm": 50})", "sensor_width_mm");
    expect_error(R"({"center": [1]})", "center");
    expect_error(R"({"crop": {"x": 0, "y": 0, "width": -1, "height": 3}})", "crop.width");
    expect_error(R"({"disparity_at_infinity": "far"})", "disparity_at_infinity");
    expect_error(R"({"disparity_at_infinity": 1,})", "malformed");
    auto missing = io::read_lightfield_config("/nonexistent/lf.json");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("/nonexistent/lf.json"), std::string::npos);
}

TEST(lightfield, stack_spec_grid_and_references) {
    auto s = io::parse_extract_stack_options(R"({
        "coc_px": 0.5, "filter": "bilinear",
        "disparities": [0, 0.5], "depths": ["inf"], "apertures": [1, 2],
        "references": [{"disparity": 1.25, "aperture": 0}, {"depth": 3, "aperture": 1.5}] })");
    ASSERT_TRUE(s) << s.message();
    EXPECT_EQ(s->coc_px, 0.5);
    EXPECT_EQ(s->filter, LightFieldFilter::Bilinear);
    ASSERT_EQ(s->references.size(), 8u);
    EXPECT_EQ(s->references[0].focus_disparity, 0.0);
    EXPECT_EQ(s->references[0].aperture_radius, 1.0);
    EXPECT_EQ(s->references[3].focus_disparity, 0.5);
    EXPECT_EQ(s->references[3].aperture_radius, 2.0);
    EXPECT_TRUE(std::isinf(s->references[4].focus_depth));
    EXPECT_TRUE(std::isnan(s->references[4].focus_disparity));
    EXPECT_EQ(s->references[6].focus_disparity, 1.25);
    EXPECT_EQ(s->references[6].aperture_radius, 0.0);
    EXPECT_EQ(s->references[7].focus_depth, 3.0);

    auto expect_error = [](const std::string& json, const std::string& key) {
        auto r = io::parse_extract_stack_options(json, "stack.json");
        ASSERT_FALSE(r) << json;
        EXPECT_NE(r.message().find(key), std::string::npos) << r.message();
    };
    expect_error(R"({"references": [{"disparity": 1, "depth": 2, "aperture": 1}]})", "references[0]");
    expect_error(R"({"references": [{"disparity": 1}]})", "references[0].aperture");
    expect_error(R"({"references": [{"disparity": 1, "aperture": -1}]})", "references[0].aperture");
    expect_error(R"({"references": [{"depth": 0, "aperture": 1}]})", "references[0].depth");
    expect_error(R"({"references": [{"disparity": 1, "aperture": 1, "fstop": 2}]})", "references[0].fstop");
    expect_error(R"({"disparities": [0, 1]})", "apertures");
    expect_error(R"({"coc_px": 0, "disparities": [0], "apertures": [1]})", "coc_px");
    expect_error(R"({"filter": "lanczos", "disparities": [0], "apertures": [1]})", "filter");
    expect_error(R"({})", "references");
}

TEST(lightfield, real_lytro_views_load_and_refocus) {
    GDOF_REQUIRE_SHARED(dir, "lightfield/lytro_2067");
    auto lf = io::load_lightfield(dir + "/2067_%02d_%02d.png");
    ASSERT_TRUE(lf) << lf.message();
    EXPECT_EQ(lf->rows, 5);
    EXPECT_EQ(lf->cols, 5);
    EXPECT_EQ(lf->views.size(), 25u);
    EXPECT_EQ(lf->central().width(), 552);
    EXPECT_EQ(lf->central().height(), 383);
    EXPECT_EQ(lf->sources[std::size_t(lf->center_row * 5 + lf->center_col)], dir + "/2067_05_05.png");

    // The sign convention on real data: the dinosaur (near) is sharp at
    // disparity +1, the wall and trees behind it at 0, and neither at -1.
    auto energy = [](const Image& im, Roi r) {
        double e = 0;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                const double gx = im.at(1, x + 1, y) - im.at(1, x, y), gy = im.at(1, x, y + 1) - im.at(1, x, y);
                e += gx * gx + gy * gy;
            }
        return e;
    };
    const Roi dinosaur{280, 160, 420, 260}, background{20, 20, 140, 110};
    auto at_near = refocus(*lf, {1.0, 2.0});
    auto at_far = refocus(*lf, {0.0, 2.0});
    auto at_neg = refocus(*lf, {-1.0, 2.0});
    ASSERT_TRUE(at_near && at_far && at_neg);
    EXPECT_GT(energy(*at_near, dinosaur), 1.3 * energy(*at_far, dinosaur));
    EXPECT_GT(energy(*at_near, dinosaur), 1.3 * energy(*at_neg, dinosaur));
    EXPECT_GT(energy(*at_far, background), 1.3 * energy(*at_near, background));
    EXPECT_GT(energy(*at_far, background), 1.3 * energy(*at_neg, background));
}
