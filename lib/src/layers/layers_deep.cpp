// Deep image -> layers (by depth clusters, depth count or id), and flattening.
//
// Sample rules (shared by layers_from_deep and flatten_deep):
// - A pixel's samples are sorted by Z (ties keep file order) and composited
//   front to back with `over`; deep samples may be stored unsorted.
// - ZBack (volumetric samples) is ignored: a sample counts at its Z.
// - Z NaN or -inf, or a non-finite alpha, is an error naming the pixel and
//   sample (nothing is silently dropped). Z = +inf (sky) is allowed and
//   belongs to the farthest layer; Z <= 0 belongs to the nearest.
// - No A channel: samples are opaque. R, G, B and Z are required.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "layers/layers_internal.h"

namespace gdof {

using namespace layers_detail;

namespace {

int find_any(const DeepImage& d, std::initializer_list<const char*> names) {
    for (const char* n : names) {
        int i = d.channel_index(n);
        if (i >= 0 && d.channel(i).type != PixelType::UInt) return i;
    }
    return -1;
}

struct DeepChannels {
    int r = -1, g = -1, b = -1, a = -1, z = -1;
    std::optional<std::array<int, 3>> p;
};

Result<DeepChannels> deep_channels(const DeepImage& deep) {
    DeepChannels c;
    c.r = find_any(deep, {"R", "r", "red"});
    c.g = find_any(deep, {"G", "g", "green"});
    c.b = find_any(deep, {"B", "b", "blue"});
    c.a = find_any(deep, {"A", "a", "alpha"});
    c.z = deep.z_channel();
    if (c.z >= 0 && deep.channel(c.z).type == PixelType::UInt) c.z = -1;
    if (c.z < 0) return Status::error("deep image has no depth channel 'Z'");
    for (auto [ch, name] : {std::pair{c.r, "R"}, std::pair{c.g, "G"}, std::pair{c.b, "B"}})
        if (ch < 0) return Status::error(std::string("deep image has no colour channel '") + name + "'");
    static const char* const kLayers[] = {"P", "Pworld", "p", "position", "Position"};
    static const char* const kSets[][3] = {
        {"x", "y", "z"}, {"X", "Y", "Z"}, {"R", "G", "B"}, {"r", "g", "b"}, {"red", "green", "blue"}};
    for (const char* layer : kLayers) {
        for (const auto& set : kSets) {
            std::array<int, 3> idx{};
            bool ok = true;
            for (int k = 0; k < 3 && ok; ++k) {
                idx[std::size_t(k)] = deep.channel_index(std::string(layer) + "." + set[k]);
                ok = idx[std::size_t(k)] >= 0 && deep.channel(idx[std::size_t(k)]).type != PixelType::UInt;
            }
            if (ok) {
                c.p = idx;
                break;
            }
        }
        if (c.p) break;
    }
    return c;
}

// First bad sample (in pixel order) as an error, else ok.
Status validate_samples(const DeepImage& deep, const DeepChannels& ch, const Exec& exec) {
    const Roi win = deep.data_window();
    const float* z = deep.samples(ch.z);
    const float* a = ch.a >= 0 ? deep.samples(ch.a) : nullptr;
    return parallel_run(exec, win.height(), [&](long r0, long r1) {
        for (int y = win.y0 + int(r0); y < win.y0 + int(r1); ++y)
            for (int x = win.x0; x < win.x1; ++x) {
                const std::size_t p = deep.pixel_index(x, y);
                const std::size_t s0 = deep.first_sample(p), n = deep.sample_count(p);
                for (std::size_t k = s0; k < s0 + n; ++k) {
                    const bool bad_z = std::isnan(z[k]) || z[k] == -std::numeric_limits<float>::infinity();
                    const bool bad_a = a && !std::isfinite(a[k]);
                    if (bad_z || bad_a)
                        return Status::error("deep pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") sample " +
                                             std::to_string(k - s0) + ": " + (bad_z ? "depth Z" : "alpha A") + " is " +
                                             std::to_string(bad_z ? z[k] : a[k]));
                }
            }
        return Status::ok();
    }, 16);
}

// Sample indices of pixel p sorted front to back (stable on ties).
void sorted_samples(const DeepImage& deep, const float* z, std::size_t p, std::vector<std::size_t>& order) {
    const std::size_t s0 = deep.first_sample(p), n = deep.sample_count(p);
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = s0 + i;
    std::sort(order.begin(), order.end(), [z](std::size_t i, std::size_t j) { return z[i] < z[j] || (z[i] == z[j] && i < j); });
}

// Front-to-back `over` of samples.
struct Over {
    double r = 0, g = 0, b = 0, a = 0;
    double zsum = 0, wsum = 0, first_z = 0;
    std::array<double, 3> psum{0, 0, 0};
    bool any = false;
    void add(double sr, double sg, double sb, double sa, double sz, const std::array<double, 3>* sp) {
        if (!any) first_z = sz;
        any = true;
        const double t = 1.0 - a;
        r += t * sr;
        g += t * sg;
        b += t * sb;
        a += t * sa;
        const double w = t * sa;  // this sample's contribution to the pixel
        if (w > 0) {
            zsum += w * sz;
            wsum += w;
            if (sp)
                for (int k = 0; k < 3; ++k) psum[std::size_t(k)] += w * (*sp)[std::size_t(k)];
        }
    }
    // Contribution-weighted mean depth; the nearest sample's when nothing contributes.
    double mean_z() const { return wsum > 0 ? zsum / wsum : first_z; }
};

// Every sample's layer, and the layers' names (ById) or slice intervals.
struct SampleLayers {
    std::vector<std::int32_t> layer_of;  // per sample
    int count = 0;
    std::vector<std::string> names;          // ById
    std::vector<double> slice_lo, slice_hi;  // depth splits
};

// One layer per id, ordered by the median depth of its samples.
Result<SampleLayers> layers_by_id(const DeepImage& deep, const float* z, const std::string& id_channel) {
    const std::size_t nsamples = deep.total_samples();
    const int idc = deep.channel_index(id_channel);
    if (idc < 0) return Status::error("layer split by id: deep image has no channel '" + id_channel + "'");
    if (deep.channel(idc).type != PixelType::UInt)
        return Status::error("layer split by id: channel '" + id_channel + "' is not a uint channel");
    const std::uint32_t* ids = deep.usamples(idc);
    std::map<std::uint32_t, std::vector<float>> depths;
    for (std::size_t k = 0; k < nsamples; ++k) depths[ids[k]].push_back(z[k]);
    struct Entry {
        std::uint32_t id;
        double median;
    };
    std::vector<Entry> entries;
    for (auto& [id, zs] : depths) {
        double m = median_finite(zs);
        if (std::isnan(m)) m = kInf;  // only +inf samples
        entries.push_back({id, m});
    }
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.median < b.median; });
    SampleLayers sl;
    std::map<std::uint32_t, int> index;
    for (const Entry& e : entries) {
        index[e.id] = sl.count++;
        sl.names.push_back(id_channel + " " + std::to_string(e.id));
    }
    sl.layer_of.resize(nsamples);
    for (std::size_t k = 0; k < nsamples; ++k) sl.layer_of[k] = index[ids[k]];
    return sl;
}

