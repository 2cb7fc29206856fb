// Push-pull fill (Gortler et al., "The Lumigraph", 1996): push averages
// weighted values down a 2x pyramid; pull blends each level with the
// upsampling of the filled level above, by the level's own weight. The
// upsampling weights each bilinear tap by the coarse pixel's own weight, so
// known coarse pixels decide before filled ones (locality at cell edges).
// Float arithmetic; coarse levels only (level 0 is the caller's planes).
#include "gdof/fill.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

#include "image/row_major_planes.h"
#include "image/view_shape.h"

namespace gdof {

namespace {

// A coarse level: weights in [0, 1] and normalised (not weighted) values,
// one plane after another.
struct Level {
    int w = 0, h = 0;
    int ox = 0, oy = 0;  // its grid's offset over the finer level (push)
    std::vector<float, DefaultInitAllocator<float>> weight, values;  // weights set by push(), values where the weight is > 0 (the others by pull() before they are read)
    float* plane(int c) { return values.data() + std::size_t(c) * std::size_t(w) * std::size_t(h); }
    const float* plane(int c) const { return values.data() + std::size_t(c) * std::size_t(w) * std::size_t(h); }
};

// A coarse level as a pull reads it: its grid, weights and (filled) values,
// which may lie elsewhere than the level's own (a spin's copy).
struct Coarse {
    int w = 0, h = 0, ox = 0, oy = 0;
    const float* weight = nullptr;
    const float* values = nullptr;  // planes back to back
    const float* plane(int c) const { return values + std::size_t(c) * std::size_t(w) * std::size_t(h); }
};

Coarse coarse(const Level& l, const float* values) { return {l.w, l.h, l.ox, l.oy, l.weight.data(), values}; }
Coarse coarse(const Level& l) { return coarse(l, l.values.data()); }

// The confidence of a coarse pixel that holds no sample of its own (filled
// from the level above) in the pull's taps: small, so that such pixels only
// decide where none of the four taps holds samples. Results move by at most
// 0.0005 (relative L1, benchmark panels) between 0.001 and 0.1.
constexpr float kFilledTap = 0.01f;

// Where a fine pixel centre falls between two coarse pixels along one axis:
// the two coarse indices and the weight of the second.
struct Tap {
    int a, b;
    float t;
};

// `offset` (0 or 1): the coarse grid's offset (push), fine pixel i lies in
// coarse pixel (i + offset) / 2.
std::vector<Tap> taps(int fine, int coarse, int offset) {
    std::vector<Tap> out(static_cast<std::size_t>(fine));
    for (int i = 0; i < fine; ++i) {
        const double c = std::clamp((i + offset + 0.5) / 2.0 - 0.5, 0.0, double(coarse - 1));
        const int a = int(c);
        out[std::size_t(i)] = {a, std::min(a + 1, coarse - 1), float(c - a)};
    }
    return out;
}

// Push: each coarse pixel the weight-normalised average of its (up to) 2x2
// fine pixels (left unset where they have no weight); its weight their
// weights' sum, at most 1. The fine level is
// level 0 (the caller's planes, weights clamped to [0, 1], values counted
// only where the weight is > 0) or a coarse level. The coarse grid is offset
// by (ox, oy), 0 or 1: coarse pixel (X, Y) covers fine columns 2X - ox and
// 2X + 1 - ox, rows likewise (push_pull's spins).
Level push(int fw, int fh, const float* fweight, std::span<const float* const> fplanes, bool level0, int ox,
           int oy, const Exec& exec) {
    Level c;
    c.ox = ox;
    c.oy = oy;
    c.w = (fw + ox + 1) / 2;
    c.h = (fh + oy + 1) / 2;
    const int nc = int(fplanes.size());
    const std::size_t cn = std::size_t(c.w) * std::size_t(c.h);
    c.weight.resize(cn);
    c.values.resize(std::size_t(nc) * cn);
    parallel_for(exec, c.h, [&](long y0, long y1) {
        // Per coarse pixel of the row: its four fine pixels' weights (0 where
        // absent), in the order (0, 0), (1, 0), (0, 1), (1, 1), and their sum.
        // Pointers and sizes in locals: the stores may alias what is reached
        // through a reference.
        const int cw = c.w;
        std::vector<float> w4(4 * static_cast<std::size_t>(cw)), wsum(static_cast<std::size_t>(cw));
        float* w4p = w4.data();
        float* wsp = wsum.data();
        auto clamp_w = [level0](float w) { return level0 ? (w > 0.0f ? std::min(w, 1.0f) : 0.0f) : w; };
        for (long yl = y0; yl < y1; ++yl) {
            const int y = int(yl);
            const int r0 = 2 * y - oy;  // the fine rows r0 (absent when -1) and r0 + 1
            const bool row0 = r0 >= 0, row1 = r0 + 1 < fh;
            const float* f0 = row0 ? fweight + std::size_t(r0) * std::size_t(fw) : nullptr;
            const float* f1 = row1 ? fweight + std::size_t(r0 + 1) * std::size_t(fw) : nullptr;
            float* cwt = c.weight.data() + std::size_t(y) * std::size_t(cw);
            for (int x = 0; x < cw; ++x) {
                const int c0 = 2 * x - ox;
                const bool col0 = c0 >= 0, col1 = c0 + 1 < fw;
                float* w = w4p + 4 * std::size_t(x);
                w[0] = row0 && col0 ? clamp_w(f0[c0]) : 0.0f;
                w[1] = row0 && col1 ? clamp_w(f0[c0 + 1]) : 0.0f;
                w[2] = row1 && col0 ? clamp_w(f1[c0]) : 0.0f;
                w[3] = row1 && col1 ? clamp_w(f1[c0 + 1]) : 0.0f;
                const float sum = ((w[0] + w[1]) + w[2]) + w[3];
                wsp[x] = sum;
                cwt[x] = std::min(1.0f, sum);
            }
            for (int k = 0; k < nc; ++k) {
                // Read only where the weight below is > 0 (so never an absent row).
                const float* plane = fplanes[std::size_t(k)];
                const float* v0 = row0 ? plane + std::size_t(r0) * std::size_t(fw) : nullptr;
                const float* v1 = row1 ? plane + std::size_t(r0 + 1) * std::size_t(fw) : nullptr;
                float* out = c.plane(k) + std::size_t(y) * std::size_t(cw);
                for (int x = 0; x < cw; ++x) {
                    const float sum = wsp[x];
                    // Nothing known below (most of a layer's frame): no reads, and
                    // no write either: a pixel of weight 0 is read only after a
                    // pull has written it (every tap a pull reads is pulled first).
                    if (!(sum > 0.0f)) continue;
                    const float* w = w4p + 4 * std::size_t(x);
                    const int c0 = 2 * x - ox;
                    // Unknown fine values may be anything (NaN): never multiplied in.
                    float acc = 0.0f;
                    acc += w[0] > 0.0f ? w[0] * v0[c0] : 0.0f;
                    acc += w[1] > 0.0f ? w[1] * v0[c0 + 1] : 0.0f;
                    acc += w[2] > 0.0f ? w[2] * v1[c0] : 0.0f;
                    acc += w[3] > 0.0f ? w[3] * v1[c0 + 1] : 0.0f;
                    out[x] = acc / sum;
                }
            }
        }
    }, 8);
    return c;
}

// How level 0's pull stores a value: times `scale`, added to the pixel
// (`add`, every spin after the first) or in place of it.
struct Deposit {
    float scale = 1.0f;
    bool add = false;
};

// A pulled pixel `o` of weight wx blended with the upsampling of its four
// coarse taps (rows `top` and `bot`, tap weights and their sum t) by 1 - wx.
inline void blend(float& o, float wx, const float* top, const float* bot, const Tap& vx, const std::array<float, 5>& t,
                  Deposit d) {
    const float up = (t[0] * top[vx.a] + t[1] * top[vx.b] + t[2] * bot[vx.a] + t[3] * bot[vx.b]) / t[4];
    const float v = wx > 0.0f ? wx * o + (1.0f - wx) * up : up;
    o = d.add ? o + d.scale * v : d.scale * v;
}

// Pull: every pixel of a fine level whose weight is below 1 blends its value
// with the bilinear upsampling of the (filled) coarser level `c` by
// (1 - weight). Level 0 (`unknown_only`) writes only its unknown pixels
// (weight 0 or NaN), straight into the caller's planes: known pixels keep
// their bits, the pulled value stored as `deposit` says. With `wanted`
// (row-major, non-empty) only the pixels it marks are pulled (the others keep
// their pushed values, never read).
void pull(int fw, int fh, const float* fweight, bool unknown_only, std::span<float* const> out, const Coarse& c,
          std::span<const unsigned char> wanted, Deposit deposit, const Exec& exec) {
    const std::vector<Tap> tx = taps(fw, c.w, c.ox), ty = taps(fh, c.h, c.oy);
    const int nc = int(out.size());
    const float* cw = c.weight;
    parallel_for(exec, fh, [&](long y0, long y1) {
        // Per pulled pixel of the row (weight below 1, wanted): its column,
        // own weight, and four tap weights with their sum, shared by the planes.
        struct Pulled {
            int x;
            float wx;
            std::array<float, 5> t;
        };
        std::vector<Pulled> pulled;
        pulled.reserve(static_cast<std::size_t>(fw));
        for (long yl = y0; yl < y1; ++yl) {
            const Tap& vy = ty[std::size_t(yl)];
            const std::size_t ra = std::size_t(vy.a) * std::size_t(c.w), rb = std::size_t(vy.b) * std::size_t(c.w);
            const std::size_t row = std::size_t(yl) * std::size_t(fw);
            pulled.clear();
            const unsigned char* wr = wanted.empty() ? nullptr : wanted.data() + row;
            for (int x = 0; x < fw; ++x) {
                if (wr) {  // eight unwanted pixels skipped at a time (most are)
                    std::uint64_t eight = 1;
                    if ((x & 7) == 0 && x + 8 <= fw) std::memcpy(&eight, wr + x, 8);
                    if (eight == 0) {
                        x += 7;
                        continue;
                    }
                    if (!wr[x]) continue;
                }
                const float fwt = fweight[row + std::size_t(x)];
                const float wx = unknown_only ? (fwt > 0.0f ? 1.0f : 0.0f) : fwt;
                if (wx >= 1.0f) continue;
                // The four coarse taps weighted by their bilinear weights times their
                // own confidence (pushed weight, + kFilledTap): a coarse pixel that
                // holds samples outweighs one that was itself filled from further up.
                // A plain bilinear tap let a pixel one step from known pixels, across
                // a power-of-two cell boundary, take its value from a level whose
                // cells span the whole neighbourhood (a lamp's brightness over a dark
                // ceiling 60 px away).
                const Tap& vx = tx[std::size_t(x)];
                Pulled p{x, wx, {}};
                std::array<float, 5>& t = p.t;
                t[0] = (1.0f - vx.t) * (1.0f - vy.t) * (cw[ra + std::size_t(vx.a)] + kFilledTap);
                t[1] = vx.t * (1.0f - vy.t) * (cw[ra + std::size_t(vx.b)] + kFilledTap);
                t[2] = (1.0f - vx.t) * vy.t * (cw[rb + std::size_t(vx.a)] + kFilledTap);
                t[3] = vx.t * vy.t * (cw[rb + std::size_t(vx.b)] + kFilledTap);
                t[4] = t[0] + t[1] + t[2] + t[3];
                if (nc == 1) {  // one plane (a radius map): no list
                    blend(out[0][row + std::size_t(x)], wx, c.plane(0) + ra, c.plane(0) + rb, vx, t, deposit);
                    continue;
                }
                pulled.push_back(p);
            }
            for (int k = 0; k < nc; ++k) {
                const float* top = c.plane(k) + ra;
                const float* bot = c.plane(k) + rb;
                float* o = out[std::size_t(k)] + row;
                for (const Pulled& p : pulled) blend(o[p.x], p.wx, top, bot, tx[std::size_t(p.x)], p.t, deposit);
            }
        }
    }, 16);
}

// The pixels of coarse level `c` that pull() reads for the fine level's
// pixels marked in `pulled` whose weight is below 1 (unknown only: not > 0):
// the four taps of each, whatever their bilinear weights, so every value
// read is the one a whole pull computes. Coarse row Y is read only by fine
// rows whose taps are Y, so each coarse row is marked by one task.
std::vector<unsigned char> taps_read(int fw, int fh, const float* fweight, bool unknown_only,
                                     std::span<const unsigned char> pulled, const Coarse& c, const Exec& exec) {
    const std::vector<Tap> tx = taps(fw, c.w, c.ox), ty = taps(fh, c.h, c.oy);
    std::vector<unsigned char> out(std::size_t(c.w) * std::size_t(c.h), 0);
    parallel_for(exec, c.h, [&](long Y0, long Y1) {
        for (long Y = Y0; Y < Y1; ++Y) {
            unsigned char* o = out.data() + std::size_t(Y) * std::size_t(c.w);
            // Fine rows around 2Y + 0.5 - oy are the only ones with a tap on Y.
            for (int y = std::max(0, int(2 * Y) - 3); y < std::min(fh, int(2 * Y) + 4); ++y) {
                if (ty[std::size_t(y)].a != int(Y) && ty[std::size_t(y)].b != int(Y)) continue;
                // Locals (a byte store may alias anything reached through a
                // reference); eight unmarked pixels skipped at a time (most are).
                const std::size_t row = std::size_t(y) * std::size_t(fw);
                const unsigned char* p = pulled.data() + row;
                const float* wt = fweight + row;
                const Tap* t = tx.data();
                for (int x = 0; x < fw;) {
                    std::uint64_t eight = 0;
                    if (x + 8 <= fw) std::memcpy(&eight, p + x, 8);
                    if (x + 8 <= fw && eight == 0) {
                        x += 8;
                        continue;
                    }
                    if (p[x] && !(unknown_only ? wt[x] > 0.0f : wt[x] >= 1.0f)) o[t[x].a] = o[t[x].b] = 1;
                    ++x;
                }
            }
        }
    }, 16);
    return out;
}

// The first coarse level of a fill (the push of the caller's planes, its
// costliest step) on the grid offset by (ox, oy), and which of its pixels
// the wanted ones' pull reads: the same for every spin of that offset.
struct FirstLevel {
    Level level;
    std::vector<unsigned char> needed;  // empty without `wanted`
};

// The offset of level l's grid (l = 0: the first coarse level's) for a
// spin's `shift`: bit l. A level of 2 px or less is not offset (an offset
// grid would not shrink it).
int grid_offset(const std::array<int, 2>& shift, int l, int axis, int fine_size) {
    return fine_size > 2 ? (shift[std::size_t(axis)] >> l) & 1 : 0;
}

// One fill on row-major planes of width x height (push_pull_fill's
// contract) from its first coarse level `first`, the coarser levels' grids
// offset by `shift` px (< 2^levels). A `shared` first level (other spins
// start from it too) is not written: the pull blends into a copy of the
// pixels it reads. Rows of a level are independent in both passes, so they
// run in parallel and the result is the same for any thread count. Level 0
// is read and written in place: only its unknown pixels change, as
// `deposit` says.
void push_pull(std::span<float* const> planes, const float* weight, int width, int height,
               std::span<const unsigned char> wanted, FirstLevel& first, bool shared, std::array<int, 2> shift,
               Deposit deposit, const Exec& exec) {
    const int nc = int(planes.size());
    const Level& l0 = first.level;
    const std::size_t n0 = std::size_t(l0.w) * std::size_t(l0.h);
    // The first level's values as this spin fills them: its own when not
    // shared, else a copy of the pixels its pull writes and the pull below it
    // reads (every pixel without `wanted`; the others are never read).
    std::vector<float, DefaultInitAllocator<float>> mine;
    float* v0 = first.level.values.data();
    if (shared) {
        mine.resize(std::size_t(nc) * n0);  // unset but where copied
        v0 = mine.data();
        const unsigned char* need = first.needed.empty() ? nullptr : first.needed.data();
        parallel_for(exec, l0.h, [&](long r0, long r1) {
            const std::size_t i0 = std::size_t(r0) * std::size_t(l0.w), i1 = std::size_t(r1) * std::size_t(l0.w);
            if (!need) {
                for (int k = 0; k < nc; ++k)
                    std::copy(l0.plane(k) + i0, l0.plane(k) + i1, v0 + std::size_t(k) * n0 + i0);
                return;
            }
            for (std::size_t i = i0; i < i1; ++i) {
                std::uint64_t eight = 1;  // eight unneeded pixels skipped at a time (most are)
                if ((i & 7) == 0 && i + 8 <= i1) std::memcpy(&eight, need + i, 8);
                if (eight == 0) {
                    i += 7;
                    continue;
                }
                if (!need[i]) continue;
                for (int k = 0; k < nc; ++k) v0[std::size_t(k) * n0 + i] = l0.plane(k)[i];
            }
        }, 16);
    }
    // Push: halve until 1x1, from the first level's pushed values.
    std::vector<const float*> fine(planes.size());
    std::vector<Level> levels;  // levels[i]: the level above the first by i + 1
    while (levels.empty() ? (l0.w > 1 || l0.h > 1) : (levels.back().w > 1 || levels.back().h > 1)) {
        const Level& f = levels.empty() ? l0 : levels.back();
        const int l = int(levels.size()) + 1;
        for (int k = 0; k < nc; ++k) fine[std::size_t(k)] = f.plane(k);
        Level c = push(f.w, f.h, f.weight.data(), fine, false, grid_offset(shift, l, 0, f.w),
                       grid_offset(shift, l, 1, f.h), exec);
        levels.push_back(std::move(c));
    }
    // With `wanted`: the coarse pixels each level's pulled pixels read, level
    // by level (needed[i] marks levels[i]'s, first.needed the first level's).
    std::vector<std::vector<unsigned char>> needed;
    if (!wanted.empty())
        for (std::size_t i = 0; i < levels.size(); ++i) {
            const Level& f = i == 0 ? l0 : levels[i - 1];
            needed.push_back(taps_read(f.w, f.h, f.weight.data(), false, i == 0 ? first.needed : needed[i - 1],
                                       coarse(levels[i]), exec));
        }
    auto wanted_at = [&](std::size_t i) {
        return needed.empty() ? std::span<const unsigned char>{} : std::span<const unsigned char>(needed[i]);
    };
    // Pull: from the top, each level blended with the upsampled level above.
    std::vector<float*> ptrs(static_cast<std::size_t>(nc));
    for (int li = int(levels.size()) - 2; li >= 0; --li) {
        Level& f = levels[std::size_t(li)];
        for (int k = 0; k < nc; ++k) ptrs[std::size_t(k)] = f.plane(k);
        pull(f.w, f.h, f.weight.data(), false, ptrs, coarse(levels[std::size_t(li) + 1]), wanted_at(std::size_t(li)),
             Deposit{}, exec);
    }
    if (!levels.empty()) {
        for (int k = 0; k < nc; ++k) ptrs[std::size_t(k)] = v0 + std::size_t(k) * n0;
        pull(l0.w, l0.h, l0.weight.data(), false, ptrs, coarse(levels[0]),
             first.needed, Deposit{}, exec);
    }
    // Level 0: only the unknown pixels (that are wanted), from the first coarse level.
    pull(width, height, weight, true, planes, coarse(l0, v0), wanted, deposit, exec);
}

// FillGrids::Spun: fills on pyramids whose grids are offset by these (x, y)
// px, averaged (cycle spinning, Coifman & Donoho 1995): x = 13k, y = 21k
// (mod 32), so the offsets modulo every cell size up to 32 px are spread.
// Levels balanced bit by bit instead (x in {0, 31, 10, 21}) left a step
// hidden by a 26 px strip 2.5 px off its place, against 1.5 here and 5 on
// one grid (test_fill). Their first coarse level's offset is (0, 0) for
// two and (1, 1) for the other two, so two first levels serve four spins;
// even offsets only (one first level for all) doubled what a pan moves
// (tests/bench/run --pan, plate + Z 0.00030 -> 0.00059).
constexpr std::array<std::array<int, 2>, 4> kSpins = {{{0, 0}, {13, 21}, {26, 10}, {7, 31}}};

}  // namespace

bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, const Exec& exec, FillGrids grids) {
    return push_pull_fill(planes, weight, {}, exec, grids);
}

bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, std::span<const unsigned char> wanted,
                    const Exec& exec, FillGrids grids) {
    using namespace image_detail;
    if (planes.window.empty() || planes.nchannels <= 0) return false;
    if (!wanted.empty() && wanted.size() != planes.window.npixels()) return false;
    if (!check_view_shape(planes, kAnyChannelCount, planes.window, "fill planes") ||
        !check_view_shape(weight, 1, planes.window, "fill weight"))
        return false;
    const RowMajorPlanes<float> p(planes);
    const RowMajorPlanes<const float> w(weight);
    const int width = planes.width(), height = planes.height();
    const std::size_t n = std::size_t(width) * std::size_t(height);
    bool any = false, missing = false;
    for (std::size_t i = 0; i < n && !(any && missing); ++i) {
        any = any || w.plane(0)[i] > 0.0f;
        missing = missing || !(w.plane(0)[i] > 0.0f);
    }
    if (!any) return false;
    if (!missing) return true;
    // The first coarse level of each grid offset the spins start from (two
    // of the four with kSpins), pushed once.
    const std::vector<const float*> level0(p.planes().begin(), p.planes().end());
    std::array<std::optional<FirstLevel>, 4> firsts;
    const std::size_t spins = grids == FillGrids::Spun ? kSpins.size() : 1;
    const float scale = 1.0f / float(spins);
    // Spin k's first level: its grid's offset (ox, oy) as ox + 2 oy.
    auto first_of = [&](std::size_t k) {
        return std::size_t(grid_offset(kSpins[k], 0, 0, width) + 2 * grid_offset(kSpins[k], 0, 1, height));
    };
    for (std::size_t k = 0; k < spins; ++k) {
        const std::size_t f = first_of(k);
        const int ox = int(f % 2), oy = int(f / 2);
        std::optional<FirstLevel>& first = firsts[f];
        if (!first) {
            first.emplace();
            first->level = push(width, height, w.plane(0), level0, true, ox, oy, exec);
            if (!wanted.empty())
                first->needed = taps_read(width, height, w.plane(0), true, wanted, coarse(first->level), exec);
        }
        // A later spin from the same first level needs it as pushed.
        bool shared = false;
        for (std::size_t j = k + 1; j < spins; ++j) shared = shared || first_of(j) == f;
        push_pull(p.planes(), w.plane(0), width, height, wanted, *first, shared, kSpins[k], Deposit{scale, k > 0}, exec);
    }
    p.store();
    return true;
}

}  // namespace gdof
