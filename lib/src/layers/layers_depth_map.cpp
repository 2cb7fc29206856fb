// Flat RGBA + depth -> depth slices, with continued surfaces and background
// extension (layers.h).
//
//   1. per pixel: its depth (the prepared plate depth, or the decoded depth
//      channel) and, for a split mixed pixel, its foreground's depth and share;
//   2. slices from all sample depths (and radii: Auto's blur cuts);
//   3. per slice, in parallel: its own samples, then the pixels of nearer
//      slices that continue its surface (continuation.cpp), into one image;
//   4. extension behind the nearer slices (layers_extend.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "layers/layers_internal.h"

namespace gdof {

using namespace layers_detail;

namespace {

// What the slicer sees of a plate: one sample per present pixel, two for a
// split mixed pixel.
struct PlateSamples {
    std::vector<float> depth;          // per pixel (+inf: sky, far slice); meaningful where present
    std::vector<unsigned char> present;
    std::vector<int> mixed;            // per pixel: index into PlateDepth::mixed, -1 if not mixed (empty: none)
    const std::vector<MixedPixel>* parts = nullptr;
    const MixedPixel* mixed_at(std::size_t i) const {
        return mixed.empty() || mixed[i] < 0 ? nullptr : &(*parts)[std::size_t(mixed[i])];
    }
};

// A bound between a front's surface and its own edge pixels (anti-aliased
// ones, a little deeper than the front but within `continuity` of it) would
// leave those in a farther slice: a sliver that blurs alone and, nearest to
// the pixels the front hides, continues the background there with the
// front's colour. Each pixel at a silhouette (a neighbour beyond
// `continuity`, farther) that continues the surface of a 4-neighbour in a
// nearer slice joins that slice (the nearest of them). Pixels split in two
// (fg_slice) stay as they are.
void edges_join_their_front(FrameBuffer<int>& slice, const FrameBuffer<int>& fg_slice, const std::vector<float>& depth,
                            int W, int H, double continuity, const Exec& exec) {
    // Decided on the slices as assigned, written after.
    std::vector<std::vector<std::pair<std::size_t, int>>> joins(static_cast<std::size_t>(H));
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                const int s = slice[i];
                if (s <= 0 || fg_slice[i] >= 0) continue;
                // Most pixels: no 4-neighbour in a nearer slice.
                auto nearer = [&](std::size_t j) { return slice[j] >= 0 && slice[j] < s; };
                if (!((x > 0 && nearer(i - 1)) || (x + 1 < W && nearer(i + 1)) ||
                      (y > 0 && nearer(i - std::size_t(W))) || (y + 1 < H && nearer(i + std::size_t(W)))))
                    continue;
                const float d = depth[i];
                int front = s;
                bool silhouette = false;
                for (long yy = std::max(0L, y - 1); yy <= std::min(long(H) - 1, y + 1); ++yy)
                    for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx) {
                        const std::size_t j = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
                        if (j == i || slice[j] < 0) continue;
                        const float q = depth[j];
                        if (double(q) > double(d) * continuity) silhouette = true;
                        const bool four = xx == x || yy == y;
                        if (four && slice[j] < front && same_surface(d, q, continuity)) front = slice[j];
                    }
                if (silhouette && front < s) joins[std::size_t(y)].emplace_back(i, front);
            }
    }, 16);
    for (const auto& row : joins)
        for (const auto& [i, s] : row) slice[i] = s;
}