// Depth slices (Auto or Count) of the sample depths.
SampleLayers layers_by_depth(std::span<const float> z, const LayerSplit& split, std::span<const float> sample_radius,
                             const Exec& exec, const SilhouetteGrid* grid) {
    const DepthSlices slices = choose_slices(z, split, sample_radius, exec, grid);
    SampleLayers sl;
    sl.count = slices.count();
    sl.slice_lo = slices.lo;
    sl.slice_hi = slices.hi;
    sl.layer_of.resize(z.size());
    constexpr long kBlock = 1 << 16;
    parallel_for(exec, long((z.size() + kBlock - 1) / kBlock), [&](long b0, long b1) {
        for (std::size_t k = std::size_t(b0 * kBlock); k < std::min(z.size(), std::size_t(b1 * kBlock)); ++k)
            sl.layer_of[k] = slices.slice_of(z[k]);
    });
    return sl;
}

// Bounding box and depth range of every layer's samples.
struct LayerExtents {
    std::vector<Roi> box;
    std::vector<double> znear, zfar;
};

LayerExtents layer_extents(const DeepImage& deep, const float* z, const SampleLayers& sl, const Exec& exec) {
    const Roi win = deep.data_window();
    const std::size_t nl = std::size_t(sl.count);
    // Bands of rows in parallel, each with its own extents, merged after.
    constexpr int kBand = 32;
    const int nbands = (win.height() + kBand - 1) / kBand;
    std::vector<LayerExtents> band(static_cast<std::size_t>(nbands));
    const bool banded = parallel_for(exec, nbands, [&](long b0, long b1) {
        for (long b = b0; b < b1; ++b) {
            LayerExtents& e = band[std::size_t(b)];
            e.box.resize(nl);
            e.znear.assign(nl, kInf);
            e.zfar.assign(nl, -kInf);
            for (int y = win.y0 + int(b) * kBand; y < std::min(win.y1, win.y0 + int(b + 1) * kBand); ++y)
                for (int x = win.x0; x < win.x1; ++x) {
                    const std::size_t p = deep.pixel_index(x, y);
                    const std::size_t s0 = deep.first_sample(p), n = deep.sample_count(p);
                    for (std::size_t k = s0; k < s0 + n; ++k) {
                        const std::size_t l = std::size_t(sl.layer_of[k]);
                        Roi& bx = e.box[l];
                        bx = bx.empty() ? Roi{x, y, x + 1, y + 1}
                                        : Roi{std::min(bx.x0, x), std::min(bx.y0, y), std::max(bx.x1, x + 1), std::max(bx.y1, y + 1)};
                        e.znear[l] = std::min(e.znear[l], double(z[k]));
                        e.zfar[l] = std::max(e.zfar[l], double(z[k]));
                    }
                }
        }
    });
    LayerExtents e;
    e.box.resize(nl);
    e.znear.assign(nl, kInf);
    e.zfar.assign(nl, -kInf);
    if (!banded) return e;  // cancelled: bands it skipped hold nothing (the caller reports it)
    for (const LayerExtents& b : band)
        for (std::size_t l = 0; l < nl; ++l) {
            e.box[l] = unite(e.box[l], b.box[l]);
            e.znear[l] = std::min(e.znear[l], b.znear[l]);
            e.zfar[l] = std::max(e.zfar[l], b.zfar[l]);
        }
    return e;
}

