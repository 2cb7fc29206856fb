// The defocus pipeline (defocus_layers) on hand-built layers against
// independent references: the analytic Gaussian for a constant blur, the
// identity for zero blur, the paper's Figure 6 (no holes in a blurred
// interior) and Figure 7 (a blurred layer spreads beyond its silhouette).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <mutex>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"

using namespace gdof;
using namespace gdof::test;

namespace {

double gaussian2d(double x, double y, double sigma, double total) {
    return total / (2.0 * M_PI * sigma * sigma) * std::exp(-(x * x + y * y) / (2.0 * sigma * sigma));
}

// One solver at full resolution on every layer (the pyramid: test_defocus_pyramid.cpp).
DefocusOptions with_solver(DiffusionSolver s) {
    DefocusOptions d;
    d.diffusion.solver = s;
    d.diffusion.pyramid = false;
    return d;
}

class defocus_constant : public ::testing::TestWithParam<std::tuple<DiffusionSolver, double>> {};

}  // namespace

TEST(defocus, MarginAndRegionMaths) {
    EXPECT_EQ(defocus_margin(0.0), 0);
    EXPECT_EQ(defocus_margin(-3.0), 0);
    EXPECT_EQ(defocus_margin(std::nan("")), 0);
    EXPECT_EQ(defocus_margin(2.0), 4);    // ceil(3) + 1
    EXPECT_EQ(defocus_margin(8.0), 13);   // ceil(12) + 1
    EXPECT_EQ(defocus_margin(60.0), 91);  // ceil(90) + 1
    EXPECT_EQ(defocus_margin(0.1), 2);    // any blur reaches at least the neighbours
    EXPECT_EQ(defocus_input_region(Roi{10, 20, 30, 40}, 8.0), (Roi{-3, 7, 43, 53}));
    EXPECT_TRUE(defocus_input_region(Roi{}, 8.0).empty());
    EXPECT_EQ(defocus_input_region(Roi{10, 20, 30, 40}, 0.0), (Roi{10, 20, 30, 40}));
    // RoD: grown, clipped to the frame (display window ∪ data window): blur
    // does not leak out of a full-frame plate, but spreads into the display
    // window from a smaller data window, and into existing overscan.
    EXPECT_EQ(defocus_output_region(Roi{0, 0, 100, 50}, Roi{0, 0, 100, 50}, 2.0), (Roi{0, 0, 100, 50}));
    EXPECT_EQ(defocus_output_region(Roi{10, 10, 20, 20}, Roi{0, 0, 100, 50}, 2.0), (Roi{6, 6, 24, 24}));
    EXPECT_EQ(defocus_output_region(Roi{-50, 0, 100, 50}, Roi{0, 0, 100, 50}, 2.0), (Roi{-50, 0, 100, 50}));
    EXPECT_TRUE(defocus_output_region(Roi{}, Roi{0, 0, 100, 50}, 2.0).empty());
}

