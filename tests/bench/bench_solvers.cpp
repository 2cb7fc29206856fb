// Diffusion solver speed against the blur radius: explicit (cost ~ R^2) and
// ADI (cost ~ its step count, clamp(8 R, 4, 64)) on a 640x360 four-plane
// layer with a constant radius. The crossover sets DiffusionSolver::Auto's
// threshold (kAutoExplicitMaxRadius in lib/src/diffusion.cpp).
//
//   bench_solvers [--benchmark_...]
#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "gdof/diffusion.h"

namespace {

constexpr int W = 640, H = 360;

void run_solver(benchmark::State& state, gdof::DiffusionSolver solver) {
    const float radius = float(state.range(0));
    std::vector<float> r(std::size_t(W) * H, radius);
    std::array<std::vector<float>, 4> planes;
    for (int c = 0; c < 4; ++c) {
        planes[c].resize(r.size());
        for (std::size_t i = 0; i < r.size(); ++i) planes[c][i] = float((i * 2654435761u + c) % 1000) / 1000.0f;
    }
    std::array<float*, 4> ptr{planes[0].data(), planes[1].data(), planes[2].data(), planes[3].data()};
    gdof::DiffusionOptions s;
    s.solver = solver;
    for (auto _ : state) {
        auto st = gdof::diffuse_planes(ptr, W, H, r.data(), s);
        if (!st.is_ok()) state.SkipWithError(st.message().c_str());
        benchmark::DoNotOptimize(planes[0][0]);
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
