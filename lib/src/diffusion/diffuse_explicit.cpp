// The reference solver: repeated 3x3 averaging (an explicit Euler step of the
// heat equation with the isotropic 9-point Laplacian), as in the paper. Every
// pixel exchanges with its 8 neighbours through conductance min(D_p, D_q)
// (or their harmonic mean on a pyramid's coarse levels: conductance.h);
// the time step keeps all weights non-negative, so it is stable by
// construction, and fluxes are antisymmetric, so totals are conserved.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "common/flush_denormals.h"
#include "common/simd_clones.h"
#include "diffusion/conductance.h"
#include "diffusion/solver_planes.h"
#include "gdof/diffusion.h"
#include "image/frame_buffer.h"

namespace gdof {

namespace {
// Isotropic 9-point Laplacian weights (1/6)[1 4 1; 4 -20 4; 1 4 1]: its second
// moment per axis equals the 5-point stencil's (2), so variance per step is 2 D dt.
constexpr float kEdge = 4.0f / 6.0f;
constexpr float kDiag = 1.0f / 6.0f;

// Link conductances (times dt) of one row y, each stored at the link's
// first pixel: east (x+1), south (y+1), south-east (x+1, y+1), south-west
// (x-1, y+1); 0 for links that leave the grid.
struct LinkRow {
    const float *ce, *cs, *cse, *csw;
};

// The conductances of the rows a band is working on, computed from the
// diffusivity as the band advances (a ring of rows, in cache), instead of
// four frame-sized arrays read on every pass.
class LinkRing {
public:
    LinkRing(const float* diffusivity, int W, int H, float dt, int slots, diffusion_detail::Conductance rule)
        : d_(diffusivity), W_(W), H_(H), dt_(dt), slots_(slots), rule_(rule), c_(4 * std::size_t(slots) * std::size_t(W)),
          row_of_(std::size_t(slots), -1) {}
    // Row y's links (computed on first use; rows are asked for in order).
    LinkRow at(int y) {
        const std::size_t slot = std::size_t(y % slots_);
        float* base = c_.data() + 4 * slot * std::size_t(W_);
        if (row_of_[slot] != y) {
            fill(y, base);
            row_of_[slot] = y;
        }
        const std::size_t w = std::size_t(W_);
        return {base, base + w, base + 2 * w, base + 3 * w};
    }

private:
    void fill(int y, float* base) const {
        const std::size_t w = std::size_t(W_);
        float *ce = base, *cs = base + w, *cse = base + 2 * w, *csw = base + 3 * w;
        const float* r0 = d_ + std::size_t(y) * w;
        const float* r1 = y + 1 < H_ ? r0 + w : nullptr;
        using diffusion_detail::Conductance;
        using diffusion_detail::link;
        // The rule outside the loop: one instance each.
        if (rule_ == Conductance::Min)
            fill_links(r0, r1, [](float a, float b) { return link(a, b, Conductance::Min); }, ce, cs, cse, csw);
        else
            fill_links(r0, r1, [](float a, float b) { return link(a, b, Conductance::Harmonic); }, ce, cs, cse, csw);
    }
    template <class Link>
    void fill_links(const float* r0, const float* r1, Link lk, float* ce, float* cs, float* cse, float* csw) const {
        const int W = W_;
        for (int x = 0; x < W; ++x) {
            const float d = r0[x];
            ce[x] = x + 1 < W ? dt_ * kEdge * lk(d, r0[x + 1]) : 0.0f;
            cs[x] = r1 ? dt_ * kEdge * lk(d, r1[x]) : 0.0f;
            cse[x] = r1 && x + 1 < W ? dt_ * kDiag * lk(d, r1[x + 1]) : 0.0f;
            csw[x] = r1 && x > 0 ? dt_ * kDiag * lk(d, r1[x - 1]) : 0.0f;
        }
    }
    const float* d_;
    int W_, H_;
    float dt_;
    int slots_;
    diffusion_detail::Conductance rule_;
    std::vector<float> c_;
    std::vector<int> row_of_;
};

// One row of one plane, one iteration: `out` from the previous iterate's
// rows above (`um`, null on the first row), at (`u0`) and below (`us`, null
// on the last row); `c` the row's links, `n` the row above's. Only columns
// [x0, x1) can change (the links elsewhere are 0): the rest is copied, which
// is what the sums give there. The interior takes a branch-free loop the
// compiler vectorises; the same sums in the same order as the border pixels'.
//
// step_row_edges does the copies and the pixels with border tests (all of
// [x0, x1) on the first and last rows) and returns the interior [xa, xb).
std::pair<int, int> step_row_edges(int W, int x0, int x1, const LinkRow& c, const LinkRow& n, const float* um,
                                   const float* u0, const float* us, float* out) {
    auto checked = [&](int x) {
        const float up = u0[x];
        float acc = 0.0f;
        if (x + 1 < W) acc += c.ce[x] * (u0[x + 1] - up);
        if (x > 0) acc += c.ce[x - 1] * (u0[x - 1] - up);
        if (us) {
            acc += c.cs[x] * (us[x] - up);
            if (x + 1 < W) acc += c.cse[x] * (us[x + 1] - up);
            if (x > 0) acc += c.csw[x] * (us[x - 1] - up);
        }
        if (um) {
            acc += n.cs[x] * (um[x] - up);
            if (x > 0) acc += n.cse[x - 1] * (um[x - 1] - up);
            if (x + 1 < W) acc += n.csw[x + 1] * (um[x + 1] - up);
        }
        out[x] = up + acc;
    };
    std::copy(u0, u0 + x0, out);
    std::copy(u0 + x1, u0 + W, out + x1);
    if (!um || !us || W < 3) {
        for (int x = x0; x < x1; ++x) checked(x);
        return {0, 0};
    }
    if (x0 == 0) checked(0);
    if (x1 == W && W > 1) checked(W - 1);
    return {std::max(1, x0), std::min(W - 1, x1)};
}

// The interior sum of one pixel (step_row's order of terms).
#define GDOF_STENCIL(um, u0, us, x)                                                                                   \
    ((u0)[x] + (ce_r[x] * ((u0)[(x) + 1] - (u0)[x]) + ce_r[(x) - 1] * ((u0)[(x) - 1] - (u0)[x]) +                  \
                cs_r[x] * ((us)[x] - (u0)[x]) + cse_r[x] * ((us)[(x) + 1] - (u0)[x]) +                              \
                csw_r[x] * ((us)[(x) - 1] - (u0)[x]) + cs_n[x] * ((um)[x] - (u0)[x]) +                              \
                cse_n[(x) - 1] * ((um)[(x) - 1] - (u0)[x]) + csw_n[(x) + 1] * ((um)[(x) + 1] - (u0)[x])))

GDOF_CLONES
void step_row(int W, int x0, int x1, const LinkRow& c, const LinkRow& n, const float* __restrict um,
              const float* __restrict u0, const float* __restrict us, float* __restrict out) {
    const auto [xa, xb] = step_row_edges(W, x0, x1, c, n, um, u0, us, out);
    const float* __restrict ce_r = c.ce;
    const float* __restrict cs_r = c.cs;
    const float* __restrict cse_r = c.cse;
    const float* __restrict csw_r = c.csw;
    const float* __restrict cs_n = n.cs;
    const float* __restrict cse_n = n.cse;
    const float* __restrict csw_n = n.csw;
    for (int x = xa; x < xb; ++x) out[x] = GDOF_STENCIL(um, u0, us, x);
}

// Four planes of one row at once (R, G, B, A): each plane's sums are
// step_row's, lane by lane in vectors of 8 (the same operations in the same
// order: the same bits), with the links loaded once for the four.
typedef float Vec8 __attribute__((vector_size(32)));

GDOF_CLONES
void step_row4(int W, int x0, int x1, const LinkRow& c, const LinkRow& n, const std::array<const float*, 4>& um,
               const std::array<const float*, 4>& u0, const std::array<const float*, 4>& us,
               const std::array<float*, 4>& out) {
    std::pair<int, int> in;
    for (int p = 0; p < 4; ++p) in = step_row_edges(W, x0, x1, c, n, um[p], u0[p], us[p], out[p]);
    const float* ce_r = c.ce;
    const float* cs_r = c.cs;
    const float* cse_r = c.cse;
    const float* csw_r = c.csw;
    const float* cs_n = n.cs;
    const float* cse_n = n.cse;
    const float* csw_n = n.csw;
    // Unaligned 8-float loads and stores by memcpy into locals: no function
    // takes or returns a vector (in the default clone that would cross an ABI
    // without AVX, which clang rejects).
    constexpr std::size_t k8 = sizeof(Vec8);
    int x = in.first;
    for (; x + 8 <= in.second; x += 8) {
        Vec8 ke, kw, ks, kse, ksw, kn, knw, kne;
        std::memcpy(&ke, ce_r + x, k8);
        std::memcpy(&kw, ce_r + x - 1, k8);
        std::memcpy(&ks, cs_r + x, k8);
        std::memcpy(&kse, cse_r + x, k8);
        std::memcpy(&ksw, csw_r + x, k8);
        std::memcpy(&kn, cs_n + x, k8);
        std::memcpy(&knw, cse_n + x - 1, k8);
        std::memcpy(&kne, csw_n + x + 1, k8);
        for (int p = 0; p < 4; ++p) {
            const float *m = um[std::size_t(p)], *a = u0[std::size_t(p)], *b = us[std::size_t(p)];
            Vec8 up, e, w, s, se, sw, nn, nw, ne;
            std::memcpy(&up, a + x, k8);
            std::memcpy(&e, a + x + 1, k8);
            std::memcpy(&w, a + x - 1, k8);
            std::memcpy(&s, b + x, k8);
            std::memcpy(&se, b + x + 1, k8);
            std::memcpy(&sw, b + x - 1, k8);
            std::memcpy(&nn, m + x, k8);
            std::memcpy(&nw, m + x - 1, k8);
            std::memcpy(&ne, m + x + 1, k8);
            const Vec8 acc = ke * (e - up) + kw * (w - up) + ks * (s - up) + kse * (se - up) + ksw * (sw - up) +
                             kn * (nn - up) + knw * (nw - up) + kne * (ne - up);
            const Vec8 r = up + acc;
            std::memcpy(out[std::size_t(p)] + x, &r, k8);
        }
    }
    for (; x < in.second; ++x)
        for (int p = 0; p < 4; ++p) out[std::size_t(p)][x] = GDOF_STENCIL(um[std::size_t(p)], u0[std::size_t(p)], us[std::size_t(p)], x);
}
#undef GDOF_STENCIL

// Iterations fused per pass over memory: a band of rows is advanced k
// iterations at once through ring buffers of three rows per intermediate
// iterate (they stay in cache), so the planes cross memory once per k
// iterations instead of once per iteration. Each band recomputes the k - 1
// rows of halo it needs on either side from the same inputs, so every value
// is the one a single-iteration sweep computes: the same bits for any band
// layout and thread count.
// Bands are tall enough that the halo is a small share of their work (at 64
// rows and 6 iterations it was a third) and short enough that every thread
// gets several (4K: 2160 rows, 9 bands; a coarse level of 300 rows, 5).
constexpr int kFused = 10;
int band_rows(int height) { return std::clamp(height / 8, 64, 256); }

// Columns [x0, x1) of a band's rows whose pixels can change: those with a
// diffusivity > 0 in rows [ya, yb) (a link with an insulating end conducts
// nothing under either rule of conductance.h, so an insulating pixel never
// changes).
struct Columns {
    int x0 = 0, x1 = 0;
};
Columns active_columns(const float* d, int W, int ya, int yb) {
    int lo = W, hi = -1;
    for (int y = ya; y < yb; ++y) {
        const float* r = d + std::size_t(y) * std::size_t(W);
        int x = 0;
        while (x < lo && !(r[x] > 0.0f)) ++x;
        if (x < lo) lo = x;
        int z = W - 1;
        while (z > hi && !(r[z] > 0.0f)) --z;
        if (z > hi) hi = z;
    }
    if (hi < lo) return {};
    return {lo, hi + 1};
}

// Advances rows [y0, y1) of `src` by k iterations into `dst` (nc planes).
// Where no diffusivity is > 0 (insulating pixels: everything stays), values
// are copied instead of summed: the same bits.
void advance_band(const float* diffusivity, int W, int H, float dt, diffusion_detail::Conductance rule,
                  std::span<float* const> src, std::span<float* const> dst, int y0, int y1, int k,
                  std::vector<float>& ring) {
    const int nc = int(src.size());
    const std::size_t rw = std::size_t(W);
    // Iterate s covers rows [lo(s), hi(s)); row t - s of iterate s is made at time t.
    auto lo = [&](int s) { return std::max(0, y0 - (k - s)); };
    auto hi = [&](int s) { return std::min(H, y1 + (k - s)); };
    // A pixel's value moves only through links with diffusivity > 0 at both
    // ends: the columns that can change anywhere in the band's reach.
    const Columns cols = active_columns(diffusivity, W, std::max(0, lo(1) - 1), std::min(H, hi(1) + 1));
    if (cols.x1 <= cols.x0) {
        for (int c = 0; c < nc; ++c)
            std::copy(src[std::size_t(c)] + std::size_t(y0) * rw, src[std::size_t(c)] + std::size_t(y1) * rw,
                      dst[std::size_t(c)] + std::size_t(y0) * rw);
        return;
    }
    // ring: (k - 1) iterates x 3 rows x nc planes.
    ring.resize(std::size_t(std::max(0, k - 1)) * 3 * std::size_t(nc) * rw);
    auto ring_row = [&](int s, int y, int c) {  // iterate s in 1..k-1
        return ring.data() + ((std::size_t(s - 1) * 3 + std::size_t(y % 3)) * std::size_t(nc) + std::size_t(c)) * rw;
    };
    // Row y of iterate s (0: src, k: dst) for plane c; null outside the image.
    auto row_of = [&](int s, int y, int c) -> float* {
        if (y < 0 || y >= H) return nullptr;
        if (s == 0) return src[std::size_t(c)] + std::size_t(y) * rw;
        if (s == k) return dst[std::size_t(c)] + std::size_t(y) * rw;
        return ring_row(s, y, c);
    };
    // At time t the rows t - 1 .. t - k are worked on, with the links of
    // rows t - k - 1 .. t - 1.
    LinkRing links(diffusivity, W, H, dt, k + 2, rule);
    const LinkRow none{nullptr, nullptr, nullptr, nullptr};
    for (int t = lo(1) + 1; t < hi(1) + k; ++t)
        for (int s = 1; s <= k; ++s) {
            const int y = t - s;
            if (y < lo(s) || y >= hi(s)) continue;
            const LinkRow above = y > 0 ? links.at(y - 1) : none;
            const LinkRow here = links.at(y);
            int c = 0;
            for (; c + 4 <= nc; c += 4) {
                std::array<const float*, 4> um, u0, us;
                std::array<float*, 4> out;
                for (int p = 0; p < 4; ++p) {
                    um[std::size_t(p)] = row_of(s - 1, y - 1, c + p);
                    u0[std::size_t(p)] = row_of(s - 1, y, c + p);
                    us[std::size_t(p)] = row_of(s - 1, y + 1, c + p);
                    out[std::size_t(p)] = row_of(s, y, c + p);
                }
                step_row4(W, cols.x0, cols.x1, here, above, um, u0, us, out);
            }
            for (; c < nc; ++c)
                step_row(W, cols.x0, cols.x1, here, above, row_of(s - 1, y - 1, c), row_of(s - 1, y, c),
                         row_of(s - 1, y + 1, c), row_of(s, y, c));
        }
}

// The solver on row-major planes of width x height.
Status explicit_kernel(std::span<float* const> planes, int width, int height, const float* diffusivity,
                       const DiffusionOptions& settings, const Exec& exec, diffusion_detail::Conductance rule) {
    const int W = width, H = height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    std::vector<float> row_max(std::size_t(H), 0.0f);  // rows in parallel: a max, the same for any split
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            row_max[std::size_t(y)] = *std::max_element(diffusivity + std::size_t(y) * std::size_t(W),
                                                        diffusivity + std::size_t(y + 1) * std::size_t(W));
    }, 16);
    float dmax = 0.0f;
    for (float m : row_max) dmax = std::max(dmax, m);
    // iterations from the largest blur: dt * dmax * 10/3 <= 1 / safety
    const double rmax = radius_from_diffusivity(dmax);
    const int iters = explicit_iterations(rmax, settings);
    const float dt = float(1.0 / iters);

