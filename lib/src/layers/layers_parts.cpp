// Multipart / multilayer EXR -> layers.
//
// Candidates: every flat part's unprefixed layer ("R", "G", "B", optional
// "A": opaque without it) and every prefixed layer ("fg.R", "fg.G", "fg.B"
// and "fg.A" required) of a part. A candidate becomes a layer when it has a
// position pass or a depth channel under the same prefix:
//   positions: blur_map.h's find_position_channels with the prefix
//     ("fg.P.x" ..., or PositionSource::position_channels under the prefix);
//   depth: "fg.Z", "fg.depth.Z", "fg.Depth.Z", "fg.depth", "fg.Depth" (or
//     PositionSource::depth_channel under the prefix), decoded with
//     PositionSource::depth_decode to metric depth.
// Layer Z is the decoded depth; with positions only, the depth along the view
// axis of the part's camera (worldToCamera / worldToNDC attributes), or, with
// no camera attributes, P.z (a camera at the origin looking down +z, as
// resolve_camera assumes). Covered pixels: A > 0 or any colour != 0; their
// invalid depths become +inf (far away). Deep parts go through
// layers_from_deep (Auto split). Order: front to back by median depth of the
// covered pixels (stable; layers without finite depth last).
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "layers/layers_internal.h"

namespace gdof {

using namespace layers_detail;

namespace {

struct Candidate {
    std::string prefix;
    RgbaIndices rgba;
    std::optional<std::array<int, 3>> pos;
    int depth = -1;
};

std::string with_prefix(const std::string& prefix, const std::string& name) {
    return prefix.empty() ? name : prefix + "." + name;
}

std::optional<std::array<int, 3>> find_positions(const Image& img, const std::string& prefix, const PositionSource& src) {
    if (src.position_channels.empty()) {
        if (prefix.empty()) {
            auto r = find_position_channels(img, "");
            return r ? *r : std::nullopt;
        }
        for (const char* layer : {"P", "Pworld", "p", "position", "Position"}) {
            auto r = find_position_channels(img, prefix + "." + layer);
            if (r && *r) return *r;
        }
        return std::nullopt;
    }
    std::string spec;
    if (src.position_channels.find(',') != std::string::npos) {
        std::size_t start = 0;
        while (start <= src.position_channels.size()) {
            std::size_t comma = src.position_channels.find(',', start);
            if (comma == std::string::npos) comma = src.position_channels.size();
            if (!spec.empty()) spec += ",";
            spec += with_prefix(prefix, src.position_channels.substr(start, comma - start));
            start = comma + 1;
        }
    } else {
        spec = with_prefix(prefix, src.position_channels);
    }
    auto r = find_position_channels(img, spec);
    return r ? *r : std::nullopt;
}

int find_depth(const Image& img, const std::string& prefix, const PositionSource& src) {
    if (!src.depth_channel.empty()) {
        auto r = find_depth_channel(img, with_prefix(prefix, src.depth_channel));
        return r ? *r : -1;
    }
    if (prefix.empty()) {
        auto r = find_depth_channel(img, "");
        return r ? *r : -1;
    }
    for (const char* n : {"Z", "depth.Z", "Depth.Z", "depth", "Depth"}) {
        int c = img.channel_index(prefix + "." + n);
        if (c >= 0 && img.channel(c).type != PixelType::UInt) return c;
    }
    return -1;
}

std::vector<Candidate> candidates(const Image& img, const PositionSource& src) {
    std::vector<std::string> prefixes;
    std::set<std::string> seen;
    {
        const RgbaIndices ix = find_rgba(img, "");
        if (ix.r >= 0 && ix.g >= 0 && ix.b >= 0) {
            prefixes.push_back("");
            seen.insert("");
        }
    }
    for (const auto& ch : img.channels()) {
        const std::size_t dot = ch.name.rfind('.');
        if (dot == std::string::npos || dot == 0) continue;
        const std::string base = ch.name.substr(dot + 1);
        if (base != "R" && base != "r" && base != "red") continue;
        const std::string prefix = ch.name.substr(0, dot);
        if (seen.insert(prefix).second) prefixes.push_back(prefix);
    }
    std::vector<Candidate> out;
    for (const std::string& p : prefixes) {
        Candidate c;
        c.prefix = p;
        c.rgba = find_rgba(img, p);
        if (c.rgba.r < 0 || c.rgba.g < 0 || c.rgba.b < 0) continue;
        if (!p.empty() && c.rgba.a < 0) continue;
        bool uint_colour = false;
        for (int i : {c.rgba.r, c.rgba.g, c.rgba.b, c.rgba.a})
            if (i >= 0 && img.channel(i).type == PixelType::UInt) uint_colour = true;
        if (uint_colour) continue;
        c.pos = find_positions(img, p, src);
        c.depth = find_depth(img, p, src);
        if (!c.pos && c.depth < 0) continue;
        out.push_back(c);
    }
    return out;
}

Layer make_layer(const Image& img, const Candidate& c, const PositionSource& src, const std::string& name) {
    const Roi win = img.data_window();
    const std::size_t n = img.npixels();
    const float* r = img.plane(c.rgba.r);
    const float* g = img.plane(c.rgba.g);
    const float* b = img.plane(c.rgba.b);
    const float* a = c.rgba.a >= 0 ? img.plane(c.rgba.a) : nullptr;
    std::vector<unsigned char> covered(n, 0);
    Roi box;
    for (int y = win.y0; y < win.y1; ++y)
        for (int x = win.x0; x < win.x1; ++x) {
            const std::size_t i = img.offset(x, y);
            if (!a || a[i] > 0.0f || r[i] != 0.0f || g[i] != 0.0f || b[i] != 0.0f) {
                covered[i] = 1;
                box = unite(box, Roi{x, y, x + 1, y + 1});
            }
        }
    std::vector<std::string> names = {"R", "G", "B", "A", "Z"};
    if (c.pos) names.insert(names.end(), {"P.x", "P.y", "P.z"});
    Layer L;
    L.name = name;
    L.image = Image::with_channels(names, box);
    L.image.set_display_window(img.display_window());
    L.image.metadata = img.metadata;
    L.image.name = name;
    L.image.view = img.view;
    std::optional<Camera> cam;
    if (c.depth < 0) {
        auto cr = Camera::from_metadata(img.metadata, img.display_window());
        if (cr) cam = *cr;
    }
    const float* zp = c.depth >= 0 ? img.plane(c.depth) : nullptr;
    const float* pp[3] = {c.pos ? img.plane((*c.pos)[0]) : nullptr, c.pos ? img.plane((*c.pos)[1]) : nullptr,
                          c.pos ? img.plane((*c.pos)[2]) : nullptr};
    std::vector<float> depths;
    double znear = kInf, zfar = -kInf;
    for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x) {
            const std::size_t i = img.offset(x, y);
            const std::size_t o = L.image.offset(x, y);
            if (!covered[i]) {
                L.image.plane(4)[o] = kNaN;
                if (c.pos)
                    for (int k = 0; k < 3; ++k) L.image.plane(5 + k)[o] = kNaN;
                continue;
            }
            L.image.plane(0)[o] = r[i];
            L.image.plane(1)[o] = g[i];
            L.image.plane(2)[o] = b[i];
            L.image.plane(3)[o] = a ? a[i] : 1.0f;
            double depth;
            if (zp) {
                depth = decode_depth(zp[i], src.depth_decode);
            } else {
                const Vec3 p(pp[0][i], pp[1][i], pp[2][i]);
                depth = cam ? cam->project(p).depth : p.z;
            }
            if (!std::isfinite(depth)) depth = kInf;
            L.image.plane(4)[o] = float(depth);
            if (c.pos)
                for (int k = 0; k < 3; ++k) L.image.plane(5 + k)[o] = pp[k][i];
            depths.push_back(float(depth));
            znear = std::min(znear, depth);
            zfar = std::max(zfar, depth);
        }
    L.depth_near = box.empty() ? std::numeric_limits<double>::quiet_NaN() : znear;
    L.depth_far = box.empty() ? std::numeric_limits<double>::quiet_NaN() : zfar;
    L.slice_near = L.depth_near;
    L.slice_far = L.depth_far;
    return L;
}

}  // namespace