// A deep image's colour, alpha and depth samples (alpha 1 without an A channel).
struct SamplePlanes {
    const float *z, *r, *g, *b, *a;
    SamplePlanes(const DeepImage& deep, const DeepChannels& ch)
        : z(deep.samples(ch.z)), r(deep.samples(ch.r)), g(deep.samples(ch.g)), b(deep.samples(ch.b)),
          a(ch.a >= 0 ? deep.samples(ch.a) : nullptr) {}
    double alpha(std::size_t k) const { return a ? a[k] : 1.0; }
};

// pixel(x, y, order) for every pixel of the data window with samples, `order`
// its sample indices front to back. Parallel over rows; false if cancelled.
template <class PixelFn>
bool for_each_sorted_pixel(const DeepImage& deep, const float* z, const Exec& exec, PixelFn pixel) {
    const Roi win = deep.data_window();
    return parallel_for(exec, win.height(), [&](long r0, long r1) {
        std::vector<std::size_t> order;
        for (long row = r0; row < r1; ++row) {
            const int y = win.y0 + int(row);
            for (int x = win.x0; x < win.x1; ++x) {
                const std::size_t p = deep.pixel_index(x, y);
                if (deep.sample_count(p) == 0) continue;
                sorted_samples(deep, z, p, order);
                pixel(x, y, order);
            }
        }
    });
}

// The sample that owns a pixel (where the composite's coverage reaches one
// half; the last sample with coverage if it never does) and the nearest
// sample with coverage, of `order` (front to back); npos: no coverage.
struct PixelSurface {
    static constexpr std::size_t npos = std::size_t(-1);
    std::size_t owner = npos, first = npos;
};
PixelSurface pixel_surface(const SamplePlanes& s, const std::vector<std::size_t>& order) {
    PixelSurface ps;
    double acc = 0.0;
    for (std::size_t k : order) {
        const double a = std::clamp(s.alpha(k), 0.0, 1.0);
        if (!(a > 0.0)) continue;
        if (ps.first == PixelSurface::npos) ps.first = k;
        ps.owner = k;
        acc += (1.0 - acc) * a;
        if (acc >= 0.5) break;
    }
    return ps;
}

