// The reference solver: repeated 3x3 averaging (an explicit Euler step of the
// heat equation with the isotropic 9-point Laplacian), as in the paper. Every
// pixel exchanges with its 8 neighbours through conductance min(D_p, D_q);
// the time step keeps all weights non-negative, so it is stable by
// construction, and fluxes are antisymmetric, so totals are conserved.
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/flush_denormals.h"
#include "diffusion/solver_planes.h"
#include "gdof/diffusion.h"

namespace gdof {

namespace {
// Isotropic 9-point Laplacian weights (1/6)[1 4 1; 4 -20 4; 1 4 1]: its second
// moment per axis equals the 5-point stencil's (2), so variance per step is 2 D dt.
constexpr float kEdge = 4.0f / 6.0f;
constexpr float kDiag = 1.0f / 6.0f;

// The solver on row-major planes of width x height.
Status explicit_kernel(std::span<float* const> planes, int width, int height, const float* diffusivity,
                       const DiffusionOptions& settings, const Exec& exec) {
    const int W = width, H = height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    float dmax = 0.0f;
    for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, diffusivity[i]);
    // iterations from the largest blur: dt * dmax * 10/3 <= 1 / safety
    const double rmax = radius_from_diffusivity(dmax);
    const int iters = explicit_iterations(rmax, settings);
    const float dt = float(1.0 / iters);

    // Link conductances (times dt), each stored once at the link's first pixel:
    // east (x+1), south (y+1), south-east (x+1, y+1), south-west (x-1, y+1).
    std::vector<float> ce(n, 0.0f), cs(n, 0.0f), cse(n, 0.0f), csw(n, 0.0f);
    auto D = [&](int x, int y) { return diffusivity[std::size_t(y) * std::size_t(W) + std::size_t(x)]; };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            float d = D(x, y);
            if (x + 1 < W) ce[i] = dt * kEdge * std::min(d, D(x + 1, y));
            if (y + 1 < H) cs[i] = dt * kEdge * std::min(d, D(x, y + 1));
            if (x + 1 < W && y + 1 < H) cse[i] = dt * kDiag * std::min(d, D(x + 1, y + 1));
            if (x > 0 && y + 1 < H) csw[i] = dt * kDiag * std::min(d, D(x - 1, y + 1));
        }

    std::vector<float> next(n);
    for (float* plane : planes) {
        for (int it = 0; it < iters; ++it) {
            const float* u = plane;
            bool ok = parallel_for(exec, H, [&](long y0, long y1) {
                const ScopedFlushDenormals ftz;
                for (long yl = y0; yl < y1; ++yl) {
                    const int y = int(yl);
                    for (int x = 0; x < W; ++x) {
                        const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                        const float up = u[i];
                        double acc = 0.0;
                        if (x + 1 < W) acc += ce[i] * (u[i + 1] - up);
                        if (x > 0) acc += ce[i - 1] * (u[i - 1] - up);
                        if (y + 1 < H) {
                            const std::size_t s = i + std::size_t(W);
                            acc += cs[i] * (u[s] - up);
                            if (x + 1 < W) acc += cse[i] * (u[s + 1] - up);
                            if (x > 0) acc += csw[i] * (u[s - 1] - up);
                        }
                        if (y > 0) {
                            const std::size_t nn = i - std::size_t(W);
                            acc += cs[nn] * (u[nn] - up);
                            if (x > 0) acc += cse[nn - 1] * (u[nn - 1] - up);
                            if (x + 1 < W) acc += csw[nn + 1] * (u[nn + 1] - up);
                        }
                        next[i] = float(up + acc);
                    }
                }
            }, 8);
            if (!ok) return Status::cancelled("diffusion");
            std::copy(next.begin(), next.end(), plane);
        }
    }
    return Status::ok();
}

}  // namespace

Status diffuse_explicit(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                        const Exec& exec) {
    return diffusion_detail::run_solver_kernel(planes, diffusivity, [&](std::span<float* const> p, int w, int h, const float* d) {
        return explicit_kernel(p, w, h, d, settings, exec);
    });
}

}  // namespace gdof
