// defocus(): a file's contents -> layers -> defocus_layers -> one flat part
// with the input's display window, metadata and colour channel types, and
// the other channels of a flat input carried over unchanged.
//
//   a deep part                         -> layers_from_deep (the first deep part),
//                                          each layer extended behind the nearer
//                                          layers that fully hide it
//   several flat parts, or one part with
//   layer groups ("fg.R/G/B/A" ...)     -> layers_from_parts
//   one flat part with R, G, B(, A) and
//   a depth channel                     -> layers_from_depth_map, extended by
//                                          the largest blur radius of the image
#include <chrono>
#include <cmath>
#include <set>

#include "diffusion/defocus_internal.h"

namespace gdof {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Prefixes p with p.R, p.G, p.B and p.A all present ("" not included).
std::set<std::string> rgba_groups(const Image& img) {
    std::set<std::string> groups;
    for (const ChannelSpec& c : img.channels()) {
        const std::string& n = c.name;
        if (n.size() < 3 || n.compare(n.size() - 2, 2, ".R") != 0) continue;
        const std::string p = n.substr(0, n.size() - 2);
        if (img.channel_index(p + ".G") >= 0 && img.channel_index(p + ".B") >= 0 && img.channel_index(p + ".A") >= 0)
            groups.insert(p);
    }
    return groups;
}

bool is_group_colour(const std::string& name, const std::set<std::string>& groups) {
    for (const std::string& g : groups)
        for (const char* c : {".R", ".G", ".B", ".A"})
            if (name == g + c) return true;
    return false;
}

std::string channel_list(const Image& img) {
    std::string s;
    for (int c = 0; c < img.nchannels() && c < 12; ++c) s += (c ? "," : "") + img.channel(c).name;
    if (img.nchannels() > 12) s += ",...";
    return s.empty() ? std::string("none") : s;
}

// Largest finite blur radius of a flat image (P, or depth + camera per `source`).
// The largest finite value (0 if none).
double largest_finite(const std::vector<float>& r) {
    double m = 0.0;
    for (float v : r)
        if (std::isfinite(v)) m = std::max(m, double(v));
    return m;
}

// Copies channel `c` of src onto dst (same channel spec added), over the
// overlap of the windows; zero elsewhere.
void carry_channel(const Image& src, int c, Image& dst) {
    const int dc = dst.add_channel(src.channel(c));
    const Roi ov = intersect(src.data_window(), dst.data_window());
    for (int y = ov.y0; y < ov.y1; ++y) {
        if (src.channel(c).type == PixelType::UInt) {
            const std::uint32_t* s = src.uplane(c) + src.offset(ov.x0, y);
            std::copy(s, s + ov.width(), dst.uplane(dc) + dst.offset(ov.x0, y));
        } else {
            const float* s = src.plane(c) + src.offset(ov.x0, y);
            std::copy(s, s + ov.width(), dst.plane(dc) + dst.offset(ov.x0, y));
        }
    }
}

}  // namespace