Status plate_samples(const Image& img, const SliceOptions& o, const float* r, const float* g, const float* b,
                     const float* a, PlateSamples& s, const Exec& exec) {
    const std::size_t n = img.npixels();
    const std::size_t W = std::size_t(std::max(1, img.data_window().width()));
    const long rows = long((n + W - 1) / W);
    s.present.resize(n);
    parallel_for(exec, rows, [&](long y0, long y1) {
        for (std::size_t i = std::size_t(y0) * W; i < std::min(n, std::size_t(y1) * W); ++i)
            s.present[i] = (!a || a[i] > 0.0f || r[i] != 0.0f || g[i] != 0.0f || b[i] != 0.0f) ? 1 : 0;
    }, 16);
    if (o.depth) {
        if (!(o.depth->window == img.data_window()) || o.depth->depth.size() != n)
            return Status::error("depth-map layers: the prepared depth covers " + to_string(o.depth->window) +
                                 ", the image " + to_string(img.data_window()));
        s.depth.resize(n);
        parallel_for(exec, rows, [&](long y0, long y1) {
            for (std::size_t i = std::size_t(y0) * W; i < std::min(n, std::size_t(y1) * W); ++i) {
                const float d = o.depth->depth[i];
                s.depth[i] = std::isfinite(d) ? d : float(kInf);
            }
        }, 16);
        if (o.depth->has_mixed()) {
            s.parts = &o.depth->mixed;
            s.mixed.assign(n, -1);
            for (std::size_t k = 0; k < o.depth->mixed.size(); ++k) s.mixed[o.depth->mixed[k].index] = int(k);
        }
        return Status::ok();
    }
    const PositionSource& src = o.source;
    auto zc = find_depth_channel(img, src.depth_channel);
    if (!zc) return zc.status();
    if (*zc < 0)
        return Status::error("depth-map layers: no depth channel (looked for Z, depth.Z, Depth.Z, depth, Depth)",
                             StatusCode::NotFound, "depth_channel");
    if (Status st = src.depth_decode.validate(); !st) return st.prefix("depth channel '" + img.channel(*zc).name + "'");
    const float* zraw = img.plane(*zc);
    s.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = decode_depth(zraw[i], src.depth_decode);
        s.depth[i] = std::isfinite(d) ? float(d) : float(kInf);
    }
    return Status::ok();
}

// The layers of a plate, made one at a time (LayerSource). Everything that
// concerns all slices is prepared once: each pixel's slice (and its
// foreground part's), the slices' boxes and depth ranges, the background
// owner of every pixel (and its distance), and where each pixel is hidden.
class PlateLayers final : public LayerSource {
public:
    static Result<std::unique_ptr<LayerSource>> create(const Image& img, const SliceOptions& options, const Exec& exec);

    int size() const override { return slices_.count(); }
    Roi frame() const override { return frame_; }
    Roi display_window() const override { return img_.display_window(); }
    Result<const Layer*> make(int s, Layer& storage, const Exec& exec) const override;

private:
    explicit PlateLayers(const Image& img) : img_(img) {}

    // What a slice holds of pixel i: whole (its own slice), its foreground
    // part (a split mixed pixel whose foreground is in the slice), or nothing.
    struct Part {
        float rgb[3], alpha, z;
    };
    bool part_of(std::size_t i, int s, Part& p, bool continued = false) const;
    // Layer s before its extension: its own pixels (and, with continued
    // surfaces, those of nearer slices that continue its surface).
    Status make_base(int s, Layer& L, const Exec& exec) const;
    friend Result<std::vector<Layer>> continued_layers(const Image&, const SliceOptions&, const Exec&);

    const Image& img_;
    SliceOptions options_;  // spans and depth cleared: used only by create()
    const float *r_ = nullptr, *g_ = nullptr, *b_ = nullptr, *a_ = nullptr;
    std::optional<std::array<int, 3>> pos_;
    PlateSamples ps_;
    std::vector<MixedPixel> mixed_parts_;  // ps_.parts points here
    DepthSlices slices_;
    FrameBuffer<int> slice_, fg_slice_;  // per pixel; -1: none
    std::vector<Roi> box_;               // per slice: its own pixels
    Roi frame_;                          // their union (extensions stay inside)
    std::vector<double> znear_, zfar_;
    FrameBuffer<int> owner_;
    FrameBuffer<float> owner_distance_;
    ExtensionPlan plan_;
    ExtendOptions extend_;
};

