// Method 2 speed: compositing 4096x2160 from a 24-image stack against a plain
// copy of one reference in the same run (the issue's target: within 3x).
//
//   bench_compositing [--benchmark_...]    (env GDOF_BENCH_DIR: where the stack
//   is written once and reused; default /tmp/gdof_bench_stack)
//
// The stack: 24 tiled (64 x 64) half RGBA EXRs, focus 0.8..30 m x f/2.8, f/8,
// near/far from the thin lens. Desired focus: a tilted pair of B-spline
// surfaces whose near/far sweep the whole stack across the frame, so most
// references are used.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "gdof/compositing.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/image_io.h"
#include "gdof/io/stack_reader.h"

namespace {

namespace fs = std::filesystem;
constexpr int W = 4096, H = 2160, N = 24;

std::string bench_dir() {
    const char* e = std::getenv("GDOF_BENCH_DIR");
    return e ? e : "/tmp/gdof_bench_stack";
}

const gdof::FocalStack& stack() {
    static gdof::FocalStack s = [] {
        const std::string dir = bench_dir();
        fs::create_directories(dir);
        std::string refs;
        for (int i = 0; i < N; ++i) {
            const double focus = 0.8 * std::pow(30.0 / 0.8, double(i / 2) / 11.0);
            const double fn = i % 2 ? 8.0 : 2.8;
            char name[64];
            std::snprintf(name, sizeof name, "ref.%04d.exr", i + 1);
            refs += std::string(i ? "," : "") + "{\"file\": \"" + name + "\", \"focus_distance\": " +
                    std::to_string(focus) + ", \"f_number\": " + std::to_string(fn) + "}";
            const std::string path = dir + "/" + name;
            if (fs::exists(path)) continue;
            gdof::Image img = gdof::Image::with_channels({"R", "G", "B", "A"}, {0, 0, W, H});
            for (int c = 0; c < 4; ++c)
                if (auto st = img.set_channel_type(c, gdof::PixelType::Half); !st) std::fprintf(stderr, "%s\n", st.message().c_str());
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    img.at(0, x, y) = float(i) / N + 0.1f * std::sin(0.05f * x + i);
                    img.at(1, x, y) = 0.5f + 0.2f * std::cos(0.03f * y - i);
                    img.at(2, x, y) = float((x ^ y) & 255) / 255.0f;
                    img.at(3, x, y) = 1.0f;
                }
            img.storage.tile_width = img.storage.tile_height = 64;
            img.storage.compression = "zip";
            if (auto st = gdof::io::write_flat(path, img); !st) std::fprintf(stderr, "%s\n", st.message().c_str());
        }
        const std::string json = "{\"gdof_stack\": 1, \"coc_px\": 2, \"focal_length_mm\": 50, \"sensor_width_mm\": 36, "
                                 "\"width\": " + std::to_string(W) + ", \"height\": " + std::to_string(H) +
                                 ", \"references\": [" + refs + "]}";
        std::ofstream(dir + "/manifest.json") << json;
        return gdof::parse_stack_manifest(json, dir).value();
    }();
    return s;
}

gdof::FocusSurfaces surfaces() {
    // Near from 0.7 m (left) to 25 m (right), far = 1.6 x near (+ a vertical tilt).
    std::vector<double> gn, gf;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 6; ++i) {
            const double n = 0.7 * std::pow(25.0 / 0.7, i / 5.0) * (1.0 + 0.2 * j);
            gn.push_back(n);
            gf.push_back(n * 1.6);
        }
    return {gdof::BSplineSurface::create(6, 2, gn).value(), gdof::BSplineSurface::create(6, 2, gf).value()};
}

gdof::DesiredFocus desired() { return gdof::desired_from_surfaces(surfaces(), W, H).value(); }