// Neighbouring depths within this ratio are one surface (as a plate's
// default SliceOptions::continuity).
constexpr double kContinuity = 1.05;

// A deep image's front surface seen as a plate, for diffusion's layering:
// - Auto's blur cuts at silhouettes (SilhouetteGrid; only when they are
//   made): per pixel the depth and radius of the sample that owns it
//   (pixel_surface: a faint veil in front does not), and the composited
//   light (what a bound may hide). A partial
//   sample in front of the owner (a silhouette pixel's other fragment) is
//   not given as a mixed pixel's front, as a plate's mixed pixels are: its
//   silhouette is already a neighbour's, and adding them moved the bound on
//   Cornell two planes (overall 0.0722 -> 0.0765, docs/diffusion.md).
// - Each layer's surface onward and seams, as a plate layer's (Layer::onward,
//   Layer::seam): the owner's depth (and position) per pixel, and once the
//   samples are sliced, the owner's slice and, where the nearest partial
//   sample lies in another, that one (a split pixel's foreground).
struct FrontSurface {
    std::vector<float> depth, radius, rgb[3], p[3];
    std::vector<unsigned char> present;
    std::vector<int> slice, fg_slice;
    SilhouetteGrid grid;
};

// `for_cuts`: with the radii and light the cuts need (sample_radius given).
std::unique_ptr<FrontSurface> front_surface(const DeepImage& deep, const DeepChannels& ch, std::span<const float> sample_radius,
                                            bool for_cuts, const Exec& exec) {
    const Roi win = deep.data_window();
    const std::size_t W = std::size_t(win.width()), n = win.npixels();
    auto f = std::make_unique<FrontSurface>();
    f->depth.assign(n, 0.0f);
    if (for_cuts) {
        f->radius.assign(n, 0.0f);
        for (auto& c : f->rgb) c.assign(n, 0.0f);
    }
    const float* sp[3] = {nullptr, nullptr, nullptr};
    if (ch.p)
        for (int c = 0; c < 3; ++c) {
            sp[c] = deep.samples((*ch.p)[std::size_t(c)]);
            f->p[c].assign(n, kNaN);
        }
    f->present.assign(n, 0);
    const SamplePlanes s(deep, ch);
    for_each_sorted_pixel(deep, s.z, exec, [&](int x, int y, const std::vector<std::size_t>& order) {
        const PixelSurface ps = pixel_surface(s, order);
        if (ps.owner == PixelSurface::npos) return;
        const std::size_t i = std::size_t(y - win.y0) * W + std::size_t(x - win.x0);
        f->present[i] = 1;
        f->depth[i] = s.z[ps.owner];
        if (for_cuts) {
            double acc = 0.0, cr = 0.0, cg = 0.0, cb = 0.0;
            for (std::size_t k : order) {
                const double t = 1.0 - acc;
                cr += t * s.r[k], cg += t * s.g[k], cb += t * s.b[k];
                acc += t * std::clamp(s.alpha(k), 0.0, 1.0);
            }
            f->radius[i] = sample_radius[ps.owner];
            f->rgb[0][i] = float(cr), f->rgb[1][i] = float(cg), f->rgb[2][i] = float(cb);
        }
        if (ch.p)
            for (int c = 0; c < 3; ++c) f->p[c][i] = sp[c][ps.owner];
    });
    if (!for_cuts) return f;
    SilhouetteGrid& g = f->grid;
    g.width = win.width();
    g.height = win.height();
    g.depth = f->depth.data();
    g.present = f->present.data();
    g.radius = f->radius.data();
    for (int c = 0; c < 3; ++c) g.rgb[c] = f->rgb[c].data();
    return f;
}

