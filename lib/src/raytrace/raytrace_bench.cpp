// Raw primary-ray throughput (the yardstick --stats compares the renderer with).
#include <atomic>
#include <chrono>
#include <limits>

#include "gdof/raytrace.h"

namespace gdof {

double raw_primary_mrays(const RayTracer& tracer, int repeats, const Exec& exec) {
    const Camera& cam = tracer.scene().camera;
    const Roi d = cam.display_window();
    const long rows = d.height();
    std::atomic<std::uint64_t> hits{0};
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = parallel_for(
        exec, rows,
        [&](long b, long e) {
            std::uint64_t h = 0;
            for (long r = b; r < e; ++r)
                for (int k = 0; k < repeats; ++k)
                    for (int x = d.x0; x < d.x1; ++x) {
                        const CameraRay ray = cam.central_ray(x + 0.5, d.y0 + int(r) + 0.5);
                        h += tracer.intersect(ray.origin, ray.direction, 0.0, std::numeric_limits<double>::infinity())
                                 .hit();
                    }
            hits += h;  // keeps the loop from being optimised away
        },
        4);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!ok || s <= 0) return 0;
    return double(d.npixels()) * repeats / s * 1e-6 + 0.0 * double(hits.load());
}

}  // namespace gdof
