// DiffusionSolver::Auto: the cost model picks explicit where its R^2 iteration
// count is cheaper than ADI's steps (kAdiStepCost each) and ADI above; the
// result is then bit for bit that solver's; in the defocus pipeline each layer
// decides from its own largest radius (stats count them), and the image stays
// within the solvers' documented agreement (2% relative L2).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "defocus_test_helpers.h"
#include "diffusion/diffusion_test_helpers.h"
#include "gdof/defocus.h"
#include "gdof/diffusion.h"

using namespace gdof;
using namespace gdof::test;

namespace {

std::array<std::vector<float>, 2> textured(int w, int h) {
    std::array<std::vector<float>, 2> p;
    for (int c = 0; c < 2; ++c) {
        p[std::size_t(c)].resize(std::size_t(w) * h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) p[std::size_t(c)][std::size_t(y) * w + x] = texture(x, y, c);
    }
    return p;
}

std::array<std::vector<float>, 2> diffused(int w, int h, float radius, DiffusionOptions s) {
    auto p = textured(w, h);
    std::vector<float> r(std::size_t(w) * h, radius);
    r[0] = 0.0f;  // a varying map: the choice follows its largest radius
    EXPECT_TRUE(test::diffuse_vectors({&p[0], &p[1]}, w, h, r, s).is_ok());
    return p;
}

}  // namespace

TEST(diffusion_auto, CostModelPicksTheCheaperSolver) {
    DiffusionOptions s;  // the default is Auto
    ASSERT_EQ(s.solver, DiffusionSolver::Auto);
    for (double R : {0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 15.5, 15.7, 30.0, 42.9, 43.0, 60.0, 200.0}) {
        const bool explicit_cheaper = explicit_iterations(R, s) <= kAdiStepCost * adi_steps_for(R, s);
        EXPECT_EQ(choose_solver(R, s), explicit_cheaper ? DiffusionSolver::Explicit : DiffusionSolver::Adi) << R;
    }
    // The documented crossover with default settings: explicit up to 42.9 px
    // (ceil(5/12 R^2) = 767 iterations against 64 ADI steps at a cost of 12).
    EXPECT_EQ(choose_solver(42.9, s), DiffusionSolver::Explicit);
    EXPECT_EQ(choose_solver(43.0, s), DiffusionSolver::Adi);
    // Fewer ADI steps make ADI cheaper: at 12 px (60 iterations vs 4 steps).
    s.adi_steps = 4;
    EXPECT_EQ(choose_solver(12.0, s), DiffusionSolver::Adi);
    // A fixed solver is never overridden.
    s.solver = DiffusionSolver::Explicit;
    EXPECT_EQ(choose_solver(200.0, s), DiffusionSolver::Explicit);
    s.solver = DiffusionSolver::Adi;
    EXPECT_EQ(choose_solver(0.5, s), DiffusionSolver::Adi);
    EXPECT_EQ(parse_diffusion_solver("auto").value(), DiffusionSolver::Auto);
    EXPECT_STREQ(to_string(DiffusionSolver::Auto), "auto");
}

TEST(diffusion_auto, RunsExactlyTheChosenSolver) {
    const int W = 61, H = 47;
    DiffusionOptions a, e, i;
    e.solver = DiffusionSolver::Explicit;
    i.solver = DiffusionSolver::Adi;
    // Small blur: explicit; large: ADI. The pair differs by more than rounding,
    // so equality shows which one ran.
    for (float R : {3.0f, 50.0f}) {
        const auto got = diffused(W, H, R, a), ex = diffused(W, H, R, e), ad = diffused(W, H, R, i);
        ASSERT_NE(ex, ad) << R;
        EXPECT_EQ(got, R < 42.9f ? ex : ad) << R;
    }
}

TEST(diffusion_auto, EachLayerChoosesByItsOwnBlur) {
    const Roi display{0, 0, 200, 120};
    // Foreground over x < 100 at 3 px; the background reaches 50 px on the right.
    Layer fg = make_layer(Roi{20, 20, 90, 100}, display, [](int x, int y) {
        return Rgba{texture(x, y, 0), texture(x, y, 1), 0.3f, 1.0f};
    }, 2.0, "fg");
    Layer bg = make_layer(display, display, [](int x, int y) {
        return Rgba{texture(x, y, 2), 0.5f, texture(x, y + 3, 0), 1.0f};
    }, 8.0, "bg");
    const BlurField field = map_field(display, [](int x, int) { return x < 100 ? 3.0f : 50.0f; });
    auto render = [&](DiffusionSolver solver, DefocusStats* st) {
        DefocusOptions s;
        s.diffusion.solver = solver;
        s.diffusion.pyramid = false;  // the solvers themselves, on every layer
        auto r = defocus_layers({fg, bg}, field, test_camera(display), s, st);
        EXPECT_TRUE(r) << r.message();
        return std::move(r).value();
    };
    DefocusStats st;
    const Image autos = render(DiffusionSolver::Auto, &st);
    EXPECT_EQ(st.layers_explicit, 1);
    EXPECT_EQ(st.layers_adi, 1);
    EXPECT_NE(st.report().find("1 explicit, 1 adi"), std::string::npos) << st.report();
    DefocusStats se, sa;
    const Image ex = render(DiffusionSolver::Explicit, &se), ad = render(DiffusionSolver::Adi, &sa);
    EXPECT_EQ(se.layers_explicit, 2);
    EXPECT_EQ(sa.layers_adi, 2);
    double num = 0, den = 0;
    for (int c = 0; c < 4; ++c)
        for (int y = 0; y < display.y1; ++y)
            for (int x = 0; x < display.x1; ++x) {
                const double d = value_at(autos, c, x, y) - value_at(ex, c, x, y);
                num += d * d;
                den += value_at(ex, c, x, y) * value_at(ex, c, x, y);
            }
    EXPECT_LT(std::sqrt(num / den), 0.02);
    EXPECT_FALSE(bit_identical(autos, ex));  // the background ran ADI
    EXPECT_FALSE(bit_identical(autos, ad));  // the foreground ran explicit
}
