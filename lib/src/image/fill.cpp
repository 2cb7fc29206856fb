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
    std::vector<float, DefaultInitAllocator<float>> weight, values;  // weights set by push(), values where the weight is > 0 (the others by pull() before they are read)
    float* plane(int c) { return values.data() + std::size_t(c) * std::size_t(w) * std::size_t(h); }
    const float* plane(int c) const { return values.data() + std::size_t(c) * std::size_t(w) * std::size_t(h); }
};

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

std::vector<Tap> taps(int fine, int coarse) {
    std::vector<Tap> out(static_cast<std::size_t>(fine));
    for (int i = 0; i < fine; ++i) {
        const double c = std::clamp((i + 0.5) / 2.0 - 0.5, 0.0, double(coarse - 1));
        const int a = int(c);
        out[std::size_t(i)] = {a, std::min(a + 1, coarse - 1), float(c - a)};
    }
    return out;
}

// Push: each coarse pixel the weight-normalised average of its (up to) 2x2
// fine pixels (left unset where they have no weight); its weight their
// weights' sum, at most 1. The fine level is
// level 0 (the caller's planes, weights clamped to [0, 1], values counted
// only where the weight is > 0) or a coarse level.
Level push(int fw, int fh, const float* fweight, std::span<const float* const> fplanes, bool level0,
           const Exec& exec) {
    Level c;
    c.w = (fw + 1) / 2;
    c.h = (fh + 1) / 2;
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
            const bool row1 = 2 * y + 1 < fh;
            const float* f0 = fweight + std::size_t(2 * y) * std::size_t(fw);
            const float* f1 = row1 ? f0 + fw : nullptr;
            float* cwt = c.weight.data() + std::size_t(y) * std::size_t(cw);
            for (int x = 0; x < cw; ++x) {
                const bool col1 = 2 * x + 1 < fw;
                float* w = w4p + 4 * std::size_t(x);
                w[0] = clamp_w(f0[2 * x]);
                w[1] = col1 ? clamp_w(f0[2 * x + 1]) : 0.0f;
                w[2] = row1 ? clamp_w(f1[2 * x]) : 0.0f;
                w[3] = row1 && col1 ? clamp_w(f1[2 * x + 1]) : 0.0f;
                const float sum = ((w[0] + w[1]) + w[2]) + w[3];
                wsp[x] = sum;
                cwt[x] = std::min(1.0f, sum);
            }
            for (int k = 0; k < nc; ++k) {
                const float* v0 = fplanes[std::size_t(k)] + std::size_t(2 * y) * std::size_t(fw);
                const float* v1 = v0 + fw;  // read only where the weight below is > 0
                float* out = c.plane(k) + std::size_t(y) * std::size_t(cw);
                for (int x = 0; x < cw; ++x) {
                    const float sum = wsp[x];
                    // Nothing known below (most of a layer's frame): no reads, and
                    // no write either: a pixel of weight 0 is read only after a
                    // pull has written it (every tap a pull reads is pulled first).
                    if (!(sum > 0.0f)) continue;
                    const float* w = w4p + 4 * std::size_t(x);
                    // Unknown fine values may be anything (NaN): never multiplied in.
                    float acc = 0.0f;
                    acc += w[0] > 0.0f ? w[0] * v0[2 * x] : 0.0f;
                    acc += w[1] > 0.0f ? w[1] * v0[2 * x + 1] : 0.0f;
                    acc += w[2] > 0.0f ? w[2] * v1[2 * x] : 0.0f;
                    acc += w[3] > 0.0f ? w[3] * v1[2 * x + 1] : 0.0f;
                    out[x] = acc / sum;
                }
            }
        }
    }, 8);
    return c;
}

// A pulled pixel `o` of weight wx blended with the upsampling of its four
// coarse taps (rows `top` and `bot`, tap weights and their sum t) by 1 - wx.
inline void blend(float& o, float wx, const float* top, const float* bot, const Tap& vx, const std::array<float, 5>& t) {
    const float up = (t[0] * top[vx.a] + t[1] * top[vx.b] + t[2] * bot[vx.a] + t[3] * bot[vx.b]) / t[4];
    o = wx > 0.0f ? wx * o + (1.0f - wx) * up : up;
}

