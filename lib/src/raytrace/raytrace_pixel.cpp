// What the renderer writes per pixel: the flat beauty + AOVs averaged over
// the aperture samples, or the samples grouped into deep surfaces.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "raytrace/raytrace_internal.h"

namespace gdof {

namespace {

struct AovName {
    const char* name;
    RenderAov flag;
};
constexpr AovName kAovNames[] = {{"albedo", RenderAov::Albedo},
                                 {"Z", RenderAov::Depth},
                                 {"P", RenderAov::Position},
                                 {"N", RenderAov::Normal},
                                 {"id", RenderAov::Id}};

}  // namespace

Result<RenderAov> parse_render_aovs(const std::string& list) {
    if (list == "all") return RenderAov::All;
    if (list == "none") return RenderAov::None;
    RenderAov aovs = RenderAov::None;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        bool known = false;
        for (const AovName& a : kAovNames)
            if (item == a.name) aovs |= a.flag, known = true;
        if (!known)
            return Status::error("unknown AOV '" + item + "' (expected a comma-separated list of albedo, Z, P, N, id; or all, none)");
    }
    if (list.empty() || list.back() == ',') return Status::error("empty AOV name in '" + list + "'");
    return aovs;
}

std::string format_render_aovs(RenderAov aovs) {
    std::string s;
    for (const AovName& a : kAovNames)
        if (has(aovs, a.flag)) s += (s.empty() ? "" : ",") + std::string(a.name);
    return s.empty() ? "none" : s;
}

