// Extension of layers behind nearer ones (see layers.h): the hidden pixels of
// a layer near its own coverage get a push-pull continuation of its colour,
// depth and positions, opaque.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "gdof/fill.h"
#include "image/mask_dilate.h"
#include "layers/layers_internal.h"

namespace gdof {

namespace layers_detail {

namespace {

// A layer's own coverage over `work`: A > 0 or any colour != 0, and its
// alpha clamped to [0, 1] there (0 elsewhere).
void coverage(const Image& img, const Roi& work, FrameBuffer<float>& alpha, FrameBuffer<unsigned char>& own,
              const Exec& exec) {
    const std::size_t n = work.npixels();
    alpha.resize(n);  // every element written below
    own.resize(n);
    const Roi w = intersect(img.data_window(), work);
    const std::size_t ww = std::size_t(work.width());
    parallel_for(exec, work.height(), [&](long r0, long r1) {
        for (int y = work.y0 + int(r0); y < work.y0 + int(r1); ++y) {
            const std::size_t row = std::size_t(y - work.y0) * ww;
            unsigned char* own_row = own.data() + row;  // locals: byte stores may alias references
            float* alpha_row = alpha.data() + row;
            std::fill_n(own_row, ww, 0);
            std::fill_n(alpha_row, ww, 0.0f);
            if (w.empty() || y < w.y0 || y >= w.y1) continue;
            const std::size_t o = img.offset(w.x0, y);
            const float *R = img.plane(0) + o, *G = img.plane(1) + o, *B = img.plane(2) + o, *A = img.plane(3) + o;
            unsigned char* ow = own_row + (w.x0 - work.x0);
            float* al = alpha_row + (w.x0 - work.x0);
            const int wx = w.width();
            for (int x = 0; x < wx; ++x) {
                const float a = A[x];
                const bool present = covers(R[x], G[x], B[x], a);
                ow[x] = present ? 1 : 0;
                al[x] = present ? std::clamp(a, 0.0f, 1.0f) : 0.0f;
            }
        }
    }, 16);
}

// The rim of a layer's own coverage: own pixels within kRim px (Chebyshev)
// of a pixel the extension fills (`ext`; ExtendOptions::fill_from_hidden_edge,
// plates), else of any pixel the layer does not cover. Only the rim feeds
// the extension's fill: the fill continues what the layer shows at the edge
// where it is hidden. Pixels deeper inside (a lamp 6 px below the
// ceiling's cut) would otherwise reach the hidden part through the fill's
// coarse levels (a ghost of the lamp over the whole ceiling behind a nearer
// band on the benchmark's Cornell box), and so would an edge that meets a
// farther layer or emptiness, which nothing is filled beside (the lamp's
// lower edge, where the ceiling's slice ends at the lamp's recess: a line of
// lamp light along the nearer band's blurred edge in one frame of a focus
// pull). A layer with no own pixel near its hidden ones (none, or only
// beyond kRim) takes the rim of all its coverage.
constexpr int kRim = 4;

// ExtendOptions::HighlightKnee::RimMedian: the knee is this many times the
// median of the rim's colours. A bound through the benchmark's Cornell lamp
// (17 on a ceiling at 0.002, the plate at 1920x1080 with the sphere of focus
// cut at 3.96 m by a step of 6 px) left wings beside the lamp 25 times the
// ceiling without a knee, 9 times with a knee at 1 and 4 times with this
// one; at 2 they were 2 times, but the plates' edges measured 0.3% worse
// (Cornell two planes at 640x360), at 8 they are unchanged.
constexpr float kRimMedianKnee = 8.0f;

// The knee above which the fill compresses colours (+inf: none), from the
// colours the fill is fed (`colour`: unpremultiplied R, G, B planes over
// the work region, read where `weight` > 0) that are not black.
float highlight_knee(ExtendOptions::HighlightKnee mode, const std::array<float*, 7>& colour,
                     const FrameBuffer<float>& weight, int ww, int wh, const Exec& exec) {
    using Knee = ExtendOptions::HighlightKnee;
    if (mode == Knee::None) return std::numeric_limits<float>::infinity();
    if (mode == Knee::One) return 1.0f;
    std::vector<std::vector<float>> rows(static_cast<std::size_t>(wh));
    parallel_for(exec, wh, [&](long r0, long r1) {
        for (long y = r0; y < r1; ++y) {
            std::vector<float>& out = rows[std::size_t(y)];
            for (std::size_t wi = std::size_t(y) * std::size_t(ww); wi < std::size_t(y + 1) * std::size_t(ww); ++wi) {
                if (!(weight[wi] > 0.0f)) continue;
                const float v = (colour[0][wi] + colour[1][wi] + colour[2][wi]) / 3.0f;
                // Black says nothing of the light's level: a rim mostly of
                // a shadowed face (0 on 14% of the Cornell plate) would put
                // the knee at 0 and compress every colour like a log.
                if (v > 0.0f && std::isfinite(v)) out.push_back(v);
            }
        }
    }, 16);
    std::vector<float> all;
    for (const auto& r : rows) all.insert(all.end(), r.begin(), r.end());
    if (all.empty()) return 1.0f;
    const auto mid = all.begin() + std::ptrdiff_t(all.size() / 2);
    std::nth_element(all.begin(), mid, all.end());
    return std::clamp(kRimMedianKnee * *mid, 1e-6f, 1.0f);
}

// The pixels an extension fills, split by the grids they are filled on.
// `spun` (FillGrids::Spun, four pyramids): with one, the edge of what a
// layer continues behind a nearer one falls on the pyramid's cell
// boundaries and jumps by up to a cell as the picture moves by a pixel (the
// inside of a blurred pole over a checker flickered in a pan). `single`: the
// hidden pixels of a layer that backs the whole frame farther than the
// extension's reach from its own pixels, which no blur brings into view:
// one pyramid there (90% of the 4K frame benchmark's farthest layer's
// extension; all spun, its fill took 0.31 s, against 0.13 s split and 0.09 s
// on one grid).
struct FillPixels {
    FrameBuffer<unsigned char> spun, single;  // `single` empty: none
    bool any_spun = false;
};

// The fill of `planes` at `pixels` from the known ones (`weight`).
bool fill_extension(const ImageView& planes, const ConstImageView& weight, const FillPixels& pixels,
                    const Exec& exec) {
    bool known = true;
    if (pixels.any_spun) known = push_pull_fill(planes, weight, pixels.spun, exec, FillGrids::Spun);
    if (known && !pixels.single.empty())
        known = push_pull_fill(planes, weight, pixels.single, exec, FillGrids::Single);
    return known && (pixels.any_spun || !pixels.single.empty());
}

// Own pixels within kRim px of a `seed` pixel.
FrameBuffer<unsigned char> own_near(const FrameBuffer<unsigned char>& own, const FrameBuffer<unsigned char>& seed,
                                    int w, int h, const Exec& exec) {
    FrameBuffer<unsigned char> rim = image_detail::dilate_square(seed, w, h, kRim, exec);
    // Pointers and bounds by value: byte stores may alias anything reached
    // through a reference, which stops vectorisation.
    const std::size_t W = std::size_t(w);
    parallel_for(exec, h, [o = own.data(), r = rim.data(), W](long r0, long r1) {
        for (std::size_t i = std::size_t(r0) * W; i < std::size_t(r1) * W; ++i) r[i] = o[i] && r[i] ? 1 : 0;
    }, 64);
    return rim;
}

FrameBuffer<unsigned char> coverage_rim(const FrameBuffer<unsigned char>& own, const FrameBuffer<unsigned char>& ext,
                                        bool facing_fill, int w, int h, const Exec& exec) {
    if (facing_fill) {
        FrameBuffer<unsigned char> rim = own_near(own, ext, w, h, exec);
        if (std::any_of(rim.begin(), rim.end(), [](unsigned char v) { return v != 0; })) return rim;
    }
    FrameBuffer<unsigned char> uncovered(own.size());  // every element written
    const std::size_t W = std::size_t(w);
    parallel_for(exec, h, [o = own.data(), u = uncovered.data(), W](long r0, long r1) {
        for (std::size_t i = std::size_t(r0) * W; i < std::size_t(r1) * W; ++i) u[i] = !o[i];
    }, 64);
    return own_near(own, uncovered, w, h, exec);
}

}  // namespace

Result<ExtensionPlan> plan_extension(const std::vector<Layer>& layers, const Roi& frame, const ExtendOptions& opt,
                                     const Exec& exec) {
    ExtensionPlan plan;
    plan.frame = frame;
    const int nl = int(layers.size());
    if (nl >= int(ExtensionPlan::kNeverHidden))
        return Status::error("layer extension: " + std::to_string(nl) + " layers (at most " +
                             std::to_string(ExtensionPlan::kNeverHidden - 1) + ")");
    for (int s = 0; s < nl; ++s)
        if (!layers[std::size_t(s)].image.data_window().empty()) {
            if (plan.nearest < 0) plan.nearest = s;
            plan.farthest = s;
        }
    const std::size_t n = frame.npixels();
    parallel_assign(plan.hidden_from, n, ExtensionPlan::kNeverHidden, std::size_t(frame.width()), exec);
    std::vector<float> occ(n, 0.0f);
    FrameBuffer<float> alpha;
    FrameBuffer<unsigned char> own;
    for (int s = 0; s < nl; ++s) {
        if (exec.is_cancelled()) return Status::cancelled();
        const Image& img = layers[std::size_t(s)].image;
        const Roi box = intersect(img.data_window(), frame);
        if (box.empty()) continue;
        coverage(img, box, alpha, own, exec);
        const int BW = box.width();
        parallel_for(exec, box.height(), [&](long r0, long r1) {
            for (int y = int(r0); y < int(r1); ++y)
                for (int x = 0; x < BW; ++x) {
                    const std::size_t b = std::size_t(y) * std::size_t(BW) + std::size_t(x);
                    const std::size_t i = std::size_t(y + box.y0 - frame.y0) * std::size_t(frame.width()) +
                                          std::size_t(x + box.x0 - frame.x0);
                    if (opt.occluder_alpha > 0.0f) {
                        // The nearer layers' accumulated alpha, in layer order.
                        if (plan.hidden_from[i] != ExtensionPlan::kNeverHidden) continue;
                        occ[i] = occ[i] + alpha[b] * (1.0f - occ[i]);
                        if (occ[i] >= opt.occluder_alpha) plan.hidden_from[i] = std::uint16_t(s + 1);
                    } else if (own[b] && plan.hidden_from[i] == ExtensionPlan::kNeverHidden) {
                        plan.hidden_from[i] = std::uint16_t(s + 1);
                    }
                }
        }, 16);
    }
    return plan;
}

Status extend_layer(Layer& L, int s, const ExtensionPlan& plan, const ExtendOptions& opt, const Exec& exec) {
    const Roi& frame = plan.frame;
    const int FW = frame.width();
    const int grow = int(std::ceil(opt.extend_px));
    const Roi own_box = intersect(L.image.data_window(), frame);
    const bool fills_frame = opt.farthest_fills_frame && s == plan.farthest;
    if (s <= plan.nearest || own_box.empty() || !(grow > 0 || fills_frame)) return Status::ok();
    const Roi work = fills_frame ? frame : intersect(own_box.grown(grow), frame);
    const int ww = work.width(), wh = work.height();
    const std::size_t wn = work.npixels();
    auto fi = [&](int x, int y) {  // absolute -> frame index
        return std::size_t(y - frame.y0) * std::size_t(FW) + std::size_t(x - frame.x0);
    };
    FrameBuffer<float> alpha;
    FrameBuffer<unsigned char> own;
    coverage(L.image, work, alpha, own, exec);
    // Distance to the layer's own coverage (not needed where the owners'
    // distances are given, nor when the layer fills the frame).
    const bool with_owner_distance = !opt.owner.empty() && !opt.owner_distance.empty();
    FrameBuffer<float> dist;
    if (!fills_frame && !with_owner_distance) distance_transform(own, ww, wh, dist, exec, opt.extend_px);
    FrameBuffer<unsigned char> ext(wn), seen_empty(wn);  // every element written below
    // Rows marked in parallel, each with its own span of extension; the
    // union is taken after, in row order.
    std::vector<Roi> row_box(static_cast<std::size_t>(wh));
    parallel_for(exec, wh, [&](long r0, long r1) {
        // Locals: the byte stores below may alias anything reached through a
        // reference, which would reload every pointer per pixel.
        const std::uint16_t* hidden_from = plan.hidden_from.data();
        const int* owner = opt.owner.empty() ? nullptr : opt.owner.data();
        const float* owner_distance = with_owner_distance ? opt.owner_distance.data() : nullptr;
        const unsigned char* own_p = own.data();
        const float* dist_p = dist.empty() ? nullptr : dist.data();
        unsigned char *ext_p = ext.data(), *seen_p = seen_empty.data();
        const bool fades_at_emptiness_only = opt.coverage_fades_at_emptiness_only;
        const double extend_px = opt.extend_px;
        for (int y = int(r0); y < int(r1); ++y) {
            int xmin = ww, xmax = -1;
            const std::size_t wrow = std::size_t(y) * std::size_t(ww), frow = fi(work.x0, work.y0 + y);
            for (int x = 0; x < ww; ++x) {
                const std::size_t wi = wrow + std::size_t(x), i = frow + std::size_t(x);
                const bool hidden = s >= int(hidden_from[i]);
                // The farthest layer still backs what its owner's reach misses (an
                // opaque plate stays opaque), but not what borders emptiness.
                const bool allowed = !owner || owner[i] == s || (fills_frame && owner[i] >= 0);
                const bool empty_here = !fades_at_emptiness_only || hidden_from[i] == ExtensionPlan::kNeverHidden;
                seen_p[wi] = !hidden && !own_p[wi] && empty_here ? 1 : 0;
                ext_p[wi] = 0;
                if (!hidden || own_p[wi] || !allowed) continue;
                const float d = fills_frame ? 0.0f : owner_distance ? owner_distance[i] : dist_p[wi];
                if (fills_frame || double(d) <= extend_px) {
                    ext_p[wi] = 1;
                    xmin = std::min(xmin, x);
                    xmax = x;
                }
            }
            if (xmax >= 0) row_box[std::size_t(y)] = Roi{work.x0 + xmin, work.y0 + y, work.x0 + xmax + 1, work.y0 + y + 1};
        }
    }, 16);
    Roi box = L.image.data_window();
    bool any = false;
    for (const Roi& r : row_box)
        if (!r.empty()) box = unite(box, r), any = true;
    if (!any) return extend_ring(L, s, plan, opt, exec);  // nothing within extend_px

    // Spun where the extension reaches from the layer's own pixels (all of
    // it unless the layer backs the frame), one grid beyond.
    FillPixels fill_at;
    if (fills_frame) {
        const FrameBuffer<unsigned char> reach = image_detail::dilate_square(own, ww, wh, grow, exec);
        fill_at.spun.resize(wn);
        fill_at.single.resize(wn);
        std::vector<unsigned char> row_spun(static_cast<std::size_t>(wh), 0), row_single(static_cast<std::size_t>(wh), 0);
        parallel_for(exec, wh, [&](long r0, long r1) {
            const unsigned char *e = ext.data(), *r = reach.data();
            unsigned char *sp = fill_at.spun.data(), *si = fill_at.single.data();
            for (long y = r0; y < r1; ++y) {
                unsigned char n = 0, m = 0;
                for (std::size_t wi = std::size_t(y) * ww; wi < std::size_t(y + 1) * ww; ++wi) {
                    sp[wi] = e[wi] && r[wi] ? 1 : 0;
                    si[wi] = e[wi] && !r[wi] ? 1 : 0;
                    n |= sp[wi];
                    m |= si[wi];
                }
                row_spun[std::size_t(y)] = n;
                row_single[std::size_t(y)] = m;
            }
        }, 16);
        const auto set = [](unsigned char v) { return v != 0; };
        fill_at.any_spun = std::any_of(row_spun.begin(), row_spun.end(), set);
        if (!std::any_of(row_single.begin(), row_single.end(), set)) fill_at.single = {};
    } else {
        fill_at.spun = ext;
        fill_at.any_spun = true;
    }

    const Image& src = L.image;
    const bool has_p = src.nchannels() >= 8;
    const int nfill = has_p ? 7 : 4;  // r, g, b, Z (, P.x, P.y, P.z)
    // Frame-sized at 4K and left unset where the weight is 0: the fill reads
    // values only where the weight is > 0 and writes the wanted unknown ones,
    // the only ones read after it. The weights are set in the loop below.
    FrameBuffer<float> fill_planes(std::size_t(nfill) * wn);  // back to back over `work`
    std::array<float*, 7> fill{};
    for (int c = 0; c < nfill; ++c) fill[std::size_t(c)] = fill_planes.data() + std::size_t(c) * wn;
    FrameBuffer<float> wcol(wn), wgeo(wn);
    std::vector<unsigned char> same_weights(static_cast<std::size_t>(wh), 1);
    const FrameBuffer<unsigned char> rim = coverage_rim(own, ext, opt.fill_from_hidden_edge, ww, wh, exec);
    parallel_for(exec, wh, [&](long r0, long r1) {
        // Locals: the stores below may alias anything reached through a reference.
        const unsigned char* rim_p = rim.data();
        const float* alpha_p = alpha.data();
        float *wc = wcol.data(), *wg = wgeo.data();
        std::array<float*, 7> fp = fill;
        const std::array<const float*, 8> sp = layer_planes(src);
        for (int y = int(r0); y < int(r1); ++y) {
            const std::size_t wrow = std::size_t(y) * std::size_t(ww);
            std::fill_n(wc + wrow, ww, 0.0f);
            std::fill_n(wg + wrow, ww, 0.0f);
            bool same = true;
            for (int x = 0; x < ww; ++x) {
                const std::size_t wi = wrow + std::size_t(x);
                if (!rim_p[wi] || !(alpha_p[wi] > 0.0f)) continue;
                const float al = alpha_p[wi];
                wc[wi] = al;
                const std::size_t o = src.offset(work.x0 + x, work.y0 + y);
                for (int c = 0; c < 3; ++c) fp[std::size_t(c)][wi] = sp[std::size_t(c)][o] / sp[3][o];
                bool geo = std::isfinite(sp[4][o]);
                for (int k = 0; has_p && k < 3; ++k) geo = geo && std::isfinite(sp[std::size_t(5 + k)][o]);
                if (geo) {
                    wg[wi] = al;
                    fp[3][wi] = sp[4][o];
                    for (int k = 0; has_p && k < 3; ++k) fp[std::size_t(4 + k)][wi] = sp[std::size_t(5 + k)][o];
                } else {
                    same = false;
                }
            }
            if (!same) same_weights[std::size_t(y)] = 0;
        }
    }, 16);
    // Highlights enter the fill compressed above the knee (ExtendOptions::
    // fill_highlight_knee) and leave it expanded below.
    const float knee = highlight_knee(opt.fill_highlight_knee, fill, wcol, ww, wh, exec);
    if (std::isfinite(knee))
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (int c = 0; c < 3; ++c) {
                float* v = fill[std::size_t(c)];
                for (std::size_t wi = std::size_t(r0) * ww; wi < std::size_t(r1) * ww; ++wi)
                    if (wcol[wi] > 0.0f && v[wi] > knee) v[wi] = knee * (1.0f + std::log(v[wi] / knee));
            }
        }, 16);
    const ImageView fill_view = ImageView::planar(fill_planes.data(), nfill, work);
    // Colour and geometry share one fill when their weights are the same (no
    // sky or missing positions among the layer's pixels): the same bits, as
    // the fill treats planes independently given the weights.
    bool have_colour, have_depth;
    if (std::all_of(same_weights.begin(), same_weights.end(), [](unsigned char v) { return v != 0; })) {
        have_colour = have_depth = fill_extension(fill_view, ConstImageView::planar(wcol.data(), 1, work), fill_at, exec);
    } else {
        have_colour = fill_extension(fill_view.channels(0, 3), ConstImageView::planar(wcol.data(), 1, work), fill_at, exec);
        have_depth =
            fill_extension(fill_view.channels(3, nfill - 3), ConstImageView::planar(wgeo.data(), 1, work), fill_at, exec);
    }
    wgeo = {};
    if (std::isfinite(knee) && have_colour)
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (int c = 0; c < 3; ++c) {
                float* v = fill[std::size_t(c)];
                for (std::size_t wi = std::size_t(r0) * ww; wi < std::size_t(r1) * ww; ++wi)
                    if (ext[wi] && v[wi] > knee) v[wi] = knee * std::exp(v[wi] / knee - 1.0f);
            }
        }, 16);
    // The continued coverage (continue_coverage): own alpha (plates, fading at
    // emptiness only: own presence, 1), 0 where seen empty. Where nothing is
    // seen empty and every own pixel is opaque it is 1 everywhere, so the
    // fill is skipped (an opaque plate's layers, the frame-sized farthest too).
    FrameBuffer<float> cover, wcover;
    const bool presence_only = opt.coverage_fades_at_emptiness_only;
    bool coverage_continues = false;
    if (opt.continue_coverage) {
        std::vector<unsigned char> row_varies(static_cast<std::size_t>(wh), 0);
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (long y = r0; y < r1; ++y)
                for (std::size_t wi = std::size_t(y) * ww; wi < std::size_t(y + 1) * ww; ++wi)
                    if (seen_empty[wi] || (own[wi] && alpha[wi] < 1.0f && !presence_only)) {
                        row_varies[std::size_t(y)] = 1;
                        break;
                    }
        }, 16);
        coverage_continues = std::any_of(row_varies.begin(), row_varies.end(), [](unsigned char v) { return v != 0; });
    }
    if (coverage_continues) {
        cover.resize(wn);
        wcover.resize(wn);
        parallel_for(exec, wh, [&](long r0, long r1) {
            for (std::size_t wi = std::size_t(r0) * ww; wi < std::size_t(r1) * ww; ++wi) {
                cover[wi] = own[wi] ? (presence_only ? 1.0f : alpha[wi]) : 0.0f;
                wcover[wi] = own[wi] || seen_empty[wi] ? 1.0f : 0.0f;
            }
        }, 16);
        if (!fill_extension(ImageView::planar(cover.data(), 1, work), ConstImageView::planar(wcover.data(), 1, work),
                            fill_at, exec))
            std::fill(cover.begin(), cover.end(), 1.0f);
    }

    // Re-window the layer to include the extension (in place when it fits
    // in the layer's window already: a farthest layer that fills the frame).
    const Roi old = src.data_window();
    if (!(box == old)) rewindow_layer(L, box, exec);
    Image& out = L.image;
    parallel_for(exec, wh, [&](long r0, long r1) {
        // Locals: the float stores below may alias anything reached through a reference.
        const unsigned char* ext_p = ext.data();
        const float* cover_p = coverage_continues ? cover.data() : nullptr;
        const std::array<float*, 7> fp = fill;
        const std::array<float*, 8> op = layer_planes(out);
        for (int y = int(r0); y < int(r1); ++y) {
            const std::size_t wrow = std::size_t(y) * std::size_t(ww);
            const std::size_t orow = out.offset(work.x0, work.y0 + y);
            for (int x = 0; x < ww; ++x) {
                const std::size_t wi = wrow + std::size_t(x);
                if (!ext_p[wi]) continue;
                const std::size_t o = orow + std::size_t(x);
                const float a = cover_p ? std::clamp(cover_p[wi], 0.0f, 1.0f) : 1.0f;
                for (int c = 0; c < 3; ++c) op[std::size_t(c)][o] = have_colour ? fp[std::size_t(c)][wi] * a : 0.0f;
                op[3][o] = a;
                op[4][o] = have_depth ? fp[3][wi] : float(kInf);
                for (int k = 0; has_p && k < 3; ++k) op[std::size_t(5 + k)][o] = have_depth ? fp[std::size_t(4 + k)][wi] : kNaN;
            }
        }
    }, 16);
    return extend_ring(L, s, plan, opt, exec);
}