    // Ping-pong between the caller's planes and one set of buffers.
    const int nc = int(planes.size());
    // Every row of every plane is written by the first pass (no zeroing first:
    // 4 frame-sized planes at 4K, on one thread).
    FrameBuffer<float> next(std::size_t(nc) * n);
    std::vector<float*> cur(planes.begin(), planes.end()), nxt(static_cast<std::size_t>(nc));
    for (int c = 0; c < nc; ++c) nxt[std::size_t(c)] = next.data() + std::size_t(c) * n;
    const int rows = band_rows(H);
    const long nbands = (H + rows - 1) / rows;
    bool cancelled = false;
    for (int done = 0; done < iters;) {
        const int k = std::min(kFused, iters - done);
        const bool ok = parallel_for(exec, nbands, [&](long b0, long b1) {
            const ScopedFlushDenormals ftz;
            std::vector<float> ring;
            for (long b = b0; b < b1; ++b)
                advance_band(diffusivity, W, H, dt, rule, cur, nxt, int(b) * rows, std::min(H, int(b + 1) * rows), k,
                             ring);
        });
        if (!ok) {
            cancelled = true;
            break;
        }
        std::swap(cur, nxt);
        done += k;
    }
    // The caller's planes hold the last complete iterate (cancelled or not).
    for (int c = 0; c < nc; ++c)
        if (cur[std::size_t(c)] != planes[std::size_t(c)])
            std::copy(cur[std::size_t(c)], cur[std::size_t(c)] + n, planes[std::size_t(c)]);
    if (cancelled) return Status::cancelled("diffusion");
    return Status::ok();
}

}  // namespace

Status diffusion_detail::diffuse_explicit(const ImageView& planes, const ConstImageView& diffusivity,
                                          const DiffusionOptions& settings, const Exec& exec, Conductance conductance) {
    return run_solver_kernel(planes, diffusivity, [&](std::span<float* const> p, int w, int h, const float* d) {
        return explicit_kernel(p, w, h, d, settings, exec, conductance);
    });
}

Status diffuse_explicit(const ImageView& planes, const ConstImageView& diffusivity, const DiffusionOptions& settings,
                        const Exec& exec) {
    return diffusion_detail::diffuse_explicit(planes, diffusivity, settings, exec, diffusion_detail::Conductance::Min);
}

}  // namespace gdof
