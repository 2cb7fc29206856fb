// The fast solver: alternating-direction implicit Euler. Each of K sub-steps
// solves (I - dt Lx) u' = u row by row, then (I - dt Ly) u'' = u' column by
// column, each a symmetric tridiagonal system (Thomas algorithm) with the
// conductances of the explicit solver (min(D_p, D_q); conductance.h). The matrices are
// M-matrices with unit column sums: unconditionally stable, positivity
// preserving and conservative, at a cost independent of the blur size.
// Every step has the exact variance; the kernel's shape approaches a
// Gaussian as K grows (measured: relative L2 against the analytic Gaussian
// about 0.45 / K for large radii, see docs/diffusion.md).
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/flush_denormals.h"
#include "diffusion/conductance.h"
#include "diffusion/solver_planes.h"
#include "gdof/diffusion.h"

namespace gdof {

namespace {

constexpr int kColumnBlock = 16;

// LU factors of the tridiagonal matrix with off-diagonals -g[i] between i
// and i+1 and diagonal 1 + g[i-1] + g[i], for `lanes` independent systems
// stored interleaved (element i of lane l at i * lanes + l). g has n-1 rows.
void factor(int n, int lanes, const double* g, double* cp, double* inv_m) {
    for (int l = 0; l < lanes; ++l) {
        double gprev = 0.0, cprev = 0.0;
        for (int i = 0; i < n; ++i) {
            const std::size_t k = std::size_t(i) * lanes + l;
            const double gi = i + 1 < n ? g[k] : 0.0;
            const double m = 1.0 + gprev + gi + gprev * cprev;  // b_i - a_i cp_{i-1}
            inv_m[k] = 1.0 / m;
            cp[k] = -gi * inv_m[k];
            cprev = cp[k];
            gprev = gi;
        }
    }
}

// Solves in place for x (same interleaved layout) with the factors above.
void solve(int n, int lanes, const double* g, const double* cp, const double* inv_m, double* x) {
    for (int l = 0; l < lanes; ++l) x[l] *= inv_m[l];
    for (int i = 1; i < n; ++i) {
        const std::size_t k = std::size_t(i) * lanes, kp = k - std::size_t(lanes);
        for (int l = 0; l < lanes; ++l) x[k + l] = (x[k + l] + g[kp + l] * x[kp + l]) * inv_m[k + l];
    }
    for (int i = n - 2; i >= 0; --i) {
        const std::size_t k = std::size_t(i) * lanes, kn = k + std::size_t(lanes);
        for (int l = 0; l < lanes; ++l) x[k + l] -= cp[k + l] * x[kn + l];
    }
}

}  // namespace

int adi_steps_for(double max_radius_px, const DiffusionOptions& settings) {
    if (settings.adi_steps > 0) return settings.adi_steps;
    return std::clamp(int(std::ceil(8.0 * max_radius_px)), 4, 64);
}

namespace {

// The solver on row-major planes of width x height.
Status adi_kernel(std::span<float* const> planes, int width, int height, const float* diffusivity,
                  const DiffusionOptions& settings, const Exec& exec, diffusion_detail::Conductance rule) {
    const int W = width, H = height, nc = int(planes.size());
    float dmax = 0.0f;
    for (std::size_t i = 0; i < std::size_t(W) * std::size_t(H); ++i) dmax = std::max(dmax, diffusivity[i]);
    const int K = adi_steps_for(radius_from_diffusivity(dmax), settings);
    const double dt = 1.0 / K;
    auto D = [&](int x, int y) { return diffusivity[std::size_t(y) * std::size_t(W) + std::size_t(x)]; };
    auto G = [&](float a, float b) { return double(diffusion_detail::link(a, b, rule)); };
    const long nblocks = (W + kColumnBlock - 1) / kColumnBlock;

    for (int step = 0; step < K; ++step) {
        // Rows: one system per row, all channels as lanes of the same matrix.
        bool ok = parallel_for(exec, H, [&](long y0, long y1) {
            const ScopedFlushDenormals ftz;
            const std::size_t n = std::size_t(W);
            std::vector<double> g(n), cp(n), inv_m(n), x(n * std::size_t(nc));
            for (long yl = y0; yl < y1; ++yl) {
                const int y = int(yl);
                bool any = false;
                for (int i = 0; i + 1 < W; ++i) {
                    g[std::size_t(i)] = dt * G(D(i, y), D(i + 1, y));
                    any = any || g[std::size_t(i)] > 0.0;
                }
                if (!any) continue;  // an all-sharp row is untouched
                factor(W, 1, g.data(), cp.data(), inv_m.data());
                const std::size_t row = std::size_t(y) * n;
                for (int c = 0; c < nc; ++c) {
                    const float* p = planes[std::size_t(c)] + row;
                    double* xc = x.data() + std::size_t(c) * n;
                    for (std::size_t i = 0; i < n; ++i) xc[i] = p[i];
                    solve(W, 1, g.data(), cp.data(), inv_m.data(), xc);
                    float* q = planes[std::size_t(c)] + row;
                    for (std::size_t i = 0; i < n; ++i) q[i] = float(xc[i]);
                }
            }
        });
        if (!ok) return Status::cancelled("diffusion");
        // Columns: a block of adjacent columns solved together as lanes, so
        // every load is a contiguous run of a row.
        ok = parallel_for(exec, nblocks, [&](long b0, long b1) {
            const ScopedFlushDenormals ftz;
            const std::size_t n = std::size_t(H) * kColumnBlock;
            std::vector<double> g(n), cp(n), inv_m(n), x(n);
            for (long b = b0; b < b1; ++b) {
                const int xb = int(b) * kColumnBlock, lanes = std::min(kColumnBlock, W - xb);
                bool any = false;
                for (int j = 0; j + 1 < H; ++j)
                    for (int l = 0; l < lanes; ++l) {
                        double gv = dt * G(D(xb + l, j), D(xb + l, j + 1));
                        g[std::size_t(j) * lanes + l] = gv;
                        any = any || gv > 0.0;
                    }
                if (!any) continue;
                factor(H, lanes, g.data(), cp.data(), inv_m.data());
                for (int c = 0; c < nc; ++c) {
                    float* p = planes[std::size_t(c)];
                    for (int j = 0; j < H; ++j) {
                        const float* src = p + std::size_t(j) * std::size_t(W) + std::size_t(xb);
                        for (int l = 0; l < lanes; ++l) x[std::size_t(j) * lanes + l] = src[l];
                    }
                    solve(H, lanes, g.data(), cp.data(), inv_m.data(), x.data());
                    for (int j = 0; j < H; ++j) {
                        float* dst = p + std::size_t(j) * std::size_t(W) + std::size_t(xb);
                        for (int l = 0; l < lanes; ++l) dst[l] = float(x[std::size_t(j) * lanes + l]);
                    }
                }
            }
        });
        if (!ok) return Status::cancelled("diffusion");
    }
    return Status::ok();
}

}  // namespace

Status diffusion_detail::diffuse_adi(const ImageView& planes, const ConstImageView& diffusivity,
                                     const DiffusionOptions& settings, const Exec& exec, Conductance conductance) {
    return run_solver_kernel(planes, diffusivity, [&](std::span<float* const> p, int w, int h, const float* d) {
        return adi_kernel(p, w, h, d, settings, exec, conductance);
    });
}

Status diffuse_adi(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                   const Exec& exec) {
    return diffusion_detail::diffuse_adi(planes, diffusivity, settings, exec, diffusion_detail::Conductance::Min);
}

}  // namespace gdof
