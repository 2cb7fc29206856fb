// Extension of layers behind nearer ones (see layers.h): the hidden pixels of
// a layer near its own coverage get a push-pull continuation of its colour,
// depth and positions, opaque.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "gdof/fill.h"
#include "layers/layers_internal.h"

namespace gdof {

using namespace layers_detail;

namespace {

// Own coverage of a layer over the frame: A > 0 or any colour != 0.
void coverage(const Image& img, const Roi& frame, std::vector<float>& alpha, std::vector<unsigned char>& own,
              const Exec& exec) {
    const std::size_t n = frame.npixels();
    alpha.assign(n, 0.0f);
    own.assign(n, 0);
    const Roi w = intersect(img.data_window(), frame);
    if (w.empty()) return;
    parallel_for(exec, w.height(), [&](long r0, long r1) {
        for (int y = w.y0 + int(r0); y < w.y0 + int(r1); ++y) {
            const std::size_t o = img.offset(w.x0, y);
            const float *R = img.plane(0) + o, *G = img.plane(1) + o, *B = img.plane(2) + o, *A = img.plane(3) + o;
            const std::size_t i0 = std::size_t(y - frame.y0) * std::size_t(frame.width()) + std::size_t(w.x0 - frame.x0);
            for (int x = 0; x < w.width(); ++x) {
                const float a = A[x];
                const bool present = a > 0.0f || R[x] != 0.0f || G[x] != 0.0f || B[x] != 0.0f;
                own[i0 + std::size_t(x)] = present ? 1 : 0;
                alpha[i0 + std::size_t(x)] = present ? std::clamp(a, 0.0f, 1.0f) : 0.0f;
            }
        }
    }, 16);
}

}  // namespace

Status extend_layers_behind(std::vector<Layer>& layers, const Roi& frame, const ExtendOptions& opt, const Exec& exec) {
    if (!(opt.extend_px >= 0.0) || std::isinf(opt.extend_px))
        return Status::error("layer extension: extend_px must be finite and >= 0, got " + std::to_string(opt.extend_px));
    if (frame.empty() || layers.size() < 2) return Status::ok();
    if (!opt.owner.empty() && opt.owner.size() != frame.npixels())
        return Status::error("layer extension: " + std::to_string(opt.owner.size()) + " owners for a frame of " +
                             std::to_string(frame.npixels()) + " pixels");
    const int FW = frame.width();
    const std::size_t n = frame.npixels();
    const int nl = int(layers.size());
    for (const Layer& L : layers)
        if (L.image.nchannels() < 5 || L.image.channel(3).name != "A" || L.image.channel(4).name != "Z")
            return Status::error("layer extension: layer '" + L.name + "' is not R, G, B, A, Z");

    int nearest = -1, farthest = -1;
    for (int s = 0; s < nl; ++s)
        if (!layers[std::size_t(s)].image.data_window().empty()) {
            if (nearest < 0) nearest = s;
            farthest = s;
        }
    const int grow = int(std::ceil(opt.extend_px));
    std::vector<float> occ(n, 0.0f);          // accumulated alpha of the nearer layers
    std::vector<unsigned char> pres(n, 0);    // any nearer coverage
    std::vector<float> alpha;
    std::vector<unsigned char> own;
    for (int s = 0; s < nl; ++s) {
        if (exec.is_cancelled()) return Status::cancelled();
        Layer& L = layers[std::size_t(s)];
        coverage(L.image, frame, alpha, own, exec);
        const Roi own_box = intersect(L.image.data_window(), frame);
        const bool fills_frame = opt.farthest_fills_frame && s == farthest;
        if (s > nearest && !own_box.empty() && (grow > 0 || fills_frame)) {
            const Roi work = fills_frame ? frame : intersect(own_box.grown(grow), frame);
            const int ww = work.width(), wh = work.height();
            const std::size_t wn = work.npixels();
            auto fi = [&](int x, int y) {  // absolute -> frame index
                return std::size_t(y - frame.y0) * std::size_t(FW) + std::size_t(x - frame.x0);
            };
            std::vector<unsigned char> mine(wn, 0), ext(wn, 0), seen_empty(wn, 0);
            for (int y = 0; y < wh; ++y)
                for (int x = 0; x < ww; ++x) mine[std::size_t(y) * ww + x] = own[fi(work.x0 + x, work.y0 + y)];
            std::vector<float> dist;
            if (!fills_frame) distance_transform(mine, ww, wh, dist, exec);
            // Rows marked in parallel, each with its own span of extension;
            // the union is taken after, in row order.
            std::vector<Roi> row_box(static_cast<std::size_t>(wh));
            parallel_for(exec, wh, [&](long r0, long r1) {
                for (int y = int(r0); y < int(r1); ++y)
                    for (int x = 0; x < ww; ++x) {
                        const std::size_t wi = std::size_t(y) * ww + x, i = fi(work.x0 + x, work.y0 + y);
                        const bool hidden = opt.occluder_alpha > 0.0f ? occ[i] >= opt.occluder_alpha : pres[i] != 0;
                        // The farthest layer still backs what its owner's reach misses (an
                        // opaque plate stays opaque), but not what borders emptiness.
                        const bool allowed = opt.owner.empty() || opt.owner[i] == s || (fills_frame && opt.owner[i] >= 0);
                        if (!hidden && !own[i]) seen_empty[wi] = 1;
                        if (hidden && !own[i] && allowed && (fills_frame || dist[wi] <= opt.extend_px)) {
                            ext[wi] = 1;
                            row_box[std::size_t(y)] =
                                unite(row_box[std::size_t(y)], Roi{work.x0 + x, work.y0 + y, work.x0 + x + 1, work.y0 + y + 1});
                        }
                    }
            }, 16);
            Roi box = L.image.data_window();
            bool any = false;
            for (const Roi& r : row_box)
                if (!r.empty()) box = unite(box, r), any = true;
            if (any) {
                const Image& src = L.image;
                const bool has_p = src.nchannels() >= 8;
                const int nfill = has_p ? 7 : 4;  // r, g, b, Z (, P.x, P.y, P.z)
                std::vector<float> fill_planes(std::size_t(nfill) * wn, 0.0f);  // back to back over `work`
                std::array<float*, 7> fill{};
                for (int c = 0; c < nfill; ++c) fill[std::size_t(c)] = fill_planes.data() + std::size_t(c) * wn;
                std::vector<float> wcol(wn, 0.0f), wgeo(wn, 0.0f);
                parallel_for(exec, wh, [&](long r0, long r1) {
                for (int y = int(r0); y < int(r1); ++y)
                    for (int x = 0; x < ww; ++x) {
                        const int ax = work.x0 + x, ay = work.y0 + y;
                        const std::size_t wi = std::size_t(y) * ww + x, i = fi(ax, ay);
                        if (!own[i] || !(alpha[i] > 0.0f)) continue;
                        const float al = alpha[i];
                        wcol[wi] = al;
                        for (int c = 0; c < 3; ++c) fill[std::size_t(c)][wi] = src.at(c, ax, ay) / src.at(3, ax, ay);
                        bool geo = std::isfinite(src.at(4, ax, ay));
                        for (int k = 0; has_p && k < 3; ++k) geo = geo && std::isfinite(src.at(5 + k, ax, ay));
                        if (geo) {
                            wgeo[wi] = al;
                            fill[3][wi] = src.at(4, ax, ay);
                            for (int k = 0; has_p && k < 3; ++k) fill[std::size_t(4 + k)][wi] = src.at(5 + k, ax, ay);
                        }
                    }
                }, 16);
                const ImageView fill_view = ImageView::planar(fill_planes.data(), nfill, work);
                const bool have_colour = push_pull_fill(fill_view.channels(0, 3), ConstImageView::planar(wcol.data(), 1, work), exec);
                const bool have_depth =
                    push_pull_fill(fill_view.channels(3, nfill - 3), ConstImageView::planar(wgeo.data(), 1, work), exec);
                // The continued coverage (continue_coverage): own alpha, 0 where seen empty.
                std::vector<float> cover, wcover;
                const bool coverage_continues = opt.continue_coverage && !fills_frame;
                if (coverage_continues) {
                    cover.assign(wn, 0.0f);
                    wcover.assign(wn, 0.0f);
                    for (int y = 0; y < wh; ++y)
                        for (int x = 0; x < ww; ++x) {
                            const std::size_t wi = std::size_t(y) * ww + x, i = fi(work.x0 + x, work.y0 + y);
                            if (own[i]) cover[wi] = alpha[i], wcover[wi] = 1.0f;
                            else if (seen_empty[wi]) wcover[wi] = 1.0f;
                        }
                    if (!push_pull_fill(ImageView::planar(cover.data(), 1, work), ConstImageView::planar(wcover.data(), 1, work), exec))
                        std::fill(cover.begin(), cover.end(), 1.0f);
                }

                // Re-window the layer to include the extension.
                std::vector<ChannelSpec> specs = src.channels();
                Image out(specs, box, src.display_window());
                out.metadata = src.metadata;
                out.name = src.name;
                out.view = src.view;
                for (int c = 0; c < out.nchannels(); ++c)
                    if (c >= 4 && out.plane(c)) std::fill(out.plane(c), out.plane(c) + out.npixels(), kNaN);
                const Roi old = src.data_window();
                if (!old.empty())
                    parallel_for(exec, old.height(), [&](long r0, long r1) {
                        for (int y = old.y0 + int(r0); y < old.y0 + int(r1); ++y)
                            for (int c = 0; c < out.nchannels(); ++c)
                                if (out.plane(c)) {
                                    const float* from = src.plane(c) + src.offset(old.x0, y);
                                    std::copy(from, from + old.width(), out.plane(c) + out.offset(old.x0, y));
                                }
                    }, 16);
                parallel_for(exec, wh, [&](long r0, long r1) {
                for (int y = int(r0); y < int(r1); ++y)
                    for (int x = 0; x < ww; ++x) {
                        const std::size_t wi = std::size_t(y) * ww + x;
                        if (!ext[wi]) continue;
                        const int ax = work.x0 + x, ay = work.y0 + y;
                        const float a = coverage_continues ? std::clamp(cover[wi], 0.0f, 1.0f) : 1.0f;
                        for (int c = 0; c < 3; ++c) out.at(c, ax, ay) = have_colour ? fill[std::size_t(c)][wi] * a : 0.0f;
                        out.at(3, ax, ay) = a;
                        out.at(4, ax, ay) = have_depth ? fill[3][wi] : float(kInf);
                        for (int k = 0; has_p && k < 3; ++k) out.at(5 + k, ax, ay) = have_depth ? fill[std::size_t(4 + k)][wi] : kNaN;
                    }
                }, 16);
                L.image = std::move(out);
            }
        }
        // This layer's own coverage now hides the layers behind it.
        for (std::size_t i = 0; i < n; ++i) {
            occ[i] = occ[i] + alpha[i] * (1.0f - occ[i]);
            pres[i] = pres[i] || own[i];
        }
    }
    return Status::ok();
}

}  // namespace gdof
