// Method 2, step 3 (compositing.h): tile by tile, each tile reads only the
// references its pixels chose and copies (hard pick) or blends (soft mode).
// Also the in-memory reference source.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "gdof/compositing.h"

namespace gdof {

MemoryStackPixels::MemoryStackPixels(std::vector<const Image*> images)
    : images_(std::move(images)), reads_(images_.size()) {}

long MemoryStackPixels::reads(int ref) const { return reads_[std::size_t(ref)].load(); }

Status MemoryStackPixels::read_tile(int ref, const Roi& tile, float* rgba) {
    if (ref < 0 || ref >= size()) return Status::error("reference " + std::to_string(ref) + " out of range");
    reads_[std::size_t(ref)].fetch_add(1);
    const Image& img = *images_[std::size_t(ref)];
    const Image& first = *images_[0];
    if (img.width() != first.width() || img.height() != first.height())
        return Status::error("reference " + std::to_string(ref) + " is " + std::to_string(img.width()) + "x" +
                             std::to_string(img.height()) + " but reference 0 is " + std::to_string(first.width()) +
                             "x" + std::to_string(first.height()));
    if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > img.width() || tile.y1 > img.height())
        return Status::error("tile " + to_string(tile) + " outside the reference");
    const RgbaIndices c = find_rgba(img);
    const int ch[4] = {c.r, c.g, c.b, c.a};
    const Roi dw = img.data_window();
    float* out = rgba;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            for (int k = 0; k < 4; ++k) {
                const int cc = ch[k];
                *out++ = cc >= 0 ? img.sample(cc, dw.x0 + x, dw.y0 + y) : (k == 3 ? 1.0f : 0.0f);
            }
        }
    return Status::ok();
}

Result<Image> composite_stack(const StackSelection& sel, StackPixels& pixels, const CompositeOptions& settings,
                              int origin_x, int origin_y, CompositeStats* stats, const Exec& exec) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const int nrefs = pixels.size();
    if (int(sel.used.size()) != nrefs)
        return Status::error("the selection was made for " + std::to_string(sel.used.size()) +
                             " references, the source has " + std::to_string(nrefs));
    const int W = sel.window.width(), H = sel.window.height();
    const int T = std::max(8, settings.tile_size);
    const int k = sel.k;
    const bool soft = !sel.weight.empty();

    std::vector<std::string> names = {"R", "G", "B", "A"};
    if (settings.aovs) {
        names.push_back("stack.index");
        names.push_back("stack.deviation");
    }
    const Roi dw{origin_x, origin_y, origin_x + W, origin_y + H};
    Image out = Image::with_channels(names, dw);
    float* plane[4] = {out.plane(0), out.plane(1), out.plane(2), out.plane(3)};

    const int tx = (W + T - 1) / T, ty = (H + T - 1) / T;
    const long ntiles = long(tx) * long(ty);
    std::vector<Status> errors(static_cast<std::size_t>(ntiles));
    std::atomic<long> reads{0}, done{0};

    const bool ok = parallel_for(exec, ntiles, [&](long t0_, long t1_) {
        std::vector<float> buf(std::size_t(T) * std::size_t(T) * 4);
        std::vector<char> in_tile(static_cast<std::size_t>(nrefs));
        for (long t = t0_; t < t1_; ++t) {
            if (exec.is_cancelled()) return;
            const int bx = int(t % tx), by = int(t / tx);
            const Roi tile{bx * T, by * T, std::min(W, (bx + 1) * T), std::min(H, (by + 1) * T)};
            const int tw = tile.width();
            // Which references this tile needs.
            std::fill(in_tile.begin(), in_tile.end(), 0);
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const std::size_t o = (std::size_t(y) * std::size_t(W) + std::size_t(x)) * std::size_t(k);
                    for (int s = 0; s < k; ++s) {
                        const std::int32_t r = sel.index[o + std::size_t(s)];
                        if (r < 0) break;
                        in_tile[std::size_t(r)] = 1;
                    }
                }
            // Ascending reference order: each pixel sums its references in one fixed order.
            for (int ref = 0; ref < nrefs; ++ref) {
                if (!in_tile[std::size_t(ref)]) continue;
                Status st = pixels.read_tile(ref, tile, buf.data());
                ++reads;
                if (!st) {
                    errors[std::size_t(t)] = st;
                    return;
                }
                for (int y = tile.y0; y < tile.y1; ++y)
                    for (int x = tile.x0; x < tile.x1; ++x) {
                        const std::size_t p = std::size_t(y) * std::size_t(W) + std::size_t(x);
                        const float* src = &buf[(std::size_t(y - tile.y0) * std::size_t(tw) + std::size_t(x - tile.x0)) * 4];
                        const std::size_t o = p * std::size_t(k);
                        if (!soft) {
                            if (sel.index[o] != ref) continue;
                            for (int c = 0; c < 4; ++c) plane[c][p] = src[c];
                            continue;
                        }
                        for (int s = 0; s < k; ++s) {
                            if (sel.index[o + std::size_t(s)] != ref) continue;
                            const float w = sel.weight[o + std::size_t(s)];
                            if (w == 1.0f) {
                                for (int c = 0; c < 4; ++c) plane[c][p] = src[c];
                            } else {
                                for (int c = 0; c < 4; ++c) plane[c][p] += w * src[c];
                            }
                        }
                    }
            }
            const long d = ++done;
            exec.report(double(d) / double(ntiles));
        }
    });
    if (!ok) return Status::cancelled();
    for (const Status& e : errors)
        if (!e) return e;

    if (settings.aovs) {
        float* pi = out.plane(4);
        float* pd = out.plane(5);
        for (std::size_t p = 0; p < sel.window.npixels(); ++p) {
            pi[p] = float(sel.index[p * std::size_t(k)]);
            pd[p] = sel.deviation[p];
        }
    }
    if (stats) {
        stats->references = nrefs;
        stats->references_used = sel.references_used();
        stats->tiles = ntiles;
        stats->tile_reads = reads.load();
        stats->composite_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    }
    return out;
}

}  // namespace gdof