// Pull: every pixel of a fine level whose weight is below 1 blends its value
// with the bilinear upsampling of the (filled) coarser level `c` by
// (1 - weight). Level 0 (`unknown_only`) writes only its unknown pixels
// (weight 0 or NaN), straight into the caller's planes: known pixels keep
// their bits. With `wanted` (row-major, non-empty) only the pixels it marks
// are pulled (the others keep their pushed values, never read).
void pull(int fw, int fh, const float* fweight, bool unknown_only, std::span<float* const> out, const Level& c,
          std::span<const unsigned char> wanted, const Exec& exec) {
    const std::vector<Tap> tx = taps(fw, c.w), ty = taps(fh, c.h);
    const int nc = int(out.size());
    const float* cw = c.weight.data();
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
                    blend(out[0][row + std::size_t(x)], wx, c.plane(0) + ra, c.plane(0) + rb, vx, t);
                    continue;
                }
                pulled.push_back(p);
            }
            for (int k = 0; k < nc; ++k) {
                const float* top = c.plane(k) + ra;
                const float* bot = c.plane(k) + rb;
                float* o = out[std::size_t(k)] + row;
                for (const Pulled& p : pulled) blend(o[p.x], p.wx, top, bot, tx[std::size_t(p.x)], p.t);
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
                                     std::span<const unsigned char> pulled, const Level& c, const Exec& exec) {
    const std::vector<Tap> tx = taps(fw, c.w), ty = taps(fh, c.h);
    std::vector<unsigned char> out(std::size_t(c.w) * std::size_t(c.h), 0);
    parallel_for(exec, c.h, [&](long Y0, long Y1) {
        for (long Y = Y0; Y < Y1; ++Y) {
            unsigned char* o = out.data() + std::size_t(Y) * std::size_t(c.w);
            // Fine rows around 2Y + 0.5 are the only ones with a tap on Y.
            for (int y = std::max(0, int(2 * Y) - 2); y < std::min(fh, int(2 * Y) + 4); ++y) {
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

// The fill on row-major planes of width x height (push_pull_fill's contract).
// Rows of a level are independent in both passes, so they run in parallel
// and the result is the same for any thread count. Level 0 is read and
// written in place: only its unknown pixels change.
bool push_pull(std::span<float* const> planes, const float* weight, int width, int height,
               std::span<const unsigned char> wanted, const Exec& exec) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    const int nc = int(planes.size());
    bool any = false, missing = false;
    for (std::size_t i = 0; i < n && !(any && missing); ++i) {
        any = any || weight[i] > 0.0f;
        missing = missing || !(weight[i] > 0.0f);
    }
    if (!any) return false;
    if (!missing) return true;

    // Push: halve until 1x1.
    std::vector<const float*> fine(planes.begin(), planes.end());
    std::vector<Level> levels;
    levels.push_back(push(width, height, weight, fine, true, exec));
    while (levels.back().w > 1 || levels.back().h > 1) {
        const Level& f = levels.back();
        for (int k = 0; k < nc; ++k) fine[std::size_t(k)] = f.plane(k);
        Level c = push(f.w, f.h, f.weight.data(), fine, false, exec);
        levels.push_back(std::move(c));
    }
    // With `wanted`: the coarse pixels each level's pulled pixels read, level
    // by level (coarse level li + 1 of `needed` is levels[li]).
    std::vector<std::vector<unsigned char>> needed;
    if (!wanted.empty()) {
        needed.push_back(taps_read(width, height, weight, true, wanted, levels[0], exec));
        for (std::size_t li = 0; li + 1 < levels.size(); ++li)
            needed.push_back(taps_read(levels[li].w, levels[li].h, levels[li].weight.data(), false, needed[li],
                                       levels[li + 1], exec));
    }
    // Pull: from the top, each level blended with the upsampled level above.
    std::vector<float*> ptrs(static_cast<std::size_t>(nc));
    for (int li = int(levels.size()) - 2; li >= 0; --li) {
        Level& f = levels[std::size_t(li)];
        for (int k = 0; k < nc; ++k) ptrs[std::size_t(k)] = f.plane(k);
        pull(f.w, f.h, f.weight.data(), false, ptrs, levels[std::size_t(li) + 1],
             needed.empty() ? std::span<const unsigned char>{} : std::span<const unsigned char>(needed[std::size_t(li)]),
             exec);
    }
    // Level 0: only the unknown pixels (that are wanted), from the first coarse level.
    pull(width, height, weight, true, planes, levels[0], wanted, exec);
    return true;
}

}  // namespace

bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, const Exec& exec) {
    return push_pull_fill(planes, weight, {}, exec);
}

bool push_pull_fill(const ImageView& planes, const ConstImageView& weight, std::span<const unsigned char> wanted,
                    const Exec& exec) {
    using namespace image_detail;
    if (planes.window.empty() || planes.nchannels <= 0) return false;
    if (!wanted.empty() && wanted.size() != planes.window.npixels()) return false;
    if (!check_view_shape(planes, kAnyChannelCount, planes.window, "fill planes") ||
        !check_view_shape(weight, 1, planes.window, "fill weight"))
        return false;
    const RowMajorPlanes<float> p(planes);
    const RowMajorPlanes<const float> w(weight);
    if (!push_pull(p.planes(), w.plane(0), planes.width(), planes.height(), wanted, exec)) return false;
    p.store();
    return true;
}

}  // namespace gdof