TEST_P(defocus_constant, EqualsAnalyticGaussianAndConservesTotals) {
    const auto [solver, R] = GetParam();
    const double sigma0 = 3.0, sigma = R / 2.0, sigma_out = std::sqrt(sigma0 * sigma0 + sigma * sigma);
    const int size = int(2 * std::ceil(6.0 * sigma_out)) + 1;
    const double c = size / 2;
    const Roi frame{0, 0, size, size};
    Layer layer = make_layer(frame, frame, [&](int x, int y) {
        return Rgba{float(gaussian2d(x - c, y - c, sigma0, 1000.0)), 0.5f, 0.0f, 1.0f};
    });
    const double in_r = channel_sum(layer.image, 0), in_g = channel_sum(layer.image, 1), in_a = channel_sum(layer.image, 3);
    DefocusStats stats;
    auto out = defocus_layers({layer}, constant_field(frame, R), test_camera(frame), with_solver(solver), &stats);
    ASSERT_TRUE(out) << out.message();
    // The frame edge insulates: the result is the frame and nothing is lost.
    EXPECT_EQ(out->data_window(), frame);
    EXPECT_NEAR(channel_sum(*out, 0) / in_r, 1.0, 1e-4);
    EXPECT_NEAR(channel_sum(*out, 1) / in_g, 1.0, 1e-4);
    EXPECT_NEAR(channel_sum(*out, 3) / in_a, 1.0, 1e-4);
    double num = 0, den = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (std::hypot(x - c, y - c) > 3.0 * sigma_out) continue;  // away from the borders
            const double ref = gaussian2d(x - c, y - c, sigma_out, 1000.0);
            const double d = out->at(0, x, y) - ref;
            num += d * d;
            den += ref * ref;
        }
    const double rel = std::sqrt(num / den);
    EXPECT_LT(rel, 0.01) << to_string(solver) << " R=" << R;
    RecordProperty("rel_l2", std::to_string(rel));
    EXPECT_EQ(stats.layers, 1);
    EXPECT_EQ(stats.layers_sharp, 0);
    EXPECT_DOUBLE_EQ(stats.max_radius_px, R);
    EXPECT_EQ(stats.pixels_diffused, out->npixels());
}

INSTANTIATE_TEST_SUITE_P(defocus, defocus_constant,
                         ::testing::Combine(::testing::Values(DiffusionSolver::Adi, DiffusionSolver::Explicit),
                                            ::testing::Values(2.0, 8.0, 32.0)));

TEST(defocus, ZeroBlurIsTheIdentityBitForBit) {
    const Roi display{-20, -10, 140, 90};
    const Roi window{-15, -7, 100, 80};
    Layer layer = make_layer(window, display, [](int x, int y) {
        const float a = (x + y) % 7 == 0 ? 0.0f : 0.25f + 0.75f * texture(x, y, 3);
        return Rgba{a * texture(x, y, 0), a * texture(x, y, 1), a * texture(x, y, 2), a};
    });
    layer.image.at(0, 3, 4) = -0.0f;  // even the sign of zero survives
    for (auto solver : {DiffusionSolver::Adi, DiffusionSolver::Explicit}) {
        DefocusStats stats;
        // Both the empty field and a field that is 0 at every pixel.
        for (const BlurField& field : {BlurField(), constant_field(display, 0.0)}) {
            auto out = defocus_layers({layer}, field, test_camera(display), with_solver(solver), &stats);
            ASSERT_TRUE(out) << out.message();
            Image ref = layer.image;
            ref.remove_channel(4);
            EXPECT_TRUE(bit_identical(*out, ref)) << to_string(solver);
            EXPECT_EQ(stats.layers_sharp, 1);
            EXPECT_EQ(stats.pixels_diffused, 0u);
        }
    }
}

TEST(defocus, EmptyLayersCostNothingAndSharpLayersPassThrough) {
    const Roi display{0, 0, 120, 80};
    Layer empty = make_layer(display, display, [](int, int) { return Rgba{0, 0, 0, 0}; }, 3.0, "empty");
    Layer bg = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    }, 10.0, "bg");
    // Blur only at depth < 5 (the empty layer): bg is sharp.
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": 6,
        "min": [-1000, -1000, 0], "max": [1000, 1000, 5]}})");
    ASSERT_TRUE(field) << field.message();
    DefocusStats stats;
    auto out = defocus_layers({empty, bg}, *field, test_camera(display), {}, &stats);
    ASSERT_TRUE(out) << out.message();
    Image ref = bg.image;
    ref.remove_channel(4);
    EXPECT_TRUE(bit_identical(*out, ref));
    EXPECT_EQ(stats.layers, 2);
    EXPECT_EQ(stats.layers_empty, 1);
    EXPECT_EQ(stats.layers_sharp, 1);
    EXPECT_EQ(stats.pixels_diffused, 0u);
    EXPECT_EQ(stats.pixels_skipped, 2 * display.npixels());
    const std::string rep = stats.report();
    EXPECT_NE(rep.find("layers"), std::string::npos) << rep;
    EXPECT_NE(rep.find("1 empty, 1 sharp, 0 diffused"), std::string::npos) << rep;
    EXPECT_NE(rep.find("t diffuse"), std::string::npos) << rep;
}

