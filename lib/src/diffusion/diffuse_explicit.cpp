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

    // All planes advance together, one iteration at a time, so every
    // conductance is loaded once per iteration for all of them; interior
    // pixels take a branch-free loop the compiler vectorises, the one-pixel
    // frame the checked one. Ping-pong buffers, no copies between iterations.
    const int nc = int(planes.size());
    std::vector<std::vector<float>> next(planes.size());
    for (auto& v : next) v.resize(n);
    std::vector<float*> cur(planes.begin(), planes.end());
    std::vector<float*> nxt(planes.size(), nullptr);
    for (int c = 0; c < nc; ++c) nxt[std::size_t(c)] = next[std::size_t(c)].data();
    auto checked = [&](const float* u, float* out, int x, int y) {
        const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
        const float up = u[i];
        float acc = 0.0f;
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
        out[i] = up + acc;
    };
    bool cancelled = false;
    for (int it = 0; it < iters; ++it) {
        bool ok = parallel_for(exec, H, [&](long y0, long y1) {
            const ScopedFlushDenormals ftz;
            for (long yl = y0; yl < y1; ++yl) {
                const int y = int(yl);
                for (int c = 0; c < nc; ++c) {
                    const float* __restrict u = cur[std::size_t(c)];
                    float* __restrict out = nxt[std::size_t(c)];
                    if (y == 0 || y + 1 == H || W < 3) {
                        for (int x = 0; x < W; ++x) checked(u, out, x, y);
                        continue;
                    }
                    checked(u, out, 0, y);
                    const std::size_t row = std::size_t(y) * std::size_t(W);
                    const float* __restrict ce_r = ce.data() + row;
                    const float* __restrict cs_r = cs.data() + row;
                    const float* __restrict cse_r = cse.data() + row;
                    const float* __restrict csw_r = csw.data() + row;
                    const float* __restrict cs_n = cs_r - W;
                    const float* __restrict cse_n = cse_r - W;
                    const float* __restrict csw_n = csw_r - W;
                    const float* __restrict um = u + row - W;
                    const float* __restrict u0 = u + row;
                    const float* __restrict us = u + row + W;
                    float* __restrict o = out + row;
                    for (int x = 1; x + 1 < W; ++x) {
                        const float up = u0[x];
                        const float acc = ce_r[x] * (u0[x + 1] - up) + ce_r[x - 1] * (u0[x - 1] - up) +
                                          cs_r[x] * (us[x] - up) + cse_r[x] * (us[x + 1] - up) +
                                          csw_r[x] * (us[x - 1] - up) + cs_n[x] * (um[x] - up) +
                                          cse_n[x - 1] * (um[x - 1] - up) + csw_n[x + 1] * (um[x + 1] - up);
                        o[x] = up + acc;
                    }
                    checked(u, out, W - 1, y);
                }
            }
        }, 8);
        if (!ok) {
            cancelled = true;
            break;
        }
        std::swap(cur, nxt);
    }
    // The caller's planes hold the last complete iterate (cancelled or not).
    for (int c = 0; c < nc; ++c)
        if (cur[std::size_t(c)] != planes[std::size_t(c)]) std::copy(cur[std::size_t(c)], cur[std::size_t(c)] + n, planes[std::size_t(c)]);
    if (cancelled) return Status::cancelled("diffusion");
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
