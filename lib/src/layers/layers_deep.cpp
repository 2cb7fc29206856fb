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
Status validate_samples(const DeepImage& deep, const DeepChannels& ch) {
    const Roi win = deep.data_window();
    const float* z = deep.samples(ch.z);
    const float* a = ch.a >= 0 ? deep.samples(ch.a) : nullptr;
    for (int y = win.y0; y < win.y1; ++y)
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
SampleLayers layers_by_depth(std::span<const float> z, const LayerSplit& split, std::span<const float> sample_radius) {
    const DepthSlices slices = choose_slices(z, split, sample_radius);
    SampleLayers sl;
    sl.count = slices.count();
    sl.slice_lo = slices.lo;
    sl.slice_hi = slices.hi;
    sl.layer_of.resize(z.size());
    for (std::size_t k = 0; k < z.size(); ++k) sl.layer_of[k] = slices.slice_of(z[k]);
    return sl;
}

// Bounding box and depth range of every layer's samples.
struct LayerExtents {
    std::vector<Roi> box;
    std::vector<double> znear, zfar;
};

LayerExtents layer_extents(const DeepImage& deep, const float* z, const SampleLayers& sl) {
    const Roi win = deep.data_window();
    LayerExtents e;
    e.box.resize(std::size_t(sl.count));
    e.znear.assign(std::size_t(sl.count), kInf);
    e.zfar.assign(std::size_t(sl.count), -kInf);
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            const std::size_t p = deep.pixel_index(x, y);
            const std::size_t s0 = deep.first_sample(p), n = deep.sample_count(p);
            for (std::size_t k = s0; k < s0 + n; ++k) {
                const std::size_t l = std::size_t(sl.layer_of[k]);
                e.box[l] = unite(e.box[l], Roi{x, y, x + 1, y + 1});
                e.znear[l] = std::min(e.znear[l], double(z[k]));
                e.zfar[l] = std::max(e.zfar[l], double(z[k]));
            }
        }
    return e;
}

// The layers before any sample is composited into them: named, over their
// boxes, with the deep image's display window and metadata, zero colour and
// NaN depth (and positions).
std::vector<Layer> blank_layers(const DeepImage& deep, const LayerSplit& split, const SampleLayers& sl,
                                const LayerExtents& ext, bool with_positions) {
    std::vector<Layer> layers(static_cast<std::size_t>(sl.count));
    std::vector<std::string> chan_names = {"R", "G", "B", "A", "Z"};
    if (with_positions) chan_names.insert(chan_names.end(), {"P.x", "P.y", "P.z"});
    for (int l = 0; l < sl.count; ++l) {
        const std::size_t li = std::size_t(l);
        Layer& L = layers[li];
        const bool empty = ext.box[li].empty();
        L.depth_near = empty ? std::numeric_limits<double>::quiet_NaN() : ext.znear[li];
        L.depth_far = empty ? std::numeric_limits<double>::quiet_NaN() : ext.zfar[li];
        if (split.mode == LayerSplit::Mode::ById) {
            L.name = sl.names[li];
            L.slice_near = L.depth_near;
            L.slice_far = L.depth_far;
        } else {
            L.slice_near = sl.slice_lo[li];
            L.slice_far = sl.slice_hi[li];
            L.name = empty ? depth_range_name(L.slice_near, L.slice_far) + " (empty)"
                           : depth_range_name(L.depth_near, L.depth_far);
        }
        L.image = Image::with_channels(chan_names, ext.box[li]);
        L.image.set_display_window(deep.display_window());
        L.image.metadata = deep.metadata;
        L.image.name = L.name;
        L.image.view = deep.view;
        std::fill_n(L.image.plane(4), L.image.npixels(), kNaN);
        if (with_positions)
            for (int c = 5; c < 8; ++c) std::fill_n(L.image.plane(c), L.image.npixels(), kNaN);
    }
    return layers;
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

// R, G, B, A of a composited pixel, and `z` as its depth, at img's offset `off`.
void store_over(Image& img, std::size_t off, const Over& o, double z) {
    img.plane(0)[off] = float(o.r);
    img.plane(1)[off] = float(o.g);
    img.plane(2)[off] = float(o.b);
    img.plane(3)[off] = float(o.a);
    img.plane(4)[off] = float(z);
}

// Composites every pixel's samples, front to back, into the layers they
// belong to. Parallel over rows; false if cancelled.
bool composite_samples(const DeepImage& deep, const DeepChannels& ch, const SampleLayers& sl, std::vector<Layer>& layers,
                       const Exec& exec) {
    const SamplePlanes s(deep, ch);
    const float* sp[3] = {ch.p ? deep.samples((*ch.p)[0]) : nullptr, ch.p ? deep.samples((*ch.p)[1]) : nullptr,
                          ch.p ? deep.samples((*ch.p)[2]) : nullptr};
    return for_each_sorted_pixel(deep, s.z, exec, [&](int x, int y, const std::vector<std::size_t>& order) {
        thread_local std::vector<std::pair<int, Over>> acc;  // touched layers of the pixel
        acc.clear();
        for (std::size_t k : order) {
            const int l = sl.layer_of[k];
            auto it = std::find_if(acc.begin(), acc.end(), [l](const auto& e) { return e.first == l; });
            if (it == acc.end()) {
                acc.emplace_back(l, Over{});
                it = acc.end() - 1;
            }
            std::array<double, 3> pv{};
            if (ch.p) pv = {sp[0][k], sp[1][k], sp[2][k]};
            it->second.add(s.r[k], s.g[k], s.b[k], s.alpha(k), s.z[k], ch.p ? &pv : nullptr);
        }
        for (const auto& [l, o] : acc) {
            Image& img = layers[std::size_t(l)].image;
            const std::size_t off = img.offset(x, y);
            store_over(img, off, o, o.mean_z());
            if (ch.p && o.wsum > 0)
                for (int c = 0; c < 3; ++c) img.plane(5 + c)[off] = float(o.psum[std::size_t(c)] / o.wsum);
        }
    });
}

}  // namespace

Result<std::vector<Layer>> layers_from_deep(const DeepImage& deep, const LayerSplit& split,
                                            std::span<const float> sample_radius, const Exec& exec) {
    auto chr = deep_channels(deep);
    if (!chr) return chr.status();
    const DeepChannels ch = *chr;
    if (Status st = validate_samples(deep, ch); !st) return st;
    const std::size_t nsamples = deep.total_samples();
    const float* z = deep.samples(ch.z);
    if (!sample_radius.empty() && sample_radius.size() != nsamples)
        return Status::error("deep layers: " + std::to_string(sample_radius.size()) + " blur radii for " +
                             std::to_string(nsamples) + " samples");

    Result<SampleLayers> sl = split.mode == LayerSplit::Mode::ById
                                  ? layers_by_id(deep, z, split.id_channel)
                                  : Result<SampleLayers>(layers_by_depth(std::span<const float>(z, nsamples), split, sample_radius));
    if (!sl) return sl.status();
    std::vector<Layer> layers = blank_layers(deep, split, *sl, layer_extents(deep, z, *sl), ch.p.has_value());
    if (!composite_samples(deep, ch, *sl, layers, exec)) return Status::cancelled();
    return layers;
}

Result<Image> flatten_deep(const DeepImage& deep, const Exec& exec) {
    auto chr = deep_channels(deep);
    if (!chr) return chr.status();
    const DeepChannels ch = *chr;
    if (Status st = validate_samples(deep, ch); !st) return st;
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