// Figure 6: a heavily blurred rectangle inside a sharp opaque image stays
// opaque (sharp neighbours insulate: no holes, no dark halo inside).
TEST(defocus, BlurredInteriorHasNoHoles_Figure6) {
    const Roi display{0, 0, 260, 200};
    const Roi rect{60, 50, 200, 150};
    Layer layer = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f};
    });
    const BlurField field = map_field(display, [&](int x, int y) { return rect.contains(x, y) ? 1.0f : 0.0f; }, 60.0);
    for (auto solver : {DiffusionSolver::Adi, DiffusionSolver::Explicit}) {
        auto out = defocus_layers({layer}, field, test_camera(display), with_solver(solver));
        ASSERT_TRUE(out) << out.message();
        double amin = 1e9, amax = -1e9;
        for (int y = rect.y0; y < rect.y1; ++y)
            for (int x = rect.x0; x < rect.x1; ++x) {
                amin = std::min(amin, double(out->at(3, x, y)));
                amax = std::max(amax, double(out->at(3, x, y)));
            }
        EXPECT_GE(amin, 0.99) << to_string(solver);
        EXPECT_LE(amax, 1.0 + 1e-5) << to_string(solver);
        // Outside the rectangle the image is sharp and untouched.
        for (int y = 0; y < display.y1; y += 7)
            for (int x = 0; x < display.x1; x += 5)
                if (!rect.contains(x, y)) {
                    ASSERT_EQ(out->at(0, x, y), layer.image.at(0, x, y)) << x << "," << y;
                }
        // The interior really is blurred (the texture's contrast is gone).
        double lo = 1e9, hi = -1e9;
        for (int y = 90; y < 110; ++y)
            for (int x = 110; x < 150; ++x) {
                lo = std::min(lo, double(out->at(0, x, y)));
                hi = std::max(hi, double(out->at(0, x, y)));
            }
        EXPECT_LT(hi - lo, 0.1) << to_string(solver);
    }
}