Result<std::vector<Layer>> layers_from_parts(const ImageSet& set, const PositionSource& source, const Exec& exec) {
    if (Status st = source.depth_decode.validate(); !st) return st.prefix("depth decoding");
    struct Entry {
        Layer layer;
        double median;
    };
    std::vector<Entry> entries;
    for (std::size_t i = 0; i < set.size(); ++i) {
        if (exec.is_cancelled()) return Status::cancelled();
        const std::string part = set.part_name(i).empty() ? "part " + std::to_string(i) : set.part_name(i);
        if (set.is_deep(i)) {
            auto dl = layers_from_deep(set.deep(i), LayerSplit{}, {}, exec);
            if (!dl) return dl.status().prefix("part " + std::to_string(i) + " '" + part + "'");
            for (Layer& l : *dl) {
                l.name = part + " " + l.name;
                l.image.name = l.name;
                const std::size_t np = l.image.npixels();
                std::vector<float> zs(l.image.plane(4), l.image.plane(4) + np);
                double m = median_finite(zs);
                entries.push_back({std::move(l), m});
            }
            continue;
        }
        const Image& img = set.flat(i);
        for (const Candidate& c : candidates(img, source)) {
            std::string name = set.part_name(i).empty() ? (c.prefix.empty() ? part : c.prefix)
                                                        : (c.prefix.empty() ? part : part + "." + c.prefix);
            Layer l = make_layer(img, c, source, name);
            const std::size_t np = l.image.npixels();
            std::vector<float> zs(l.image.plane(4), l.image.plane(4) + np);
            double m = median_finite(zs);
            entries.push_back({std::move(l), m});
        }
    }
    if (entries.empty()) {
        const std::string pos = source.position_channels.empty() ? "P.x/P.y/P.z (or Pworld, .X/.Y/.Z, .R/.G/.B)"
                                                                 : "'" + source.position_channels + "'";
        const std::string depth = source.depth_channel.empty() ? "Z (or depth.Z, Depth.Z, depth, Depth)"
                                                               : "'" + source.depth_channel + "'";
        return Status::error("no layers found in " + std::to_string(set.size()) +
                             " part(s): looked for R, G, B, A with positions " + pos + " or depth " + depth +
                             ", in each part and under each layer prefix ('fg.R', 'fg.A', 'fg.Z' ...)");
    }
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        const bool fa = std::isfinite(a.median), fb = std::isfinite(b.median);
        if (fa != fb) return fa;
        return fa && a.median < b.median;
    });
    std::vector<Layer> out;
    out.reserve(entries.size());
    for (Entry& e : entries) out.push_back(std::move(e.layer));
    return out;
}

}  // namespace gdof