bool PlateLayers::part_of(std::size_t i, int s, Part& p, bool continued) const {
    const bool whole = slice_[i] == s || continued;
    if (!whole && fg_slice_[i] != s) return false;
    // A split pixel: its foreground part in the foreground's slice, its
    // background part where the pixel is whole. When both parts fall in one
    // slice it is whole there, at the foreground's depth: the foreground's
    // blur must carry it, as every mixed pixel's (plate.h, step 4). At the
    // background's depth a pole's edge pixel took the blur of the floor
    // behind it (generated scene, degraded depth: edge error 0.0701 ->
    // 0.0660 with the thin lens).
    const MixedPixel* m = ps_.mixed_at(i);
    const bool split = m && fg_slice_[i] >= 0;
    const float alpha = a_ ? a_[i] : 1.0f;
    if (!whole) {
        for (int c = 0; c < 3; ++c) p.rgb[c] = m->fg_share * m->fg_rgb[c];
        p.alpha = m->fg_share * alpha;
        p.z = m->fg_depth;
    } else {
        const float rgb[3] = {r_[i], g_[i], b_[i]};
        for (int c = 0; c < 3; ++c) p.rgb[c] = split ? m->bg_rgb[c] : rgb[c];
        p.alpha = alpha;
        p.z = m && !split ? m->fg_depth : ps_.depth[i];
    }
    return true;
}