namespace rt {

FlatLayout FlatLayout::make(RenderAov aovs, std::vector<ChannelSpec>& specs) {
    FlatLayout l;
    specs.clear();
    for (const char* n : {"R", "G", "B", "A"}) specs.push_back({n, PixelType::Float});
    auto group = [&](RenderAov flag, int& first, std::initializer_list<const char*> names) {
        if (!has(aovs, flag)) return;
        first = int(specs.size());
        for (const char* n : names) specs.push_back({n, PixelType::Float});
    };
    group(RenderAov::Albedo, l.albedo, {"albedo.R", "albedo.G", "albedo.B"});
    group(RenderAov::Depth, l.z, {"Z"});
    group(RenderAov::Position, l.p, {"P.x", "P.y", "P.z"});
    group(RenderAov::Normal, l.n, {"N.x", "N.y", "N.z"});
    if (has(aovs, RenderAov::Id)) {
        l.id = int(specs.size());
        specs.push_back({"id", PixelType::UInt});
    }
    return l;
}

void write_flat_pixel(Image& img, const FlatLayout& l, std::size_t off, const std::vector<Sample>& samples,
                      std::uint32_t central_id, bool env_opaque) {
    Vec3 rgb{0, 0, 0}, albedo{0, 0, 0}, p{0, 0, 0}, n{0, 0, 0};
    double z = 0;
    int hits = 0;
    for (const Sample& s : samples) {
        rgb = rgb + s.radiance;
        if (!s.hit) continue;
        ++hits;
        albedo = albedo + s.albedo, p = p + s.p, n = n + s.n, z += s.z;
    }
    auto put = [&](int c, double v) { img.plane(c)[off] = float(v); };
    auto put3 = [&](int c, const Vec3& v) { put(c, v.x), put(c + 1, v.y), put(c + 2, v.z); };
    const double inv = 1.0 / double(samples.size());
    put3(l.r, rgb * inv);
    put(l.a, env_opaque ? 1.0 : hits * inv);
    const double kNaN = std::numeric_limits<double>::quiet_NaN();
    const double ih = hits ? 1.0 / hits : kNaN;
    if (l.albedo >= 0) put3(l.albedo, hits ? albedo * ih : Vec3{0, 0, 0});
    if (l.z >= 0) put(l.z, hits ? z * ih : std::numeric_limits<double>::infinity());
    if (l.p >= 0) put3(l.p, p * ih);
    if (l.n >= 0) {
        Vec3 nn = n * ih;
        if (hits && length(nn) > 0) nn = normalize(nn);
        put3(l.n, nn);
    }
    if (l.id >= 0) img.uplane(l.id)[off] = central_id;
}

void deep_pixel(std::vector<Sample>& samples, const Vec3& environment, bool env_opaque,
                std::vector<DeepSurface>& out) {
    out.clear();
    const double n_total = double(samples.size());
    // Hits first, by object then depth; a new surface where the object
    // changes or the depth jumps by more than 5% (an object in front of
    // itself, e.g. an ear over the body).
    auto hits_end = std::partition(samples.begin(), samples.end(), [](const Sample& s) { return s.hit; });
    std::sort(samples.begin(), hits_end, [](const Sample& a, const Sample& b) {
        return a.id != b.id ? a.id < b.id : a.z < b.z;
    });
    struct Group {
        std::size_t begin, end;
        double zmean;
    };
    std::vector<Group> groups;
    for (auto it = samples.begin(); it != hits_end; ++it) {
        const std::size_t i = std::size_t(it - samples.begin());
        if (groups.empty() || it->id != (it - 1)->id || it->z > (it - 1)->z * 1.05) groups.push_back({i, i, 0});
        groups.back().end = i + 1;
        groups.back().zmean += it->z;
    }
    for (Group& g : groups) g.zmean /= double(g.end - g.begin);
    std::sort(groups.begin(), groups.end(), [&](const Group& a, const Group& b) {
        return a.zmean != b.zmean ? a.zmean < b.zmean : samples[a.begin].id < samples[b.begin].id;
    });
    // Front to back: a surface takes its hits out of the samples still open,
    // so alpha = hits / open and the premultiplied colour = radiance sum / open.
    double open = n_total;
    for (const Group& g : groups) {
        DeepSurface d;
        const double cnt = double(g.end - g.begin);
        Vec3 rad{0, 0, 0};
        for (std::size_t i = g.begin; i < g.end; ++i) {
            const Sample& s = samples[i];
            rad = rad + s.radiance, d.albedo = d.albedo + s.albedo, d.p = d.p + s.p, d.n = d.n + s.n;
        }
        d.rgb = rad * (1.0 / open);
        d.alpha = cnt / open;
        d.z = g.zmean;
        d.albedo = d.albedo * (1.0 / cnt), d.p = d.p * (1.0 / cnt);
        d.n = length(d.n) > 0 ? normalize(d.n) : d.n;
        d.id = samples[g.begin].id;
        open -= cnt;
        out.push_back(d);
    }
    if (env_opaque && open > 0) {  // what the misses saw, behind everything
        DeepSurface d;
        d.rgb = environment;
        d.alpha = 1.0;
        d.z = std::numeric_limits<double>::infinity();
        const double kNaN = std::numeric_limits<double>::quiet_NaN();
        d.p = d.n = Vec3{kNaN, kNaN, kNaN};
        out.push_back(d);
    }
}

Result<DeepImage> make_deep_image(const Roi& window, RenderAov aovs, std::vector<std::vector<DeepSurface>>& pixels) {
    std::vector<ChannelSpec> specs;
    FlatLayout l = FlatLayout::make(aovs & ~RenderAov::Depth, specs);
    // Z and ZBack right after A (Z is always written in deep output).
    specs.insert(specs.begin() + 4, {{"Z", PixelType::Float}, {"ZBack", PixelType::Float}});
    for (int* c : {&l.albedo, &l.p, &l.n, &l.id})
        if (*c >= 0) *c += 2;
    DeepImage deep(specs, window, window);
    std::vector<std::uint32_t> counts(pixels.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) counts[i] = std::uint32_t(pixels[i].size());
    if (Status st = deep.set_sample_counts(counts); !st) return st;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::size_t k = deep.first_sample(i);
        for (const DeepSurface& d : pixels[i]) {
            auto put = [&](int c, double v) { deep.samples(c)[k] = float(v); };
            auto put3 = [&](int c, const Vec3& v) { put(c, v.x), put(c + 1, v.y), put(c + 2, v.z); };
            put3(l.r, d.rgb);
            put(l.a, d.alpha);
            put(4, d.z), put(5, d.z);
            if (l.albedo >= 0) put3(l.albedo, d.albedo);
            if (l.p >= 0) put3(l.p, d.p);
            if (l.n >= 0) put3(l.n, d.n);
            if (l.id >= 0) deep.usamples(l.id)[k] = d.id;
            ++k;
        }
        std::vector<DeepSurface>().swap(pixels[i]);  // free as we go
    }
    return deep;
}

}  // namespace rt

}  // namespace gdof