// Figure 7 and compositing: a blurred foreground disc over a sharp
// background. The foreground's blur is extrapolated beyond its silhouette,
// so its coverage spreads into a semi-transparent rim; its interior stays
// opaque; the far background is untouched.
TEST(defocus, ForegroundSpreadsBeyondItsSilhouette_Figure7) {
    const Roi display{0, 0, 200, 160};
    const double cx = 100, cy = 80, radius = 30, R = 12;
    auto in_disc = [&](int x, int y) { return std::hypot(x + 0.5 - cx, y + 0.5 - cy) < radius; };
    Layer fg = make_layer(display, display, [&](int x, int y) {
        return in_disc(x, y) ? Rgba{1, 0, 0, 1} : Rgba{0, 0, 0, 0};
    }, 2.0, "fg");
    Layer bg = make_layer(display, display, [](int, int) { return Rgba{0, 0, 1, 1}; }, 10.0, "bg");
    // Blur R at depths 1..3 (the foreground), sharp behind.
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": 12,
        "min": [-1000, -1000, 1], "max": [1000, 1000, 3]}})");
    ASSERT_TRUE(field) << field.message();
    const Camera cam = test_camera(display);

    // The foreground alone: its coverage after diffusion.
    DefocusStats fstats;
    auto fg_only = defocus_layers({fg}, *field, cam, {}, &fstats);
    ASSERT_TRUE(fg_only) << fg_only.message();
    EXPECT_EQ(fg_only->data_window(), display);  // the layer's window (the work region lies inside it)
    int band = 0;
    for (int y = 0; y < display.y1; ++y)
        for (int x = 0; x < display.x1; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            const double a = value_at(*fg_only, 3, x, y);
            if (std::abs(d - radius) <= 2.0) {  // the silhouette band: semi-transparent
                EXPECT_GT(a, 0.05) << x << "," << y;
                EXPECT_LT(a, 0.95) << x << "," << y;
                ++band;
            }
            if (d > radius + 1.0 && d < radius + 0.5 * R) {
                EXPECT_GT(a, 0.05) << "beyond the silhouette " << x << "," << y;
            }
            if (d < radius - 1.5 * R) {
                EXPECT_GE(a, 0.99) << "interior " << x << "," << y;
            }
        }
    EXPECT_GT(band, 300);

    // Composited over the background: the rim mixes red and blue, the interior
    // is red, the far background is exactly the background.
    auto out = defocus_layers({fg, bg}, *field, cam, DefocusOptions{});
    ASSERT_TRUE(out) << out.message();
    EXPECT_EQ(out->data_window(), display);
    for (int y = 0; y < display.y1; ++y)
        for (int x = 0; x < display.x1; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            ASSERT_NEAR(out->at(3, x, y), 1.0, 1e-5);
            if (std::abs(d - radius) <= 2.0) {
                EXPECT_GT(out->at(0, x, y), 0.05);
                EXPECT_GT(out->at(2, x, y), 0.05);
            }
            if (d < radius - 1.5 * R) {
                EXPECT_GT(out->at(0, x, y), 0.99);
            }
            const bool outside_work = !Roi{70, 50, 130, 110}.grown(defocus_margin(R)).contains(x, y);
            if (outside_work) {
                ASSERT_EQ(out->at(0, x, y), 0.0f);
                ASSERT_EQ(out->at(2, x, y), 1.0f);
            } else if (d > radius + 3.0 * R) {
                EXPECT_NEAR(out->at(2, x, y), 1.0, 2e-3);
            }
        }
}

TEST(defocus, LayerWindowsAnywhereAndOutputWindow) {
    // A small layer partly outside the display window, with a negative origin.
    const Roi display{0, 0, 64, 48};
    const Roi window{-30, -20, 20, 10};
    Layer l = make_layer(window, display, [](int, int) { return Rgba{0.5f, 0.5f, 0.5f, 1.0f}; });
    const double R = 4;
    auto out = defocus_layers({l}, constant_field(display, R), test_camera(display), DefocusOptions{});
    ASSERT_TRUE(out) << out.message();
    const int m = defocus_margin(R);
    // Spreads into the display window, not past the frame (display ∪ data window).
    EXPECT_EQ(out->data_window(), intersect(window.grown(m), unite(display, window)));
    EXPECT_EQ(out->display_window(), display);
    // An empty list gives an empty result.
    auto none = defocus_layers(std::vector<Layer>{}, constant_field(display, R), test_camera(display), DefocusOptions{});
    ASSERT_TRUE(none) << none.message();
    EXPECT_TRUE(none->data_window().empty());
}