Result<std::unique_ptr<LayerSource>> PlateLayers::create(const Image& img, const SliceOptions& options,
                                                         const Exec& exec) {
    const RgbaIndices ix = find_rgba(img);
    for (auto [c, name] : {std::pair{ix.r, "R"}, std::pair{ix.g, "G"}, std::pair{ix.b, "B"}})
        if (c < 0 || img.channel(c).type == PixelType::UInt)
            return Status::error(std::string("depth-map layers: no colour channel '") + name + "'");
    if (ix.a >= 0 && img.channel(ix.a).type == PixelType::UInt)
        return Status::error("depth-map layers: alpha channel '" + img.channel(ix.a).name + "' is not a float channel");
    if (options.split.mode == LayerSplit::Mode::ById)
        return Status::error("depth-map layers: split by id ('" + options.split.id_channel +
                             "') needs a deep image; use 'auto' or a layer count");
    if (!(options.extend_px >= 0.0) || std::isinf(options.extend_px))
        return Status::error("depth-map layers: extend_px must be finite and >= 0, got " + std::to_string(options.extend_px));
    if (!(options.surface_reach_px >= 0.0) || std::isinf(options.surface_reach_px))
        return Status::error("depth-map layers: surface_reach_px must be finite and >= 0, got " +
                             std::to_string(options.surface_reach_px));
    if (!(options.continuity > 1.0) || !(options.continuity < 2.0))
        return Status::error("depth-map layers: continuity must be in (1, 2), got " + std::to_string(options.continuity));
    std::unique_ptr<PlateLayers> L(new PlateLayers(img));
    // With a prepared depth, positions come from the layers' depth and the
    // camera: a mixed pixel's position pass is as mixed as its filtered Z.
    if (!options.depth) {
        auto pr = find_position_channels(img, options.source.position_channels);
        if (!pr) return pr.status();
        L->pos_ = *pr;
    }
    const Roi win = img.data_window();
    const int W = win.width(), H = win.height();
    const std::size_t n = img.npixels();
    L->r_ = img.plane(ix.r);
    L->g_ = img.plane(ix.g);
    L->b_ = img.plane(ix.b);
    L->a_ = ix.a >= 0 ? img.plane(ix.a) : nullptr;
    PlateSamples& ps = L->ps_;
    if (Status st = plate_samples(img, options, L->r_, L->g_, L->b_, L->a_, ps, exec); !st) return st;
    if (ps.parts) {  // keep our own copy: the prepared depth need not outlive the source
        L->mixed_parts_ = *ps.parts;
        ps.parts = &L->mixed_parts_;
    }
    if (!options.radius.empty() && options.radius.size() != n)
        return Status::error("depth-map layers: " + std::to_string(options.radius.size()) + " blur radii for " +
                             std::to_string(n) + " pixels");
    const std::size_t nmixed = ps.parts ? ps.parts->size() : 0;
    if (!options.fg_radius.empty() && options.fg_radius.size() != nmixed)
        return Status::error("depth-map layers: " + std::to_string(options.fg_radius.size()) +
                             " foreground blur radii for " + std::to_string(nmixed) + " mixed pixels");

    // Slices over every sample.
    std::vector<float> sample_depths, sample_radii;
    const bool radii = !options.radius.empty() && options.split.mode == LayerSplit::Mode::Auto;  // only auto cuts by blur
    {
        // Rows in parallel: each row's sample count, then its samples at
        // its offset (the order of a serial pass).
        std::vector<std::size_t> row_start(std::size_t(H) + 1, 0);
        parallel_for(exec, H, [&](long y0, long y1) {
            for (long y = y0; y < y1; ++y) {
                std::size_t c = 0;
                for (std::size_t i = std::size_t(y) * std::size_t(W); i < std::size_t(y + 1) * std::size_t(W); ++i)
                    if (ps.present[i]) c += ps.mixed_at(i) ? 2 : 1;
                row_start[std::size_t(y) + 1] = c;
            }
        }, 16);
        for (std::size_t y = 0; y < std::size_t(H); ++y) row_start[y + 1] += row_start[y];
        sample_depths.resize(row_start.back());
        if (radii) sample_radii.resize(row_start.back());
        parallel_for(exec, H, [&](long y0, long y1) {
            for (long y = y0; y < y1; ++y) {
                std::size_t o = row_start[std::size_t(y)];
                for (std::size_t i = std::size_t(y) * std::size_t(W); i < std::size_t(y + 1) * std::size_t(W); ++i) {
                    if (!ps.present[i]) continue;
                    sample_depths[o] = ps.depth[i];
                    if (radii) sample_radii[o] = options.radius[i];
                    ++o;
                    if (const MixedPixel* m = ps.mixed_at(i)) {
                        sample_depths[o] = m->fg_depth;
                        if (radii)
                            sample_radii[o] = options.fg_radius.empty() ? options.radius[i]
                                                                        : options.fg_radius[std::size_t(ps.mixed[i])];
                        ++o;
                    }
                }
            }
        }, 16);
    }
    SilhouetteGrid grid;
    const bool at_silhouettes = radii && options.cut_at_silhouettes;
    if (at_silhouettes) {
        grid.width = W;
        grid.height = H;
        grid.depth = ps.depth.data();
        grid.present = ps.present.data();
        grid.radius = options.radius.data();
        grid.continuity = options.continuity;
        grid.rgb[0] = L->r_;
        grid.rgb[1] = L->g_;
        grid.rgb[2] = L->b_;
        if (ps.parts)
            for (std::size_t k = 0; k < ps.parts->size(); ++k) {
                const MixedPixel& m = (*ps.parts)[k];
                const float r = options.radius[m.index];
                grid.fronts.push_back({m.fg_depth, options.fg_radius.empty() ? r : options.fg_radius[k], ps.depth[m.index], r});
            }
    }
    L->slices_ = choose_slices(sample_depths, options.split, sample_radii, exec, at_silhouettes ? &grid : nullptr);
    if (exec.is_cancelled()) return Status::cancelled("depth-map layers");
    sample_depths = {};
    sample_radii = {};
    const int ns = L->slices_.count();
    if (ns >= int(ExtensionPlan::kNeverHidden))
        return Status::error("depth-map layers: " + std::to_string(ns) + " slices (at most " +
                             std::to_string(ExtensionPlan::kNeverHidden - 1) + ")");
    L->slice_.resize(n);  // every element written below
    L->fg_slice_.resize(n);
    parallel_for(exec, H, [&](long y0, long y1) {
        for (std::size_t i = std::size_t(y0) * std::size_t(W); i < std::size_t(y1) * std::size_t(W); ++i) {
            L->slice_[i] = L->fg_slice_[i] = -1;
            if (!ps.present[i]) continue;
            L->slice_[i] = L->slices_.slice_of(ps.depth[i]);
            if (const MixedPixel* m = ps.mixed_at(i)) {
                const int f = L->slices_.slice_of(m->fg_depth);
                if (f != L->slice_[i]) L->fg_slice_[i] = f;  // in one slice the pixel is simply whole
            }
        }
    }, 16);
    edges_join_their_front(L->slice_, L->fg_slice_, ps.depth, W, H, options.continuity, exec);

    // Every slice's box and depth range, and where each pixel is hidden (the
    // slices behind the first that covers it). Bands of rows in parallel,
    // each with its own extents, merged after (min and max: any order).
    ExtensionPlan& plan = L->plan_;
    plan.frame = win;
    parallel_assign(plan.hidden_from, n, ExtensionPlan::kNeverHidden, std::size_t(W), exec);
    constexpr int kBand = 32;
    const int nbands = (H + kBand - 1) / kBand;
    struct Extent {
        Roi box;
        double znear = kInf, zfar = -kInf;
    };
    std::vector<Extent> band_extent(std::size_t(nbands) * std::size_t(ns));
    parallel_for(exec, nbands, [&](long b0, long b1) {
        // Per row, each slice's first and last column (a box per row, not per
        // pixel); depth ranges per pixel (min and max: any order).
        std::vector<int> xlo(static_cast<std::size_t>(ns)), xhi(static_cast<std::size_t>(ns));
        const int* sl = L->slice_.data();
        const int* fg = L->fg_slice_.data();
        std::uint16_t* hidden = plan.hidden_from.data();
        for (long b = b0; b < b1; ++b) {
            Extent* e = band_extent.data() + std::size_t(b) * std::size_t(ns);
            for (int y = int(b) * kBand; y < std::min(H, int(b + 1) * kBand); ++y) {
                std::fill(xlo.begin(), xlo.end(), W);
                std::fill(xhi.begin(), xhi.end(), -1);
                for (int x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                    for (int k = 0; k < 2; ++k) {
                        const int s = k == 0 ? sl[i] : fg[i];
                        if (s < 0) continue;
                        Part p{};  // always set: the pixel is in slice s
                        L->part_of(i, s, p);
                        xlo[std::size_t(s)] = std::min(xlo[std::size_t(s)], x);
                        xhi[std::size_t(s)] = x;
                        Extent& x_e = e[s];
                        x_e.znear = std::min(x_e.znear, double(p.z));
                        x_e.zfar = std::max(x_e.zfar, double(p.z));
                        if (covers(p.rgb[0], p.rgb[1], p.rgb[2], p.alpha))
                            hidden[i] = std::min(hidden[i], std::uint16_t(s + 1));
                    }
                }
                for (int s = 0; s < ns; ++s)
                    if (xhi[std::size_t(s)] >= 0)
                        e[s].box = unite(e[s].box, Roi{win.x0 + xlo[std::size_t(s)], win.y0 + y,
                                                       win.x0 + xhi[std::size_t(s)] + 1, win.y0 + y + 1});
            }
        }
    });
    L->box_.assign(std::size_t(ns), Roi{});
    L->znear_.assign(std::size_t(ns), kInf);
    L->zfar_.assign(std::size_t(ns), -kInf);
    for (int b = 0; b < nbands; ++b)
        for (int s = 0; s < ns; ++s) {
            const Extent& e = band_extent[std::size_t(b) * std::size_t(ns) + std::size_t(s)];
            if (e.box.empty()) continue;
            L->box_[std::size_t(s)] = unite(L->box_[std::size_t(s)], e.box);
            L->znear_[std::size_t(s)] = std::min(L->znear_[std::size_t(s)], e.znear);
            L->zfar_[std::size_t(s)] = std::max(L->zfar_[std::size_t(s)], e.zfar);
        }
    for (int s = 0; s < ns; ++s)
        if (!L->box_[std::size_t(s)].empty()) {
            if (plan.nearest < 0) plan.nearest = s;
            plan.farthest = s;
            L->frame_ = unite(L->frame_, L->box_[std::size_t(s)]);
        }

    // Which slice continues or extends behind each pixel (the background
    // seen nearest to it).
    // Only owners within reach matter (the farthest fills beyond it); with
    // continued surfaces a layer's coverage grows by up to reach * sqrt(2)
    // before its own reach is measured.
    const double reach = std::max(options.extend_px, options.surface_reach_px);
    const double bound = options.continue_surfaces ? reach * 2.5 + 2.0 : reach;
    BackgroundOwners bo = background_owners(L->slice_, L->fg_slice_, ns, W, H, exec, bound);
    L->owner_ = std::move(bo.owner);
    L->owner_distance_ = std::move(bo.distance);

    // Plates: the background is everywhere, so the farthest slice fills every
    // hidden pixel; nearer slices reach extend_px behind their neighbours.
    L->options_ = options;
    L->options_.radius = {};
    L->options_.fg_radius = {};
    L->options_.depth = nullptr;
    L->extend_.extend_px = options.extend_px;
    L->extend_.farthest_fills_frame = true;
    // Continued coverage toward emptiness: an extension fades toward the
    // pixels where no layer has a sample (a render's transparent background),
    // so a nearer layer's blurred edge does not reveal an opaque strip of
    // colour that the plate never showed behind it (the back wall's colour
    // behind the edge of a side wall, against the void). Where a farther
    // layer is seen the extension stays opaque: an opaque plate is extended
    // as before. (Fading there too, as deep renders do, lowered the Cornell
    // box's edge error further but raised the generated scene's overall
    // error with the sphere of focus by 4%.)
    L->extend_.continue_coverage = true;
    L->extend_.coverage_fades_at_emptiness_only = true;
    L->extend_.occluder_alpha = 0.0f;
    L->extend_.owner = L->owner_;
    L->extend_.owner_distance = L->owner_distance_;
    L->extend_.fill_from_hidden_edge = true;
    L->extend_.fill_highlight_knee = ExtendOptions::HighlightKnee::RimMedian;
    L->extend_.surface_reach_px = options.surface_reach_px;
    L->extend_.front_depth = L->ps_.depth;
    L->extend_.continuity = options.continuity;
    return std::unique_ptr<LayerSource>(std::move(L));
}