// The front surface's slices, once the samples are sliced (FrontSurface);
// the radii and light the cuts needed are dropped.
void slice_front_surface(FrontSurface& f, const DeepImage& deep, const DeepChannels& ch,
                         std::span<const std::int32_t> layer_of, const Exec& exec) {
    f.radius = {};
    for (auto& c : f.rgb) c = {};
    f.grid = SilhouetteGrid{};
    const Roi win = deep.data_window();
    const std::size_t W = std::size_t(win.width());
    f.slice.assign(win.npixels(), -1);
    f.fg_slice.assign(win.npixels(), -1);
    const SamplePlanes s(deep, ch);
    for_each_sorted_pixel(deep, s.z, exec, [&](int x, int y, const std::vector<std::size_t>& order) {
        const PixelSurface ps = pixel_surface(s, order);
        if (ps.owner == PixelSurface::npos) return;
        const std::size_t i = std::size_t(y - win.y0) * W + std::size_t(x - win.x0);
        f.slice[i] = layer_of[ps.owner];
        if (layer_of[ps.first] != f.slice[i]) f.fg_slice[i] = layer_of[ps.first];
    });
}

// R, G, B, A of a composited pixel, and `z` as its depth, at img's offset `off`.
void store_over(Image& img, std::size_t off, const Over& o, double z) {
    img.plane(0)[off] = float(o.r);
    img.plane(1)[off] = float(o.g);
    img.plane(2)[off] = float(o.b);
    img.plane(3)[off] = float(o.a);
    img.plane(4)[off] = float(z);
}

// The layers of a deep image, made one at a time (LayerSource): every
// sample's layer, the layers' boxes and names, and (with an extension)
// where each pixel is hidden are prepared once; make(l) composites layer l's
// samples of every pixel and extends the layer.
class DeepLayers final : public LayerSource {
public:
    static Result<std::unique_ptr<DeepLayers>> create(const DeepImage& deep, const LayerSplit& split,
                                                      std::span<const float> sample_radius, const ExtendOptions* extend,
                                                      const Exec& exec, bool by_front_surface);
    int size() const override { return sl_.count; }
    Roi frame() const override {  // the layers' boxes; extensions stay inside (hidden pixels have samples)
        Roi f;
        for (const Roi& b : ext_.box) f = unite(f, b);
        return f;
    }
    Roi display_window() const override { return deep_.display_window(); }
    Result<const Layer*> make(int l, Layer& storage, const Exec& exec) const override;

private:
    DeepLayers(const DeepImage& deep, const LayerSplit& split) : deep_(deep), split_(split) {}
    Status plan(const ExtendOptions& extend, const Exec& exec);
    // Layer l's surface onward (Layer::onward) over `box` grown to hold it,
    // as a plate layer's.
    void mark_onward(int l, Layer& L, Roi& box, const Exec& exec) const;

    const DeepImage& deep_;
    LayerSplit split_;
    DeepChannels ch_;
    SampleLayers sl_;
    LayerExtents ext_;
    bool extend_on_ = false;
    ExtendOptions extend_;
    ExtensionPlan plan_;
    std::unique_ptr<FrontSurface> front_;  // sliced by the front surface: onward and seams
    // Not sliced by it (the bokeh filter's slices of equal extent) but
    // extended behind a layer's own surface farther: the front surface for
    // that reach and the seams, without slices.
    std::unique_ptr<FrontSurface> seen_only_;
    const FrontSurface* seen() const { return front_ ? front_.get() : seen_only_.get(); }
};

