// The defocus pipeline's operational guarantees: a sub-region render equals
// the crop of the whole render (to 1e-4 of the peak), the two solvers agree
// on a varying field (2% relative L2), results are bit-identical for any
// thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "defocus_test_helpers.h"
#include "gdof/defocus.h"

using namespace gdof;
using namespace gdof::test;

namespace {

const Roi kDisplay{0, 0, 240, 160};

// A soft-edged textured foreground blob over a textured opaque background.
std::vector<Layer> scene() {
    Layer fg = make_layer(Roi{40, 20, 180, 130}, kDisplay, [](int x, int y) {
        const double d = std::hypot((x - 110) / 60.0, (y - 75) / 40.0);
        const float a = float(std::clamp((1.0 - d) * 8.0, 0.0, 1.0));
        return Rgba{a * texture(x, y, 0), a * texture(x, y, 1), a * 0.2f, a};
    }, 2.0, "fg");
    Layer bg = make_layer(kDisplay, kDisplay, [](int x, int y) {
        return Rgba{texture(x, y, 2), texture(x + 5, y, 1), texture(x, y + 3, 0), 1.0f};
    }, 8.0, "bg");
    return {fg, bg};
}

// Radius from 0 (left, sharp) to `rmax` (right), with a bump: every layer sees
// a varying blur and sharp insulating parts.
BlurField varying_field(double rmax) {
    return map_field(kDisplay, [](int x, int y) {
        const double t = std::clamp((x - 30) / 180.0, 0.0, 1.0);
        return float(t * (0.8 + 0.2 * std::sin(y * 0.05)));
    }, rmax);
}

Image render(const std::vector<Layer>& layers, const BlurField& field, DiffusionSolver solver, int threads = 0,
             const Roi& roi = {}) {
    DefocusOptions s;
    s.diffusion.solver = solver;
    s.roi = roi;
    Exec e;
    e.nthreads = threads;
    auto r = defocus_layers(layers, field, test_camera(kDisplay), s, nullptr, e);
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r).value() : Image();
}

double rel_l2(const Image& a, const Image& b) {
    double num = 0, den = 0;
    for (int c = 0; c < 4; ++c)
        for (int y = a.data_window().y0; y < a.data_window().y1; ++y)
            for (int x = a.data_window().x0; x < a.data_window().x1; ++x) {
                const double d = value_at(a, c, x, y) - value_at(b, c, x, y);
                num += d * d;
                den += value_at(b, c, x, y) * value_at(b, c, x, y);
            }
    return std::sqrt(num / den);
}

double peak(const Image& img) {
    double m = 0;
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i) m = std::max(m, double(std::abs(img.plane(c)[i])));
    return m;
}

}  // namespace

TEST(defocus_roi, SolversAgreeOnAVaryingField) {
    const auto layers = scene();
    const BlurField field = varying_field(12.0);
    const Image adi = render(layers, field, DiffusionSolver::Adi);
    const Image expl = render(layers, field, DiffusionSolver::Explicit);
    ASSERT_EQ(adi.data_window(), expl.data_window());
    const double e = rel_l2(adi, expl);
    std::printf("[ measured ] explicit vs adi, varying field 0..12 px, two layers: relative L2 %.4f%%\n", 100 * e);
    EXPECT_LT(e, 0.02);  // the documented tolerance (docs/diffusion.md)
}

TEST(defocus_roi, BitIdenticalForAnyThreadCount) {
    const auto layers = scene();
    const BlurField field = varying_field(10.0);
    for (auto solver : {DiffusionSolver::Adi, DiffusionSolver::Explicit}) {
        const Image one = render(layers, field, solver, 1);
        const Image four = render(layers, field, solver, 4);
        const Image all = render(layers, field, solver, 0);
        EXPECT_TRUE(bit_identical(one, four)) << to_string(solver);
        EXPECT_TRUE(bit_identical(one, all)) << to_string(solver);
    }
}

TEST(defocus_roi, SubRegionEqualsTheCropOfTheWholeRender) {
    const auto layers = scene();
    const Roi rois[] = {
        {90, 60, 150, 100},   // interior, across the foreground's edge
        {0, 0, 50, 40},       // a corner of the display
        {200, 120, 270, 190}, // partly outside the display (strongest blur side)
        {120, 80, 121, 81},   // a single pixel
        {-40, -40, -10, -10}, // outside everything: transparent
    };
    double worst = 0;
    for (auto solver : {DiffusionSolver::Adi, DiffusionSolver::Explicit})
        for (double rmax : {4.0, 20.0}) {
            const BlurField field = varying_field(rmax);
            const Image full = render(layers, field, solver);
            const double pk = peak(full);
            for (const Roi& roi : rois) {
                const Image sub = render(layers, field, solver, 0, roi);
                ASSERT_EQ(sub.data_window(), roi);
                EXPECT_EQ(sub.display_window(), kDisplay);
                const double d = max_abs_diff(sub, full, roi) / pk;
                worst = std::max(worst, d);
                EXPECT_LT(d, 1e-4) << to_string(solver) << " R=" << rmax << " roi " << to_string(roi);
            }
        }
    std::printf("[ measured ] sub-region vs crop of the whole render: max |difference| = %.3g of the peak\n", worst);
}

TEST(defocus_roi, SubRegionSkipsLayersThatCannotReachIt) {
    // A blurred layer far from the requested region is not diffused at all.
    Layer far_fg = make_layer(Roi{0, 0, 30, 30}, kDisplay, [](int, int) { return Rgba{1, 0, 0, 1}; }, 2.0);
    Layer bg = make_layer(kDisplay, kDisplay, [](int, int) { return Rgba{0, 0, 1, 1}; }, 8.0);
    auto field = BlurField::parse(R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": 5,
        "min": [-1000, -1000, 1], "max": [1000, 1000, 3]}})");
    ASSERT_TRUE(field) << field.message();
    DefocusOptions s;
    s.roi = Roi{150, 100, 200, 150};
    DefocusStats st;
    auto r = defocus_layers({far_fg, bg}, *field, test_camera(kDisplay), s, &st);
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(st.pixels_diffused, 0u);
    EXPECT_EQ(st.layers_sharp, 1);
    for (int y = 100; y < 150; ++y)
        for (int x = 150; x < 200; ++x) ASSERT_EQ(r->at(2, x, y), 1.0f);
}

// The whole result is made one layer at a time (each made, diffused and
// dropped); a sub-region makes every layer first. Asked for the whole
// result's window, the sub-region path must give the same bits, for a layer
// that reaches beyond another's window (the result is cropped at the end).
TEST(defocus_roi, StreamedWholeResultEqualsTheRegionPathOverItsWindow) {
    auto layers = scene();
    layers.push_back(make_layer(Roi{150, 100, 200, 150}, kDisplay, [](int x, int y) {
        return Rgba{0.3f * texture(x, y, 0), 0.2f, 0.1f, 0.5f};
    }, 20.0, "far patch"));
    layers[1].image = Image(layers[1].image.channels(), Roi{}, kDisplay);  // an empty layer
    for (const BlurField& field : {varying_field(9.0), constant_field(kDisplay, 4.0)}) {
        const Image whole = render(layers, field, DiffusionSolver::Auto);
        const Image region = render(layers, field, DiffusionSolver::Auto, 0, whole.data_window());
        ASSERT_EQ(whole.data_window(), region.data_window());
        EXPECT_TRUE(bit_identical(whole, region));
    }
}