Status PlateLayers::make_base(int s, Layer& L, const Exec& exec) const {
    if (s < 0 || s >= size()) return Status::error("depth-map layers: no layer " + std::to_string(s));
    const Roi win = img_.data_window();
    const int W = win.width(), H = win.height();
    const Roi& own = box_[std::size_t(s)];
    const bool empty = own.empty();
    L = Layer{};
    L.depth_near = empty ? std::numeric_limits<double>::quiet_NaN() : znear_[std::size_t(s)];
    L.depth_far = empty ? std::numeric_limits<double>::quiet_NaN() : zfar_[std::size_t(s)];
    L.slice_near = slices_.lo[std::size_t(s)];
    L.slice_far = slices_.hi[std::size_t(s)];
    L.name = empty ? depth_range_name(L.slice_near, L.slice_far) + " (empty)" : depth_range_name(L.depth_near, L.depth_far);
    Roi box = own;
    std::vector<unsigned char> cont;
    const int reach = options_.continue_surfaces ? int(std::ceil(options_.extend_px)) : 0;
    if (!empty && reach > 0)
        box = unite(box, continue_surface(ps_.depth, ps_.present, slice_, owner_, s, W, H, win, options_.continuity, reach, cont));
    L.onward_marked = options_.mark_onward;
    if (!empty && options_.mark_onward && options_.extend_px > 0.0) {
        const SurfaceOnwardInput in{W, H, ps_.depth, ps_.present, slice_, fg_slice_, ps_.mixed, options_.continuity};
        const Roi own_rel{own.x0 - win.x0, own.y0 - win.y0, own.x1 - win.x0, own.y1 - win.y0};
        SurfaceOnward onward = surface_onward(in, s, own_rel, int(std::ceil(options_.extend_px)), exec);
        const Roi& b = onward.box;
        if (!b.empty()) {
            L.onward_box = Roi{b.x0 + win.x0, b.y0 + win.y0, b.x1 + win.x0, b.y1 + win.y0};
            L.onward = std::move(onward.mask);  // the same box, in absolute coordinates
            box = unite(box, L.onward_box);
        }
    }
    L.image = layer_image(pos_.has_value(), box, img_.display_window(), img_.metadata, L.name, img_.view);
    const float* pp[3] = {pos_ ? img_.plane((*pos_)[0]) : nullptr, pos_ ? img_.plane((*pos_)[1]) : nullptr,
                          pos_ ? img_.plane((*pos_)[2]) : nullptr};
    Image& out = L.image;
    const bool done = parallel_for(exec, box.height(), [&](long r0, long r1) {
        // Each row blank first (RGBA 0, Z and P NaN: whole-row fills), then
        // the slice's pixels written over it.
        const int nch = std::min(8, out.nchannels());
        const std::array<float*, 8> op = layer_planes(out);
        const int* sl = slice_.data();
        const int* fg = fg_slice_.data();
        const unsigned char* ct = cont.empty() ? nullptr : cont.data();
        const int bw = box.width();
        for (int y = box.y0 + int(r0); y < box.y0 + int(r1); ++y) {
            const std::size_t orow = out.offset(box.x0, y);
            const std::size_t irow = std::size_t(y - win.y0) * std::size_t(W) + std::size_t(box.x0 - win.x0);
            for (int c = 0; c < nch; ++c) std::fill_n(op[std::size_t(c)] + orow, bw, blank_layer_value(c));
            for (int x = 0; x < bw; ++x) {
                const std::size_t i = irow + std::size_t(x), o = orow + std::size_t(x);
                const bool continued = ct && ct[i];
                if (sl[i] != s && fg[i] != s && !continued) continue;  // blank
                Part p;
                if (!part_of(i, s, p, continued)) continue;
                for (int c = 0; c < 3; ++c) op[std::size_t(c)][o] = p.rgb[c];
                op[3][o] = p.alpha;
                op[4][o] = p.z;
                if (pos_)
                    for (int c = 0; c < 3; ++c) op[std::size_t(5 + c)][o] = pp[c][i];
            }
        }
    }, 8);
    if (!done) return Status::cancelled("depth-map layers");
    if (!L.onward.empty()) write_onward(L, win, ps_.depth.data(), {pp[0], pp[1], pp[2]});
    return Status::ok();
}