void rewindow_layer(Layer& L, const Roi& box, const Exec& exec) {
    const Image& src = L.image;
    const Roi old = src.data_window();
    Image out = Image::uninitialized(src.channels(), box, src.display_window());  // every row written below
    out.metadata = src.metadata;
    out.name = src.name;
    out.view = src.view;
    parallel_for(exec, box.height(), [&](long r0, long r1) {
        for (int y = box.y0 + int(r0); y < box.y0 + int(r1); ++y)
            for (int c = 0; c < out.nchannels(); ++c) {
                if (!out.plane(c)) continue;
                float* row = out.plane(c) + out.offset(box.x0, y);
                const bool in_old = y >= old.y0 && y < old.y1 && !old.empty();
                const int xa = in_old ? old.x0 : box.x1, xb = in_old ? old.x1 : box.x1;
                const float blank = blank_layer_value(c);
                std::fill(row, row + (xa - box.x0), blank);
                if (in_old) std::copy_n(src.plane(c) + src.offset(old.x0, y), old.width(), row + (xa - box.x0));
                std::fill(row + (xb - box.x0), row + box.width(), blank);
            }
    }, 16);
    L.image = std::move(out);
}

Status check_extendable(const Layer& L) {
    if (L.image.nchannels() < 5 || L.image.channel(3).name != "A" || L.image.channel(4).name != "Z")
        return Status::error("layer extension: layer '" + L.name + "' is not R, G, B, A, Z");
    return Status::ok();
}

