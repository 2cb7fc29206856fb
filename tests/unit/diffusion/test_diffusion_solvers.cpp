// The diffusion solvers against analytic results: a Gaussian blob of sigma0
// blurred by a Gaussian of sigma = R/2 is a Gaussian of sigma0^2 + sigma^2
// with the same total; totals are conserved; zero blur is the identity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "diffusion/diffusion_test_helpers.h"
#include "gdof/diffusion.h"

using namespace gdof;

namespace {

struct Planes {
    int w, h;
    std::vector<std::vector<float>> data;
    Planes(int w_, int h_, int n) : w(w_), h(h_), data(std::size_t(n), std::vector<float>(std::size_t(w_) * h_, 0.f)) {}
};

double gaussian2d(double x, double y, double sigma, double total) {
    return total / (2.0 * M_PI * sigma * sigma) * std::exp(-(x * x + y * y) / (2.0 * sigma * sigma));
}

double sum(const std::vector<float>& v) {
    double s = 0;
    for (float f : v) s += f;
    return s;
}

Status run(Planes& p, const std::vector<float>& radius, DiffusionSolver solver, int threads = 0) {
    DiffusionOptions s;
    s.solver = solver;
    Exec e;
    e.nthreads = threads;
    std::vector<std::vector<float>*> planes;
    for (auto& d : p.data) planes.push_back(&d);
    return test::diffuse_vectors(planes, p.w, p.h, radius, s, e);
}

class ConstantBlur : public ::testing::TestWithParam<std::tuple<DiffusionSolver, double>> {};

}  // namespace

TEST_P(ConstantBlur, EqualsAnalyticGaussianAndConservesEnergy) {
    const auto [solver, R] = GetParam();
    const double sigma = R / 2.0, sigma0 = 3.0;
    const double sigma_out = std::sqrt(sigma0 * sigma0 + sigma * sigma);
    const int size = int(2 * std::ceil(6.0 * sigma_out)) + 1;  // borders far from the blob
    const double c = size / 2;
    Planes p(size, size, 2);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            p.data[0][std::size_t(y) * size + x] = float(gaussian2d(x - c, y - c, sigma0, 1000.0));
            p.data[1][std::size_t(y) * size + x] = 1.0f;  // a constant channel must stay constant
        }
    const double before0 = sum(p.data[0]), before1 = sum(p.data[1]);
    std::vector<float> radius(std::size_t(size) * size, float(R));
    ASSERT_TRUE(run(p, radius, solver).is_ok());

    double num = 0, den = 0;
    const double inner = 3.0 * sigma_out;  // away from borders
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (std::hypot(x - c, y - c) > inner) continue;
            double ref = gaussian2d(x - c, y - c, sigma_out, 1000.0);
            double d = p.data[0][std::size_t(y) * size + x] - ref;
            num += d * d;
            den += ref * ref;
        }
    const double rel_l2 = std::sqrt(num / den);
    EXPECT_LT(rel_l2, 0.01) << "solver " << to_string(solver) << " R=" << R;
    EXPECT_NEAR(sum(p.data[0]) / before0, 1.0, 1e-4);
    EXPECT_NEAR(sum(p.data[1]) / before1, 1.0, 1e-4);
    for (float v : p.data[1]) ASSERT_NEAR(v, 1.0f, 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(Diffusion, ConstantBlur,
                         ::testing::Combine(::testing::Values(DiffusionSolver::Explicit, DiffusionSolver::Adi),
                                            ::testing::Values(2.0, 8.0, 32.0)));

TEST(Diffusion, ZeroBlurIsBitIdentical) {
    Planes p(37, 23, 4);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-5.f, 1e6f);
    for (auto& d : p.data)
        for (float& v : d) v = u(rng);
    auto copy = p.data;
    std::vector<float> radius(37 * 23, 0.0f);
    for (auto solver : {DiffusionSolver::Explicit, DiffusionSolver::Adi}) {
        ASSERT_TRUE(run(p, radius, solver).is_ok());
        EXPECT_EQ(p.data, copy);
    }
}

