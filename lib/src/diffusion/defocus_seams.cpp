// A slice bound across a continuous surface (a plate's floor cut where a
// blurred object stands on it): the near part is one layer, the far part
// the next, extended behind the near one by a fill from its rim. Blurred
// alike, the two parts should add up to the surface blurred whole, and they
// do only if the far part's colour behind the near one averages, under the
// blur kernel, as its own pixels beside it do. A fill that holds the rim's
// colour does not on a shaded surface: its error is about a(1 - a) times
// the shading's change over the kernel (a: the near part's spread
// coverage), a faint band along the bound (Cornell's walls in the sphere of
// focus, 2% near the bound).
//
// Exact for equal blurs: the far layer's colour taken as its own pixels'
// normalised blur (their spread colour over their spread coverage), since
// then near + (1 - a) * far = the whole surface's blur. The extension's
// seam pixels (Layer::seam, those behind a nearer part of the same surface)
// are spread alone over their box and taken out of the layer's spread;
// where what remains of the layer's own coverage (with its extension behind
// other surfaces, which a fill must guess) is small, the colour fades back
// to the whole spread, which the fill carries deep behind the near part.
#include <algorithm>
#include <utility>
#include <vector>

#include "diffusion/defocus_internal.h"

namespace gdof::defocus_detail {

namespace {

// Below this much of the layer's own spread coverage at a pixel, its colour
// blends towards the whole layer's (the metric moved by less than 1e-5 for
// 0.05 to 0.5 on the benchmark's plates).
constexpr float kOwnShare = 0.2f;
// No own coverage at all below this: the whole layer's colour.
constexpr float kNoShare = 1e-4f;
// At most this many boxes for a layer's seams; more (specks of seam
// scattered over a noisy surface) are spread over the one box around them
// all, as every spread has a cost of its own besides its pixels.
constexpr std::size_t kMaxSeamBoxes = 32;

// The boxes the seam pixels are spread over: the seam's box cut where
// rows, then columns, then rows again (and so on) hold no seam pixel over
// more than 2 `margin` (an XY cut), each part tightened to its pixels and
// grown by `margin` within `work`. The parts' boxes are then disjoint, each
// part's pixels lie `margin` inside its box as they did inside the one box
// around them all, and two pieces of seam far apart (a sphere's ring cut by
// a bound and a band of floor 400 px below it, at 4K) no longer spread over
// everything between them.
std::vector<Roi> seam_boxes(const Layer& layer, int margin, const Roi& work, const Exec& exec) {
    const Roi lw = layer.image.data_window();
    const std::size_t LW = std::size_t(lw.width());
    const auto seam_at = [&](int x, int y) {
        return layer.seam[std::size_t(y - lw.y0) * LW + std::size_t(x - lw.x0)] != 0;
    };
    const Roi whole = intersect(layer.seam_box, lw);
    std::vector<Roi> leaves;
    std::vector<Roi> pending{whole};
    const int gap = 2 * margin;
    while (!pending.empty()) {
        const Roi r = pending.back();
        pending.pop_back();
        if (r.empty()) continue;
        // Which rows and columns of r hold seam pixels (rows in parallel;
        // each band of rows marks its own columns, or-ed after).
        std::vector<unsigned char> rows(std::size_t(r.height()), 0);
        const long bands = (r.height() + 63) / 64;
        std::vector<std::vector<unsigned char>> band_cols(static_cast<std::size_t>(bands));
        parallel_for(exec, bands, [&](long b0, long b1) {
            for (long b = b0; b < b1; ++b) {
                std::vector<unsigned char>& cols = band_cols[std::size_t(b)];
                cols.assign(std::size_t(r.width()), 0);
                for (int y = r.y0 + int(b) * 64; y < std::min(r.y1, r.y0 + int(b + 1) * 64); ++y)
                    for (int x = r.x0; x < r.x1; ++x)
                        if (seam_at(x, y)) rows[std::size_t(y - r.y0)] = cols[std::size_t(x - r.x0)] = 1;
            }
        });
        std::vector<unsigned char> cols(std::size_t(r.width()), 0);
        for (const auto& c : band_cols)
            for (std::size_t x = 0; x < c.size(); ++x) cols[x] |= c[x];
        // The runs of marked lines along one axis, split at gaps over 2 margin.
        const auto runs = [gap](const std::vector<unsigned char>& line, int origin) {
            std::vector<std::pair<int, int>> out;  // [first, last + 1)
            for (int i = 0; i < int(line.size()); ++i) {
                if (!line[std::size_t(i)]) continue;
                if (!out.empty() && i - out.back().second <= gap) out.back().second = i + 1;
                else out.push_back({i, i + 1});
            }
            for (auto& [a, b] : out) a += origin, b += origin;
            return out;
        };
        const auto yr = runs(rows, r.y0), xr = runs(cols, r.x0);
        if (yr.empty()) continue;
        if (yr.size() > 1) {
            for (const auto& [a, b] : yr) pending.push_back(Roi{xr.front().first, a, xr.back().second, b});
        } else if (xr.size() > 1) {
            for (const auto& [a, b] : xr) pending.push_back(Roi{a, yr[0].first, b, yr[0].second});
        } else {
            leaves.push_back(Roi{xr[0].first, yr[0].first, xr[0].second, yr[0].second});
        }
    }
    if (leaves.size() > kMaxSeamBoxes) leaves.assign(1, whole);
    std::vector<Roi> boxes;
    for (const Roi& l : leaves)
        if (const Roi b = intersect(l.grown(margin), work); !b.empty()) boxes.push_back(b);
    return boxes;
}

// The seam pixels inside `box` (within work) spread alone over it, and the
// layer's colour there made its other pixels' normalised spread.
Status continue_in_box(const Layer& layer, const RadiusMap& radius, const Roi& work, const Roi& box,
                       const SpreadSeams& spread, DiffusedLayer& out, const Exec& exec) {
    const Image& img = layer.image;
    const Roi lw = img.data_window();
    const RgbaIndices ix = find_rgba(img);
    const int src_c[4] = {ix.r, ix.g, ix.b, ix.a};
    const int BW = box.width(), W = work.width();
    Image seam = Image::uninitialized(
        {{"R", PixelType::Float}, {"G", PixelType::Float}, {"B", PixelType::Float}, {"A", PixelType::Float}}, box, box);
    RadiusMap r(box.npixels());  // every element written below
    parallel_for(exec, box.height(), [&](long r0, long r1) {
        for (int y = box.y0 + int(r0); y < box.y0 + int(r1); ++y) {
            const std::size_t row = std::size_t(y - box.y0) * std::size_t(BW);
            std::copy_n(radius.data() + std::size_t(y - work.y0) * std::size_t(W) + std::size_t(box.x0 - work.x0), BW,
                        r.data() + row);
            for (int c = 0; c < 4; ++c) {
                float* d = seam.plane(c) + row;
                std::fill_n(d, BW, 0.0f);
                if (y < lw.y0 || y >= lw.y1) continue;
                const int xa = std::max(box.x0, lw.x0), xb = std::min(box.x1, lw.x1);
                const std::size_t lrow = std::size_t(y - lw.y0) * std::size_t(lw.width());
                const float* s = img.plane(src_c[c]);
                for (int x = xa; x < xb; ++x) {
                    const std::size_t l = lrow + std::size_t(x - lw.x0);
                    if (layer.seam[l]) d[x - box.x0] = s[l];
                }
            }
        }
    }, 16);
    if (exec.is_cancelled()) return Status::cancelled("seams");
    Exec quiet = exec;  // the layer's own spread reported the progress
    quiet.progress = nullptr;
    if (Status st = spread(seam.channels_view(), r, quiet); !st) return st;
    parallel_for(exec, box.height(), [&](long r0, long r1) {
        for (int y = box.y0 + int(r0); y < box.y0 + int(r1); ++y) {
            const std::size_t srow = std::size_t(y - box.y0) * std::size_t(BW);
            const std::size_t orow = std::size_t(y - work.y0) * std::size_t(W) + std::size_t(box.x0 - work.x0);
            float* E[4] = {out.rgba.plane(0) + orow, out.rgba.plane(1) + orow, out.rgba.plane(2) + orow,
                           out.rgba.plane(3) + orow};
            const float* S[4] = {seam.plane(0) + srow, seam.plane(1) + srow, seam.plane(2) + srow, seam.plane(3) + srow};
            for (int x = 0; x < BW; ++x) {
                const float a = E[3][x], own = a - S[3][x];
                if (!(own > kNoShare) || !(a > 0.0f)) continue;
                // colour = w * own's normalised colour + (1 - w) * the whole's,
                // at the layer's coverage a.
                const float w = std::min(1.0f, own / kOwnShare);
                const float k = w * a / own;
                for (int c = 0; c < 3; ++c) E[c][x] = k * (E[c][x] - S[c][x]) + (1.0f - w) * E[c][x];
            }
        }
    }, 16);
    return Status::ok();
}

}  // namespace

Status continue_across_seams(const Layer& layer, const RadiusMap& radius, const Roi& work, int margin,
                             const SpreadSeams& spread, DiffusedLayer& out, const Exec& exec) {
    if (layer.seam.empty() || layer.seam_box.empty()) return Status::ok();
    const std::vector<Roi> boxes = seam_boxes(layer, margin, work, exec);
    if (exec.is_cancelled()) return Status::cancelled("seams");  // the boxes may be unfinished
    for (const Roi& box : boxes)
        if (Status st = continue_in_box(layer, radius, work, box, spread, out, exec); !st) return st;
    return Status::ok();
}

}  // namespace gdof::defocus_detail