Status check_extend_options(const ExtendOptions& opt, const Roi& frame) {
    if (!(opt.extend_px >= 0.0) || std::isinf(opt.extend_px))
        return Status::error("layer extension: extend_px must be finite and >= 0, got " + std::to_string(opt.extend_px));
    if (!opt.owner.empty() && opt.owner.size() != frame.npixels())
        return Status::error("layer extension: " + std::to_string(opt.owner.size()) + " owners for a frame of " +
                             std::to_string(frame.npixels()) + " pixels");
    if (!(opt.surface_reach_px >= 0.0) || std::isinf(opt.surface_reach_px))
        return Status::error("layer extension: surface_reach_px must be finite and >= 0, got " +
                             std::to_string(opt.surface_reach_px));
    if (!opt.front_depth.empty() && opt.front_depth.size() != frame.npixels())
        return Status::error("layer extension: " + std::to_string(opt.front_depth.size()) +
                             " front depths for a frame of " + std::to_string(frame.npixels()) + " pixels");
    if (!(opt.continuity >= 1.0) || std::isinf(opt.continuity))
        return Status::error("layer extension: continuity must be finite and >= 1, got " + std::to_string(opt.continuity));
    if (!opt.owner_distance.empty() && opt.owner_distance.size() != opt.owner.size())
        return Status::error("layer extension: " + std::to_string(opt.owner_distance.size()) +
                             " owner distances for " + std::to_string(opt.owner.size()) + " owners");
    return Status::ok();
}

}  // namespace layers_detail

using namespace layers_detail;

Status extend_layers_behind(std::vector<Layer>& layers, const Roi& frame, const ExtendOptions& opt, const Exec& exec) {
    if (Status st = check_extend_options(opt, frame); !st) return st;
    if (frame.empty() || layers.size() < 2) return Status::ok();
    for (const Layer& L : layers)
        if (Status st = check_extendable(L); !st) return st;
    auto plan = plan_extension(layers, frame, opt, exec);
    if (!plan) return plan.status();
    for (int s = 0; s < int(layers.size()); ++s) {
        if (exec.is_cancelled()) return Status::cancelled();
        if (Status st = extend_layer(layers[std::size_t(s)], s, *plan, opt, exec); !st) return st;
    }
    return Status::ok();
}

}  // namespace gdof