TEST(defocus, BadInputsAreClearErrors) {
    const Roi display{0, 0, 40, 30};
    const Camera cam = test_camera(display);
    Layer ok = make_layer(display, display, [](int, int) { return Rgba{0.2f, 0.2f, 0.2f, 1.0f}; });

    // A covered pixel whose position is NaN: a region field is NaN there.
    Layer pnan = ok;
    for (const char* n : {"P.x", "P.y", "P.z"}) pnan.image.add_channel({n, PixelType::Float});
    for (int c = 5; c < 8; ++c)
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x) pnan.image.at(c, x, y) = c == 7 ? 5.0f : 0.0f;
    pnan.image.at(6, 11, 12) = std::numeric_limits<float>::quiet_NaN();
    auto region = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "sphere", "center": [0, 0, 5],
        "radius": 1, "blur": 3}})");
    ASSERT_TRUE(region) << region.message();
    Result<Image> r = defocus_layers({ok, pnan}, *region, cam, DefocusOptions{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("layer 1"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("(11, 12)"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("nan"), std::string::npos) << r.message();

    // A covered pixel behind the camera: the thin lens is +inf there.
    Layer behind = pnan;
    behind.name = "fg";
    behind.image.at(6, 11, 12) = 0.0f;
    behind.image.at(7, 7, 9) = -1.0f;
    auto tl = BlurField::from_thin_lens(ThinLens{});
    ASSERT_TRUE(tl);
    r = defocus_layers({behind}, *tl, cam, DefocusOptions{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("layer 0 'fg'"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("(7, 9)"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("inf"), std::string::npos) << r.message();

    // An absurd radius: names the value and max_radius.
    DefocusOptions s;
    s.diffusion.max_radius = 10;
    r = defocus_layers({ok}, constant_field(display, 25.0), cam, s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("25"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("max_radius"), std::string::npos) << r.message();

    // Colour must be finite.
    Layer inf_c = ok;
    inf_c.image.at(1, 3, 2) = std::numeric_limits<float>::infinity();
    r = defocus_layers({inf_c}, constant_field(display, 2.0), cam, DefocusOptions{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("'G'"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("(3, 2)"), std::string::npos) << r.message();

    // No alpha channel.
    Layer no_a;
    no_a.image = Image::with_channels({"R", "G", "B", "Z"}, display);
    r = defocus_layers({no_a}, constant_field(display, 2.0), cam, DefocusOptions{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("'A'"), std::string::npos) << r.message();

    // No depth and no positions.
    Layer no_z;
    no_z.image = Image::with_channels({"R", "G", "B", "A"}, display);
    no_z.image.at(3, 1, 1) = 1.0f;
    r = defocus_layers({no_z}, constant_field(display, 2.0), cam, DefocusOptions{});
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("depth"), std::string::npos) << r.message();

    // Absurd settings.
    for (auto bad : {std::function<void(DefocusOptions&)>([](DefocusOptions& d) { d.diffusion.adi_steps = -1; }),
                     std::function<void(DefocusOptions&)>([](DefocusOptions& d) { d.diffusion.max_radius = -1; }),
                     std::function<void(DefocusOptions&)>([](DefocusOptions& d) { d.diffusion.explicit_safety = 0.5; }),
                     std::function<void(DefocusOptions&)>([](DefocusOptions& d) { d.roi = Roi{10, 10, 5, 20}; })}) {
        DefocusOptions d;
        bad(d);
        r = defocus_layers({ok}, constant_field(display, 2.0), cam, d);
        EXPECT_FALSE(r);
        EXPECT_NE(r.message().find("defocus:"), std::string::npos) << r.message();
    }
}

TEST(defocus, CancelStopsTheWork) {
    const Roi display{0, 0, 80, 60};
    Layer l = make_layer(display, display, [](int x, int y) { return Rgba{texture(x, y, 0), 0, 0, 1}; });
    Exec e;
    e.cancelled = [] { return true; };
    auto r = defocus_layers({l}, constant_field(display, 8.0), test_camera(display), {}, nullptr, e);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("cancelled"), std::string::npos) << r.message();
}

TEST(defocus, ProgressIsReportedAndReachesOne) {
    const Roi display{0, 0, 80, 60};
    Layer l = make_layer(display, display, [](int x, int y) { return Rgba{texture(x, y, 0), 0, 0, 1}; });
    std::vector<double> seen;
    std::mutex mu;
    Exec e;
    e.progress = [&](double f) {
        std::lock_guard<std::mutex> lock(mu);
        seen.push_back(f);
    };
    auto r = defocus_layers({l}, constant_field(display, 8.0), test_camera(display), {}, nullptr, e);
    ASSERT_TRUE(r) << r.message();
    ASSERT_FALSE(seen.empty());
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
    for (double f : seen) {
        EXPECT_GE(f, 0.0);
        EXPECT_LE(f, 1.0);
    }
}