Result<std::unique_ptr<DeepLayers>> DeepLayers::create(const DeepImage& deep, const LayerSplit& split,
                                                       std::span<const float> sample_radius,
                                                       const ExtendOptions* extend, const Exec& exec,
                                                       bool by_front_surface) {
    auto chr = deep_channels(deep);
    if (!chr) return chr.status();
    std::unique_ptr<DeepLayers> D(new DeepLayers(deep, split));
    D->ch_ = *chr;
    if (Status st = validate_samples(deep, D->ch_, exec); !st) return st;
    const std::size_t nsamples = deep.total_samples();
    const float* z = deep.samples(D->ch_.z);
    if (!sample_radius.empty() && sample_radius.size() != nsamples)
        return Status::error("deep layers: " + std::to_string(sample_radius.size()) + " blur radii for " +
                             std::to_string(nsamples) + " samples");
    // Depth splits for diffusion: the front surface (cuts at its
    // silhouettes under Auto with radii, each layer's onward and seams).
    const bool by_front = by_front_surface && split.mode != LayerSplit::Mode::ById && nsamples > 0;
    const bool at_silhouettes = by_front && split.mode == LayerSplit::Mode::Auto &&
                                split.blur_cuts != LayerSplit::BlurCuts::Off && sample_radius.size() == nsamples;
    std::unique_ptr<FrontSurface> front;
    if (by_front) {
        front = front_surface(deep, D->ch_, sample_radius, at_silhouettes, exec);
        if (exec.is_cancelled()) return Status::cancelled("deep layers");
    }
    Result<SampleLayers> sl = split.mode == LayerSplit::Mode::ById
                                  ? layers_by_id(deep, z, split.id_channel)
                                  : Result<SampleLayers>(layers_by_depth(std::span<const float>(z, nsamples), split, sample_radius, exec,
                                                                         at_silhouettes ? &front->grid : nullptr));
    if (!sl) return sl.status();
    // A cancelled pass leaves its output unfinished: stop before using it.
    if (exec.is_cancelled()) return Status::cancelled("deep layers");
    D->sl_ = std::move(sl).value();
    if (front) {
        slice_front_surface(*front, deep, D->ch_, D->sl_.layer_of, exec);
        if (exec.is_cancelled()) return Status::cancelled("deep layers");
        D->front_ = std::move(front);
    }
    D->ext_ = layer_extents(deep, z, D->sl_, exec);
    if (exec.is_cancelled()) return Status::cancelled("deep layers");
    if (extend && D->sl_.count >= 2 && !deep.data_window().empty()) {
        if (Status st = check_extend_options(*extend, deep.data_window()); !st) return st;
        D->extend_on_ = true;
        D->extend_ = *extend;
        if (Status st = D->plan(*extend, exec); !st) return st;
        // The reach behind a layer's own surface compares with the depth
        // seen at each pixel: the front surface's (made for it alone when
        // the layers are not sliced by it).
        D->extend_.front_depth = {};
        if (extend->surface_reach_px > extend->extend_px) {
            if (!D->front_) {
                DeepChannels depth_only = D->ch_;  // no positions: only the depth and presence are read
                depth_only.p.reset();
                D->seen_only_ = front_surface(deep, depth_only, {}, false, exec);
                if (exec.is_cancelled()) return Status::cancelled("deep layers");
            }
            D->extend_.front_depth = D->seen()->depth;
            D->extend_.continuity = kContinuity;
        }
    } else if (extend) {
        if (Status st = check_extend_options(*extend, deep.data_window()); !st) return st;
    }
    return D;
}