Result<ImageSet> defocus(const ImageSet& input, const BlurField& field, const Camera& camera,
                         const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    if (input.empty()) return Status::error("defocus: the input has no image parts");

    // Which kind of input.
    int deep_part = -1;
    for (std::size_t i = 0; i < input.size(); ++i)
        if (input.is_deep(i)) {
            deep_part = int(i);
            break;
        }
    const Image* flat = (deep_part < 0) ? &input.flat(0) : nullptr;
    const bool from_parts = deep_part < 0 && (input.size() > 1 || !rgba_groups(*flat).empty());

    // The reference for the output: display window, metadata, colour types.
    Roi display;
    const Metadata* md = nullptr;
    PixelType types[4] = {PixelType::Float, PixelType::Float, PixelType::Float, PixelType::Float};
    std::string name, view;
    StorageHints storage;
    auto colour_types = [&](auto&& type_of) {
        const char* names[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c) {
            PixelType t = PixelType::Float;
            if (!type_of(names[c], t) && c == 3) type_of("R", t);  // no alpha: as R
            types[c] = t == PixelType::UInt ? PixelType::Float : t;
        }
    };
    if (deep_part >= 0) {
        const DeepImage& d = input.deep(std::size_t(deep_part));
        display = d.display_window();
        md = &d.metadata;
        name = d.name, view = d.view, storage = d.storage;
        colour_types([&](const char* n, PixelType& t) {
            const int c = d.channel_index(n);
            if (c >= 0) t = d.channel(c).type;
            return c >= 0;
        });
    } else {
        display = flat->display_window();
        md = &flat->metadata;
        name = flat->name, view = flat->view, storage = flat->storage;
        const RgbaIndices fi = find_rgba(*flat);
        colour_types([&](const char* n, PixelType& t) {
            const int c = n[0] == 'R' ? fi.r : n[0] == 'G' ? fi.g : n[0] == 'B' ? fi.b : fi.a;
            if (c >= 0) t = flat->channel(c).type;
            return c >= 0;
        });
    }

    // Layers.
    const auto t0 = std::chrono::steady_clock::now();
    Result<std::vector<Layer>> layers = std::vector<Layer>{};
    if (deep_part >= 0) {
        const DeepImage& d = input.deep(std::size_t(deep_part));
        if (d.channel_index("A") < 0 || d.channel_index("R") < 0)
            return Status::error("defocus: the deep part has no R, G, B, A channels (it has " +
                                 std::to_string(d.nchannels()) + " channels)");
        if (d.z_channel() < 0) return Status::error("defocus: the deep part has no depth channel 'Z'");
        // Every sample's blur: it places Auto's blur cuts and bounds the extension.
        std::vector<float> r(d.total_samples());
        if (Status st = evaluate_blur_deep(field, camera, d, -1, r, exec); !st)
            return st.prefix("defocus: blur field");
        layers = layers_from_deep(d, settings.split, r, exec);  // blur_cuts Off ignores the radii
        if (layers) {
            // Deep renders keep only visible samples: extend each layer behind
            // the nearer layers that fully hide it, as far as the largest blur
            // can reveal (not into genuinely empty, transparent areas).
            ExtendOptions ext;
            ext.extend_px = std::min(largest_finite(r), settings.diffusion.max_radius);
            ext.occluder_alpha = 0.999f;
            if (Status st = extend_layers_behind(*layers, d.data_window(), ext, exec); !st) return st.prefix("defocus");
        }
    } else if (from_parts) {
        layers = layers_from_parts(input, settings.source, exec);
    } else {
        const RgbaIndices rgba = find_rgba(*flat);
        if (rgba.r < 0 || rgba.g < 0 || rgba.b < 0)
            return Status::error("defocus: the input has no R, G, B channels (channels: " + channel_list(*flat) + ")");
        auto pos = find_position_channels(*flat, settings.source.position_channels);
        if (!pos) return pos.status().prefix("defocus");
        auto z = find_depth_channel(*flat, settings.source.depth_channel);
        if (!z) return z.status().prefix("defocus");
        if (*z < 0)
            return Status::error("defocus: the input has no depth channel '" +
                                 (settings.source.depth_channel.empty() ? std::string("Z") : settings.source.depth_channel) +
                                 "' (channels: " + channel_list(*flat) + ")",
                                 StatusCode::NotFound, "depth_channel");
        SliceOptions so;
        so.split = settings.split;
        so.source = settings.source;
        std::vector<float> r(flat->npixels());
        if (Status st = evaluate_blur_map(field, camera, *flat, settings.source,
                                          ImageView::planar(r.data(), 1, flat->data_window()), exec);
            !st)
            return st.prefix("defocus: blur field");
        so.extend_px = std::min(largest_finite(r), settings.diffusion.max_radius);
        if (settings.split.blur_cuts == LayerSplit::BlurCuts::On) so.radius = r;
        layers = layers_from_depth_map(*flat, so, exec);
    }
    const double t_layers = seconds_since(t0);
    if (!layers) return layers.status().prefix("defocus");
    if (layers->empty()) return Status::error("defocus: the input gave no layers");

    DefocusStats local;
    DefocusStats& S = stats ? *stats : local;
    auto out = defocus_layers(*layers, field, camera, settings, &S, exec);
    S.t_layers = t_layers;
    if (!out) return out.status();

    // One flat part: R, G, B, A with the input's types, then the carried channels.
    Image res = std::move(out).value();
    for (int c = 0; c < 4; ++c)
        if (Status st = res.set_channel_type(c, types[c]); !st) return st.prefix("defocus");
    res.set_display_window(display);
    res.metadata = *md;
    res.name = name;
    res.view = view;
    res.storage = storage;
    if (flat && input.size() == 1) {
        const RgbaIndices rgba = find_rgba(*flat);
        const std::set<std::string> groups = rgba_groups(*flat);
        for (int c = 0; c < flat->nchannels(); ++c) {
            if (c == rgba.r || c == rgba.g || c == rgba.b || c == rgba.a) continue;
            if (is_group_colour(flat->channel(c).name, groups)) continue;
            if (res.channel_index(flat->channel(c).name) >= 0) continue;
            carry_channel(*flat, c, res);
        }
    }
    ImageSet set;
    set.parts.emplace_back(std::move(res));
    return set;
}

}  // namespace gdof
