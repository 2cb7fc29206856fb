// Diffusion solver speed against the blur radius: explicit (cost ~ R^2) and
// ADI (cost ~ its step count, clamp(8 R, 4, 64)) on a 640x360 four-plane
// layer with a constant radius. The crossover sets DiffusionSolver::Auto's
// threshold (kAdiStepCost in gdof/diffusion.h).
//
//   bench_solvers [--benchmark_...]
#include <benchmark/benchmark.h>

#include <vector>

#include "gdof/diffusion.h"

namespace {

constexpr int W = 640, H = 360;

void run_solver(benchmark::State& state, gdof::DiffusionSolver solver) {
    const float radius = float(state.range(0));
    const gdof::Roi window{0, 0, W, H};
    std::vector<float> r(window.npixels(), radius);
    std::vector<float> planes(4 * r.size());
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < r.size(); ++i)
            planes[std::size_t(c) * r.size() + i] = float((i * 2654435761u + std::size_t(c)) % 1000) / 1000.0f;
    gdof::DiffusionOptions s;
    s.solver = solver;
    for (auto _ : state) {
        auto st = gdof::diffuse_planes(gdof::ImageView::planar(planes.data(), 4, window),
                                       gdof::ConstImageView::planar(r.data(), 1, window), s);
        if (!st.is_ok()) state.SkipWithError(st.message().c_str());
        benchmark::DoNotOptimize(planes[0]);
    }
    state.counters["explicit_iters"] = gdof::explicit_iterations(radius, s);
    state.counters["adi_steps"] = gdof::adi_steps_for(radius, s);
}

void BM_explicit(benchmark::State& state) { run_solver(state, gdof::DiffusionSolver::Explicit); }
void BM_adi(benchmark::State& state) { run_solver(state, gdof::DiffusionSolver::Adi); }

#define RADII ->Arg(2)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Arg(12)->Arg(14)->Arg(16)->Arg(20)->Arg(24)->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime()
BENCHMARK(BM_explicit) RADII;
BENCHMARK(BM_adi) RADII;

}  // namespace

BENCHMARK_MAIN();