// Where each pixel is hidden: every layer's own coverage of the pixel (its
// samples composited as make() does), accumulated front to back as
// extend_layers_behind does over the layers' images.
Status DeepLayers::plan(const ExtendOptions& extend, const Exec& exec) {
    const Roi win = deep_.data_window();
    plan_.frame = win;
    if (sl_.count >= int(ExtensionPlan::kNeverHidden))
        return Status::error("layer extension: " + std::to_string(sl_.count) + " layers (at most " +
                             std::to_string(ExtensionPlan::kNeverHidden - 1) + ")");
    for (int l = 0; l < sl_.count; ++l)
        if (!ext_.box[std::size_t(l)].empty()) {
            if (plan_.nearest < 0) plan_.nearest = l;
            plan_.farthest = l;
        }
    parallel_assign(plan_.hidden_from, win.npixels(), ExtensionPlan::kNeverHidden, std::size_t(win.width()), exec);
    const SamplePlanes s(deep_, ch_);
    const float thr = extend.occluder_alpha;
    const bool ok = for_each_sorted_pixel(deep_, s.z, exec, [&](int x, int y, const std::vector<std::size_t>& order) {
        thread_local std::vector<std::pair<int, Over>> acc;
        acc.clear();
        for (std::size_t k : order) {
            const int l = sl_.layer_of[k];
            auto it = std::find_if(acc.begin(), acc.end(), [l](const auto& e) { return e.first == l; });
            if (it == acc.end()) {
                acc.emplace_back(l, Over{});
                it = acc.end() - 1;
            }
            it->second.add(s.r[k], s.g[k], s.b[k], s.alpha(k), s.z[k], nullptr);
        }
        std::sort(acc.begin(), acc.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        float occ = 0.0f;
        std::uint16_t& h = plan_.hidden_from[std::size_t(y - win.y0) * std::size_t(win.width()) + std::size_t(x - win.x0)];
        for (const auto& [l, o] : acc) {
            const float a = float(o.a);
            const bool present = covers(float(o.r), float(o.g), float(o.b), a);
            if (thr > 0.0f) {
                occ = occ + (present ? std::clamp(a, 0.0f, 1.0f) : 0.0f) * (1.0f - occ);
                if (occ >= thr) {
                    h = std::uint16_t(l + 1);
                    break;
                }
            } else if (present) {
                h = std::uint16_t(l + 1);
                break;
            }
        }
    });
    return ok ? Status::ok() : Status::cancelled();
}

Result<const Layer*> DeepLayers::make(int l, Layer& L, const Exec& exec) const {
    if (l < 0 || l >= size()) return Status::error("deep layers: no layer " + std::to_string(l));
    const std::size_t li = std::size_t(l);
    const bool with_positions = ch_.p.has_value();
    L = Layer{};
    const bool empty = ext_.box[li].empty();
    L.depth_near = empty ? std::numeric_limits<double>::quiet_NaN() : ext_.znear[li];
    L.depth_far = empty ? std::numeric_limits<double>::quiet_NaN() : ext_.zfar[li];
    if (split_.mode == LayerSplit::Mode::ById) {
        L.name = sl_.names[li];
        L.slice_near = L.depth_near;
        L.slice_far = L.depth_far;
    } else {
        L.slice_near = sl_.slice_lo[li];
        L.slice_far = sl_.slice_hi[li];
        L.name = empty ? depth_range_name(L.slice_near, L.slice_far) + " (empty)" : depth_range_name(L.depth_near, L.depth_far);
    }
    const Roi own_box = ext_.box[li];
    Roi box = own_box;
    L.onward_marked = front_ != nullptr;
    if (front_ && !empty) mark_onward(l, L, box, exec);
    L.image = layer_image(with_positions, box, deep_.display_window(), deep_.metadata, L.name, deep_.view);
    Image& img = L.image;
    // Which pixels of the box hold samples of the layer (for its seams).
    const FrontSurface* seen = this->seen();
    std::vector<unsigned char> own(seen ? own_box.npixels() : 0, 0);
    const SamplePlanes s(deep_, ch_);
    const float* sp[3] = {with_positions ? deep_.samples((*ch_.p)[0]) : nullptr,
                          with_positions ? deep_.samples((*ch_.p)[1]) : nullptr,
                          with_positions ? deep_.samples((*ch_.p)[2]) : nullptr};
    const bool ok = parallel_for(exec, box.height(), [&](long r0, long r1) {
        std::vector<std::size_t> order;
        for (int y = box.y0 + int(r0); y < box.y0 + int(r1); ++y)
            for (int x = box.x0; x < box.x1; ++x) {
                const std::size_t p = deep_.pixel_index(x, y);
                const std::size_t s0 = deep_.first_sample(p), ns = deep_.sample_count(p);
                // The layer's samples of the pixel: none, one (most pixels of a
                // layer: nothing to sort), or several, composited in depth order.
                int mine = 0;
                std::size_t first = 0;
                for (std::size_t k = s0; k < s0 + ns && mine < 2; ++k)
                    if (sl_.layer_of[k] == l) first = k, ++mine;
                if (mine == 0) {
                    blank_layer_pixel(img, img.offset(x, y));
                    continue;
                }
                if (!own.empty())
                    own[std::size_t(y - own_box.y0) * std::size_t(own_box.width()) + std::size_t(x - own_box.x0)] = 1;
                if (mine == 1) {
                    order.assign(1, first);
                } else {
                    sorted_samples(deep_, s.z, p, order);
                }
                Over o;
                for (std::size_t k : order) {
                    if (sl_.layer_of[k] != l) continue;
                    std::array<double, 3> pv{};
                    if (with_positions) pv = {sp[0][k], sp[1][k], sp[2][k]};
                    o.add(s.r[k], s.g[k], s.b[k], s.alpha(k), s.z[k], with_positions ? &pv : nullptr);
                }
                const std::size_t off = img.offset(x, y);
                store_over(img, off, o, o.mean_z());
                if (with_positions)
                    for (int c = 0; c < 3; ++c) img.plane(5 + c)[off] = o.wsum > 0 ? float(o.psum[std::size_t(c)] / o.wsum) : kNaN;
            }
    });
    if (!ok) return Status::cancelled();
    if (!L.onward.empty()) {
        const FrontSurface& f = *front_;
        const bool p = !f.p[0].empty();
        write_onward(L, deep_.data_window(), f.depth.data(),
                     {p ? f.p[0].data() : nullptr, p ? f.p[1].data() : nullptr, p ? f.p[2].data() : nullptr});
    }
    if (extend_on_)
        if (Status st = extend_layer(L, l, plan_, extend_, exec); !st) return st;
    // Seams, as a plate layer's: the front surface (its owner's depth) in
    // front of an extension pixel (covered, no sample of the layer) is the
    // layer's own.
    if (seen && !empty)
        mark_seams(L, deep_.data_window(), seen->depth.data(), seen->present.data(), kContinuity,
                   [&own, &own_box](std::size_t, int x, int y) {
                       return own_box.contains(x, y) && own[std::size_t(y - own_box.y0) * std::size_t(own_box.width()) +
                                                            std::size_t(x - own_box.x0)];
                   },
                   exec);
    return &L;
}

void DeepLayers::mark_onward(int l, Layer& L, Roi& box, const Exec& exec) const {
    if (!extend_on_ || !(extend_.extend_px > 0.0)) return;
    const Roi win = deep_.data_window();
    const FrontSurface& f = *front_;
    const SurfaceOnwardInput in{win.width(), win.height(), f.depth, f.present, f.slice, f.fg_slice, {}, kContinuity};
    const Roi& own = ext_.box[std::size_t(l)];
    const Roi own_rel{own.x0 - win.x0, own.y0 - win.y0, own.x1 - win.x0, own.y1 - win.y0};
    SurfaceOnward onward = surface_onward(in, l, own_rel, int(std::ceil(extend_.extend_px)), exec);
    const Roi& b = onward.box;
    if (b.empty()) return;
    L.onward_box = Roi{b.x0 + win.x0, b.y0 + win.y0, b.x1 + win.x0, b.y1 + win.y0};
    L.onward = std::move(onward.mask);  // the same box, in absolute coordinates
    box = unite(box, L.onward_box);
}

}  // namespace