// Plain copy of reference 0: every tile through the same reader and cache.
void BM_copy_one_reference(benchmark::State& state) {
    const auto& s = stack();
    for (auto _ : state) {
        auto reader = gdof::io::StackReader::create(s).value();
        gdof::Image out = gdof::Image::with_channels({"R", "G", "B", "A"}, {0, 0, W, H});
        const int T = 64;
        const long tx = (W + T - 1) / T, ty = (H + T - 1) / T;
        gdof::parallel_for({}, tx * ty, [&](long a, long b) {
            std::vector<float> buf(T * T * 4);
            for (long t = a; t < b; ++t) {
                const gdof::Roi r{int(t % tx) * T, int(t / tx) * T, std::min(W, int(t % tx + 1) * T),
                                  std::min(H, int(t / tx + 1) * T)};
                (void)reader->read_tile(0, r, buf.data());
                for (int y = r.y0; y < r.y1; ++y)
                    for (int x = r.x0; x < r.x1; ++x)
                        for (int c = 0; c < 4; ++c)
                            out.at(c, x, y) = buf[(std::size_t(y - r.y0) * r.width() + std::size_t(x - r.x0)) * 4 + c];
            }
        });
        benchmark::DoNotOptimize(out.plane(0));
    }
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
}

// Plain whole-file read of reference 0 (io::read_flat), for scale.
void BM_read_flat_one_reference(benchmark::State& state) {
    const auto& s = stack();
    for (auto _ : state) {
        auto img = gdof::io::read_flat(s.references[0].path);
        benchmark::DoNotOptimize(img);
    }
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
}

// Selection + tiles (surfaces evaluated once outside the loop, as the index).
void BM_composite(benchmark::State& state) {
    const auto& s = stack();
    const gdof::DesiredFocus d = desired();
    std::vector<gdof::DepthInterval> l;
    for (const auto& r : s.references) l.push_back({r.near, r.far});
    const gdof::StackIndex index = gdof::StackIndex::build(l).value();
    gdof::CompositeOptions cs;
    cs.soft_k = int(state.range(0));
    int used = 0;
    for (auto _ : state) {
        auto reader = gdof::io::StackReader::create(s).value();
        auto sel = gdof::select_references(index, d, cs).value();
        used = sel.references_used();
        auto out = gdof::composite_stack(sel, *reader, cs);
        if (!out) state.SkipWithError(out.message().c_str());
        benchmark::DoNotOptimize(out);
    }
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
    state.counters["refs_used"] = used;
}

// The surfaces at every pixel: separable (desired_from_surfaces, what
// --surfaces runs) ...
void BM_surfaces(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(desired());
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
}

// ... and point by point (BSplineSurface::evaluate per pixel: the previous
// version, the baseline of the same run).
void BM_surfaces_per_pixel(benchmark::State& state) {
    const gdof::FocusSurfaces fs = surfaces();
    std::vector<float> near(std::size_t(W) * H), far(near.size());
    for (auto _ : state) {
        gdof::parallel_for({}, H, [&](long y0, long y1) {
            for (long y = y0; y < y1; ++y)
                for (int x = 0; x < W; ++x) {
                    const double u = (x + 0.5) / W, v = (y + 0.5) / H;
                    near[std::size_t(y) * W + std::size_t(x)] = float(fs.near.evaluate(u, v));
                    far[std::size_t(y) * W + std::size_t(x)] = float(fs.far.evaluate(u, v));
                }
        }, 16);
        benchmark::DoNotOptimize(near.data());
        benchmark::DoNotOptimize(far.data());
    }
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
}

// What `gdof --composite manifest --surfaces s.json` costs: the surfaces,
// the selection and the tiles (against BM_copy_one_reference).
void BM_surfaces_and_composite(benchmark::State& state) {
    const auto& s = stack();
    std::vector<gdof::DepthInterval> l;
    for (const auto& r : s.references) l.push_back({r.near, r.far});
    const gdof::StackIndex index = gdof::StackIndex::build(l).value();
    gdof::CompositeOptions cs;
    for (auto _ : state) {
        const gdof::DesiredFocus d = desired();
        auto reader = gdof::io::StackReader::create(s).value();
        auto sel = gdof::select_references(index, d, cs).value();
        auto out = gdof::composite_stack(sel, *reader, cs);
        if (!out) state.SkipWithError(out.message().c_str());
        benchmark::DoNotOptimize(out);
    }
    state.counters["Mpixel/s"] = benchmark::Counter(double(W) * H * 1e-6 * state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_copy_one_reference)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_read_flat_one_reference)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_composite)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_surfaces)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_surfaces_per_pixel)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_surfaces_and_composite)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