TEST(Diffusion, SharpPixelsAreInsulatedAndBlurredInteriorStaysOpaque) {
    // The paper's Figure 6: a rectangle of extreme blur inside a sharp opaque image.
    const int W = 200, H = 160;
    Planes p(W, H, 2);
    std::vector<float> radius(std::size_t(W) * H, 0.0f);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            std::size_t i = std::size_t(y) * W + x;
            p.data[0][i] = float((x / 8 + y / 8) % 2);  // checker colour
            p.data[1][i] = 1.0f;                          // opaque alpha
            if (x >= 50 && x < 150 && y >= 40 && y < 120) radius[i] = 60.0f;
        }
    auto before = p.data;
    for (auto solver : {DiffusionSolver::Adi, DiffusionSolver::Explicit}) {
        p.data = before;
        ASSERT_TRUE(run(p, radius, solver).is_ok());
        double inside = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                std::size_t i = std::size_t(y) * W + x;
                if (radius[i] > 0) {
                    ASSERT_GE(p.data[1][i], 0.99f) << "hole in the blurred rectangle at " << x << "," << y;
                    inside += p.data[0][i];
                } else {
                    ASSERT_EQ(p.data[0][i], before[0][i]) << "sharp pixel changed at " << x << "," << y;
                }
            }
        // the checker inside is blurred to its mean (0.5)
        EXPECT_NEAR(inside / (100.0 * 80.0), 0.5, 0.01);
        EXPECT_NEAR(p.data[0][std::size_t(80) * W + 100], 0.5f, 0.02f);
    }
}

TEST(Diffusion, SolversAgreeOnVaryingFieldAndConserveTotals) {
    const int W = 120, H = 90;
    Planes a(W, H, 4);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<float> radius(std::size_t(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            std::size_t i = std::size_t(y) * W + x;
            for (int c = 0; c < 4; ++c) a.data[std::size_t(c)][i] = ((x / 6 + y / 6) % 2) ? u(rng) : 0.2f * c;
            radius[i] = float(12.0 * (0.5 + 0.5 * std::sin(x * 0.05) * std::cos(y * 0.07)));  // 0..12 px
        }
    Planes b = a;
    std::vector<double> totals;
    for (auto& d : a.data) totals.push_back(sum(d));
    ASSERT_TRUE(run(a, radius, DiffusionSolver::Explicit).is_ok());
    ASSERT_TRUE(run(b, radius, DiffusionSolver::Adi).is_ok());
    double num = 0, den = 0;
    for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(sum(a.data[std::size_t(c)]) / totals[std::size_t(c)], 1.0, 1e-4);
        EXPECT_NEAR(sum(b.data[std::size_t(c)]) / totals[std::size_t(c)], 1.0, 1e-4);
        for (std::size_t i = 0; i < a.data[0].size(); ++i) {
            double d = a.data[std::size_t(c)][i] - b.data[std::size_t(c)][i];
            num += d * d;
            den += double(a.data[std::size_t(c)][i]) * a.data[std::size_t(c)][i];
        }
    }
    // Documented tolerance between the solvers (docs/diffusion.md): 2% relative L2.
    EXPECT_LT(std::sqrt(num / den), 0.02);
}

TEST(Diffusion, ThreadCountDoesNotChangeOneBit) {
    const int W = 97, H = 61;
    Planes a(W, H, 3);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<float> radius(std::size_t(W) * H);
    for (auto& d : a.data)
        for (float& v : d) v = u(rng);
    for (float& r : radius) r = 6.f * u(rng);
    for (auto solver : {DiffusionSolver::Explicit, DiffusionSolver::Adi}) {
        Planes one = a, many = a;
        ASSERT_TRUE(run(one, radius, solver, 1).is_ok());
        ASSERT_TRUE(run(many, radius, solver, 4).is_ok());
        EXPECT_EQ(one.data, many.data) << to_string(solver);
    }
}

TEST(Diffusion, BadRadiiAreErrorsNamingThePixel) {
    Planes p(4, 3, 1);
    std::vector<float> radius(12, 1.0f);
    radius[6] = std::nanf("");
    Status st = run(p, radius, DiffusionSolver::Adi);
    ASSERT_FALSE(st.is_ok());
    EXPECT_NE(st.message().find("(2, 1"), std::string::npos) << st.message();
    radius[6] = -1.0f;
    EXPECT_FALSE(run(p, radius, DiffusionSolver::Adi).is_ok());
    radius[6] = INFINITY;
    EXPECT_FALSE(run(p, radius, DiffusionSolver::Explicit).is_ok());
    auto parsed = parse_diffusion_solver("fast");
    ASSERT_FALSE(parsed.is_ok());
    EXPECT_NE(parsed.message().find("fast"), std::string::npos);
}
