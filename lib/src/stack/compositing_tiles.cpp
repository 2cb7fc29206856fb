// Method 2, step 3 (compositing.h): tile by tile, each tile reads only the
// references its pixels chose and copies (hard pick) or blends (soft mode),
// into planes that may be an Image's or a caller's strided memory.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "compositing_internal.h"
#include "gdof/compositing.h"

namespace gdof {

namespace detail {

CompositePlanes image_planes(Image& img) {
    CompositePlanes p;
    p.count = std::min(img.nchannels(), 6);
    const Roi& dw = img.data_window();
    for (int c = 0; c < p.count; ++c)
        p.channel[c] = {img.plane(c), 1, {0, 0, dw.width(), dw.height()}, 0, 1, std::ptrdiff_t(dw.width())};
    return p;
}

CompositePlanes view_planes(const ImageView& view, const Roi& region) {
    CompositePlanes p;
    p.count = std::min(view.nchannels, 6);
    const Roi local{0, 0, region.width(), region.height()};
    for (int c = 0; c < p.count; ++c)
        p.channel[c] = {region.empty() ? nullptr : &view.at(c, region.x0, region.y0), 1, local, 0, view.xstride,
                        view.ystride};
    return p;
}

Status composite_tiles(const StackSelection& sel, StackPixels& pixels, const CompositeOptions& settings,
                       const CompositePlanes& out, CompositeStats* stats, const Exec& exec) {
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
    const int ncolour = std::min(out.count, 4);
    if (Status st = pixels.prepare(sel.used_references(), {0, 0, W, H}); !st) return st;

    // Output sample (channel c, local pixel x, y).
    auto put = [&out](int c, int x, int y) -> float& {
        const ImageView& v = out.channel[c];
        return v.base[std::ptrdiff_t(x) * v.xstride + std::ptrdiff_t(y) * v.ystride];
    };

    const TileGrid grid({0, 0, W, H}, T);
    const long ntiles = grid.count();
    std::vector<Status> errors(static_cast<std::size_t>(ntiles));
    std::atomic<long> reads{0}, done{0};

    const bool ok = parallel_for(exec, ntiles, [&](long t0_, long t1_) {
        std::vector<float> buf(std::size_t(T) * std::size_t(T) * 4);
        std::vector<char> in_tile(static_cast<std::size_t>(nrefs));
        for (long t = t0_; t < t1_; ++t) {
            if (exec.is_cancelled()) return;
            const Roi tile = grid.tile(t);
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
                            for (int c = 0; c < ncolour; ++c) put(c, x, y) = src[c];
                            continue;
                        }
                        for (int s = 0; s < k; ++s) {
                            if (sel.index[o + std::size_t(s)] != ref) continue;
                            const float w = sel.weight[o + std::size_t(s)];
                            if (w == 1.0f) {
                                for (int c = 0; c < ncolour; ++c) put(c, x, y) = src[c];
                            } else {
                                for (int c = 0; c < ncolour; ++c) put(c, x, y) += w * src[c];
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

    if (settings.aovs && out.count >= 6)
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t p = std::size_t(y) * std::size_t(W) + std::size_t(x);
                put(4, x, y) = float(sel.index[p * std::size_t(k)]);
                put(5, x, y) = sel.deviation[p];
            }
    if (stats) {
        stats->references = nrefs;
        stats->references_used = sel.references_used();
        stats->tiles = ntiles;
        stats->tile_reads = reads.load();
        stats->composite_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    }
    return Status::ok();
}

}  // namespace detail

Result<Image> composite_stack(const StackSelection& sel, StackPixels& pixels, const CompositeOptions& settings,
                              int origin_x, int origin_y, CompositeStats* stats, const Exec& exec) {
    std::vector<std::string> names = {"R", "G", "B", "A"};
    if (settings.aovs) {
        names.push_back("stack.index");
        names.push_back("stack.deviation");
    }
    Image out = Image::with_channels(
        names, {origin_x, origin_y, origin_x + sel.window.width(), origin_y + sel.window.height()});
    if (Status st = detail::composite_tiles(sel, pixels, settings, detail::image_planes(out), stats, exec); !st)
        return st;
    return out;
}

}  // namespace gdof