Result<std::unique_ptr<LayerSource>> deep_layer_source(const DeepImage& deep, const LayerSplit& split,
                                                       std::span<const float> sample_radius,
                                                       const ExtendOptions* extend, const Exec& exec,
                                                       bool by_front_surface) {
    auto d = DeepLayers::create(deep, split, sample_radius, extend, exec, by_front_surface);
    if (!d) return d.status();
    return std::unique_ptr<LayerSource>(std::move(d).value());
}

Result<std::vector<Layer>> layers_from_deep(const DeepImage& deep, const LayerSplit& split,
                                            std::span<const float> sample_radius, const Exec& exec,
                                            bool by_front_surface) {
    auto d = DeepLayers::create(deep, split, sample_radius, nullptr, exec, by_front_surface);
    if (!d) return d.status();
    return make_all(**d, exec);
}

Result<Image> flatten_deep(const DeepImage& deep, const Exec& exec) {
    auto chr = deep_channels(deep);
    if (!chr) return chr.status();
    const DeepChannels ch = *chr;
    if (Status st = validate_samples(deep, ch, exec); !st) return st;
    const Roi win = deep.data_window();
    Image out = Image::with_channels({"R", "G", "B", "A", "Z"}, win);
    out.set_display_window(deep.display_window());
    out.metadata = deep.metadata;
    out.name = deep.name;
    out.view = deep.view;
    std::fill_n(out.plane(4), out.npixels(), kNaN);
    const SamplePlanes s(deep, ch);
    const bool ok = for_each_sorted_pixel(deep, s.z, exec, [&](int x, int y, const std::vector<std::size_t>& order) {
        Over o;
        for (std::size_t k : order) o.add(s.r[k], s.g[k], s.b[k], s.alpha(k), s.z[k], nullptr);
        store_over(out, out.offset(x, y), o, o.first_z);
    });
    if (!ok) return Status::cancelled("flatten");
    return out;
}

}  // namespace gdof