Result<const Layer*> PlateLayers::make(int s, Layer& L, const Exec& exec) const {
    if (Status st = make_base(s, L, exec); !st) return st;
    if (Status st = extend_layer(L, s, plan_, extend_, exec); !st) return st;
    // Own pixels: whole, or a split pixel's foreground part. Any other
    // covered pixel is extension, hidden by a nearer slice, whose surface
    // the plate's depth there is.
    const int *sl = slice_.data(), *fg = fg_slice_.data();
    mark_seams(L, img_.data_window(), ps_.depth.data(), nullptr, options_.continuity,
               [sl, fg, s](std::size_t i, int, int) { return sl[i] == s || fg[i] == s; }, exec);
    return &L;
}

// The list with continued surfaces (SliceOptions::continue_surfaces): a
// slice's own pixels then include the continued ones of nearer slices,
// which its neighbours' hiding depends on, so every slice is made first and
// all are extended together (with their own reach: a continued slice's
// coverage is more than the pixels its owners were chosen by).
Result<std::vector<Layer>> continued_layers(const Image& img, const SliceOptions& options, const Exec& exec) {
    auto src = PlateLayers::create(img, options, exec);
    if (!src) return src.status();
    const auto& P = static_cast<const PlateLayers&>(**src);
    std::vector<Layer> layers(static_cast<std::size_t>(P.size()));
    for (int s = 0; s < P.size(); ++s) {
        if (exec.is_cancelled()) return Status::cancelled();
        if (Status st = P.make_base(s, layers[std::size_t(s)], exec); !st) return st;
    }
    ExtendOptions ext = P.extend_;
    ext.owner_distance = {};
    if (Status st = extend_layers_behind(layers, img.data_window(), ext, exec); !st) return st;
    return layers;
}

}  // namespace

Result<std::unique_ptr<LayerSource>> depth_map_layer_source(const Image& img, const SliceOptions& options,
                                                            const Exec& exec) {
    if (!options.continue_surfaces) return PlateLayers::create(img, options, exec);
    // With continued surfaces a slice's own pixels include the continued
    // ones of nearer slices, which its neighbours' hiding depends on: the
    // layers are all made first and served.
    auto layers = continued_layers(img, options, exec);
    if (!layers) return layers.status();
    return source_of(std::move(layers).value());
}

Result<std::vector<Layer>> layers_from_depth_map(const Image& img, const SliceOptions& options, const Exec& exec) {
    if (options.continue_surfaces) return continued_layers(img, options, exec);
    auto src = PlateLayers::create(img, options, exec);
    if (!src) return src.status();
    return make_all(**src, exec);
}

}  // namespace gdof
