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
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <cmath>
#include <span>
#include <optional>
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

// The largest finite value (0 if none).
double largest_finite(std::span<const float> r) {
    double m = 0.0;
    for (float v : r)
        if (std::isfinite(v)) m = std::max(m, double(v));
    return m;
}

// The largest finite radius among the present pixels or samples (A > 0 or
// a colour != 0, as the layers take them; every one when there is no A):
// what the layers' own largest radii reach. Empty ones (a render's
// transparent sky, the most blurred of all) are in no layer. Absent colour
// planes (null) count as 0.
double largest_present(std::span<const float> r, const float* const rgba[4]) {
    double m = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        bool present = !rgba[3] || rgba[3][i] > 0.0f;
        for (int c = 0; c < 3 && !present; ++c) present = rgba[c] && rgba[c][i] != 0.0f;
        if (present && std::isfinite(r[i])) m = std::max(m, double(r[i]));
    }
    return m;
}

// Which path an input takes (see the top of the file).
enum class InputKind { Deep, Parts, DepthMap };

struct InputChoice {
    InputKind kind = InputKind::DepthMap;
    int deep_part = -1;  // Deep: the first deep part
};

// A depth map in its own part (renderers' and stereo files' "depth" parts):
// when exactly one flat part has colour (R, G, B, no layer groups) and no
// depth, and another flat part without colour has the depth channel, the
// plate with that depth attached (as `depth_channel`, default Z) in `out`.
Result<bool> with_depth_part(const ImageSet& input, const PositionSource& source, ImageSet& out) {
    int plate = -1, depth = -1, zc = -1;
    for (std::size_t i = 0; i < input.size(); ++i) {
        if (input.is_deep(i)) return false;
        const Image& img = input.flat(i);
        const RgbaIndices ix = find_rgba(img);
        auto z = find_depth_channel(img, source.depth_channel);
        if (ix.r >= 0 && ix.g >= 0 && ix.b >= 0) {
            if (plate >= 0 || !rgba_groups(img).empty() || (z && *z >= 0)) return false;
            plate = int(i);
        } else if (z && *z >= 0 && depth < 0) {
            depth = int(i), zc = *z;
        }
    }
    if (plate < 0 || depth < 0) return false;
    Image merged = input.flat(std::size_t(plate));
    const auto name = [&](int k) {
        const std::string& n = input.part_name(std::size_t(k));
        return n.empty() ? "part " + std::to_string(k) : "part '" + n + "'";
    };
    if (Status st = attach_depth(merged, input.flat(std::size_t(depth)), zc,
                                 source.depth_channel.empty() ? std::string("Z") : source.depth_channel, name(plate),
                                 name(depth));
        !st)
        return st.prefix("defocus");
    out.parts.clear();
    out.parts.emplace_back(std::move(merged));
    return true;
}

InputChoice choose_input(const ImageSet& input) {
    const std::size_t ref = defocus_reference_part(input);
    if (ref < input.size() && input.is_deep(ref)) return {InputKind::Deep, int(ref)};
    if (input.size() > 1 || !rgba_groups(input.flat(0)).empty()) return {InputKind::Parts, -1};
    return {InputKind::DepthMap, -1};
}

// What the output keeps of the input: its display window, metadata, names,
// storage and the types of its colour channels (no alpha: as R; UInt: float).
struct OutputReference {
    Roi display;
    const Metadata* metadata = nullptr;
    std::string name, view;
    StorageHints storage;
    std::array<PixelType, 4> types{PixelType::Float, PixelType::Float, PixelType::Float, PixelType::Float};
};

// type_of(c) is the type of channel c ("R", "G", "B", "A") or nullopt if absent.
template <class TypeOf>
std::array<PixelType, 4> colour_types(TypeOf&& type_of) {
    std::array<PixelType, 4> types{};
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
        std::optional<PixelType> t = type_of(names[c]);
        if (!t && c == 3) t = type_of("R");
        const PixelType v = t.value_or(PixelType::Float);
        types[std::size_t(c)] = v == PixelType::UInt ? PixelType::Float : v;
    }
    return types;
}

template <class Part>
OutputReference reference_of(const Part& part) {
    OutputReference ref;
    ref.display = part.display_window();
    ref.metadata = &part.metadata;
    ref.name = part.name;
    ref.view = part.view;
    ref.storage = part.storage;
    return ref;
}

OutputReference output_reference(const ImageSet& input, const InputChoice& choice) {
    if (choice.kind == InputKind::Deep) {
        const DeepImage& d = input.deep(std::size_t(choice.deep_part));
        OutputReference ref = reference_of(d);
        ref.types = colour_types([&](const char* n) -> std::optional<PixelType> {
            const int c = d.channel_index(n);
            if (c < 0) return std::nullopt;
            return d.channel(c).type;
        });
        return ref;
    }
    const Image& flat = input.flat(0);
    OutputReference ref = reference_of(flat);
    const RgbaIndices fi = find_rgba(flat);
    ref.types = colour_types([&](const char* n) -> std::optional<PixelType> {
        const int c = n[0] == 'R' ? fi.r : n[0] == 'G' ? fi.g : n[0] == 'B' ? fi.b : fi.a;
        if (c < 0) return std::nullopt;
        return flat.channel(c).type;
    });
    return ref;
}

// A deep part -> its layers (layers_from_deep), each extended behind the
// nearer layers that fully hide it.
Result<std::unique_ptr<LayerSource>> deep_layers(const DeepImage& d, const BlurField& field, const Camera& camera,
                                                 const DefocusOptions& settings, const Exec& exec) {
    if (d.channel_index("A") < 0 || d.channel_index("R") < 0)
        return Status::error("defocus: the deep part has no R, G, B, A channels (it has " +
                             std::to_string(d.nchannels()) + " channels)");
    if (d.z_channel() < 0) return Status::error("defocus: the deep part has no depth channel 'Z'");
    // Every sample's blur: it places Auto's blur cuts and bounds the extension.
    std::vector<float> r(d.total_samples());
    if (Status st = evaluate_blur_deep(field, camera, d, -1, r, exec); !st) return st.prefix("defocus: blur field");
    // Deep renders keep only visible samples: extend each layer behind the
    // nearer layers that fully hide it, as far as the largest blur can reveal
    // (not into genuinely empty, transparent areas).
    ExtendOptions ext;
    ext.extend_px = std::min(largest_finite(r), settings.diffusion.max_radius);
    ext.surface_reach_px = defocus_margin(ext.extend_px);  // behind its own surface, as far as the blur spreads
    ext.occluder_alpha = 0.999f;
    ext.continue_coverage = true;  // a ray through empty depths: the layer is empty there
    ext.fill_highlight_knee = ExtendOptions::HighlightKnee::One;
    // Diffusion slices deep inputs by their front surface, as plates: cut
    // only at the silhouettes that need a bound, each layer's surface
    // onward and seams marked (docs/diffusion.md); blur_cuts Off ignores
    // the radii.
    const bool by_front_surface = settings.filter == DefocusFilter::Diffusion;
    auto layers = deep_layer_source(d, settings.split, r, &ext, exec, by_front_surface);
    if (!layers) return layers.status().prefix("defocus");
    const float* rgba[4];
    const char* const names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
        const int k = d.channel_index(names[c]);
        rgba[c] = k >= 0 ? d.samples(k) : nullptr;
    }
    return with_largest_blur_radius(std::move(layers).value(), std::min(largest_present(r, rgba), ext.extend_px));
}

// One flat RGBA + depth part -> layers_from_depth_map, extended by the
// largest blur radius of the image.
// The blur radius of every pixel of a plate at its prepared depth (pixel
// centres), of every mixed pixel's foreground (one per entry of pd.mixed)
// and of every front_mixed pixel's background (rb).
Status plate_radii(const BlurField& field, const Camera& camera, const PlateDepth& pd, FrameBuffer<float>& r,
                   std::vector<float>& rf, std::vector<float>& rb, const Exec& exec) {
    const Roi w = pd.window;
    const int W = w.width();
    r.resize(pd.depth.size());  // every element evaluated below
    Status st = parallel_run(exec, w.height(), [&](long y0, long y1) {
        std::vector<PixelDepth> px(static_cast<std::size_t>(W));
        for (long yy = y0; yy < y1; ++yy) {
            const std::size_t row = std::size_t(yy) * std::size_t(W);
            for (int x = 0; x < W; ++x) px[std::size_t(x)] = {w.x0 + x + 0.5, w.y0 + yy + 0.5, pd.depth[row + std::size_t(x)]};
            if (Status s = field.evaluate(camera, px, std::span<float>(r.data() + row, std::size_t(W))); !s) return s;
        }
        return Status::ok();
    }, 8, "blur map");
    if (!st) return st;
    // At each listed pixel's centre, the depth `depth_of` gives.
    auto at_pixels = [&](const std::vector<MixedPixel>& list, auto depth_of, std::vector<float>& out) {
        std::vector<PixelDepth> q(list.size());
        for (std::size_t k = 0; k < list.size(); ++k) {
            const std::size_t i = list[k].index;
            q[k] = {w.x0 + double(i % std::size_t(W)) + 0.5, w.y0 + double(i / std::size_t(W)) + 0.5, depth_of(list[k])};
        }
        out.assign(q.size(), 0.0f);
        return field.evaluate(camera, q, out);
    };
    if (Status s = at_pixels(pd.mixed, [](const MixedPixel& m) { return m.fg_depth; }, rf); !s) return s;
    return at_pixels(pd.front_mixed, [](const MixedPixel& m) { return m.bg_depth; }, rb);
}

// A plate: its depth decoded and cleaned (holes, speckles, noise, mixed silhouette
// pixels, plate.h), every sample's blur at its own depth, then the slices.
Result<std::unique_ptr<LayerSource>> depth_map_layers(const Image& flat, const BlurField& field, const Camera& camera,
                                                      const DefocusOptions& settings, const Exec& exec,
                                                      DepthCleanupStats& depth_stats) {
    const RgbaIndices rgba = find_rgba(flat);
    if (rgba.r < 0 || rgba.g < 0 || rgba.b < 0)
        return Status::error("defocus: the input has no R, G, B channels (channels: " + channel_list(flat) + ")");
    // Checked here, not only per layer: a layer's extension would carry a
    // bad pixel to its neighbours, and the message must name the plate's own.
    if (Status st = defocus_detail::check_finite_colour(flat, rgba, "defocus", exec); !st) return st;
    auto pos = find_position_channels(flat, settings.source.position_channels);
    if (!pos) return pos.status().prefix("defocus");
    auto z = find_depth_channel(flat, settings.source.depth_channel);
    if (!z) return z.status().prefix("defocus");
    if (*z < 0)
        return Status::error("defocus: the input has no depth channel '" +
                             (settings.source.depth_channel.empty() ? std::string("Z") : settings.source.depth_channel) +
                             "' (channels: " + channel_list(flat) + ")",
                             StatusCode::NotFound, "depth_channel");
    auto pd = prepare_plate_depth(flat, *z, settings.source.depth_decode, camera, settings.cleanup, exec);
    if (!pd) return pd.status().prefix("defocus");
    FrameBuffer<float> r;
    std::vector<float> rf, rb;
    if (Status st = plate_radii(field, camera, *pd, r, rf, rb, exec); !st) return st.prefix("defocus: blur field");
    // A mixed pixel at the edge of a front sharper than its background is
    // split: its background's share blurs with the background (plate.h, step 4).
    split_sharp_fronts(*pd, std::span<float>(r.data(), r.size()), rf, rb);
    depth_stats = pd->stats;
    SliceOptions so;
    so.split = settings.split;
    so.source = settings.source;
    so.depth = &pd.value();
    so.extend_px = std::min(std::max(largest_finite(r), largest_finite(rf)), settings.diffusion.max_radius);
    so.surface_reach_px = defocus_margin(so.extend_px);  // behind its own surface, as far as the blur spreads
    so.mark_onward = settings.filter == DefocusFilter::Diffusion;
    // Plates are continuous (floors, tables): only cuts by blur let a blurred
    // foreground spread over a sharp background, so they are on unless told not.
    if (settings.split.blur_cuts != LayerSplit::BlurCuts::Off) {
        so.radius = r;
        so.fg_radius = rf;
        so.cut_at_silhouettes = settings.filter == DefocusFilter::Diffusion;
    }
    auto layers = depth_map_layer_source(flat, so, exec);
    if (!layers) return layers.status().prefix("defocus");
    const float* planes[4] = {flat.plane(rgba.r), flat.plane(rgba.g), flat.plane(rgba.b),
                              rgba.a >= 0 ? flat.plane(rgba.a) : nullptr};
    // Mixed pixels are present: their foregrounds' radii count.
    const double largest = std::max(largest_present(r, planes), largest_finite(rf));
    return with_largest_blur_radius(std::move(layers).value(), std::min(largest, so.extend_px));
}

// The layers of an input by its kind; errors start with "defocus: ".
Result<std::unique_ptr<LayerSource>> input_layers(const ImageSet& input, const InputChoice& choice,
                                                  const BlurField& field, const Camera& camera,
                                                  const DefocusOptions& settings, const Exec& exec,
                                                  DepthCleanupStats& depth_stats) {
    switch (choice.kind) {
        case InputKind::Deep: return deep_layers(input.deep(std::size_t(choice.deep_part)), field, camera, settings, exec);
        case InputKind::Parts: {
            auto layers = layers_from_parts(input, settings.source, exec);
            if (!layers) return layers.status().prefix("defocus");
            auto largest = defocus_detail::largest_layer_radius(*layers, field, camera, settings, exec);
            if (!largest) return largest.status();
            return with_largest_blur_radius(source_of(std::move(layers).value()), *largest);
        }
        case InputKind::DepthMap: break;
    }
    return depth_map_layers(input.flat(0), field, camera, settings, exec, depth_stats);
}

// The channels of a single flat input carried to the output: all but its
// colour (R, G, B, A and the layer groups' colour) and names the output
// already has (the first of a repeated name wins).
std::vector<int> carried_channels(const Image& flat, const Image& rgba) {
    const RgbaIndices ix = find_rgba(flat);
    const std::set<std::string> groups = rgba_groups(flat);
    std::set<std::string> taken;
    for (const ChannelSpec& c : rgba.channels()) taken.insert(c.name);
    std::vector<int> carried;
    for (int c = 0; c < flat.nchannels(); ++c) {
        if (c == ix.r || c == ix.g || c == ix.b || c == ix.a) continue;
        if (is_group_colour(flat.channel(c).name, groups)) continue;
        if (!taken.insert(flat.channel(c).name).second) continue;
        carried.push_back(c);
    }
    return carried;
}

// Row y of `dst` over its window: `src` (its own row y, `src_win` in
// absolute pixels) where the windows overlap, zero elsewhere.
template <class T>
void carry_row(const T* src, const Roi& src_win, T* dst, const Roi& dst_win, int y) {
    const Roi ov = intersect(src_win, dst_win);
    const bool in = !ov.empty() && y >= ov.y0 && y < ov.y1;
    T* row = dst + std::size_t(y - dst_win.y0) * std::size_t(dst_win.width());
    const int xa = in ? ov.x0 : dst_win.x1, xb = in ? ov.x1 : dst_win.x1;
    std::fill(row, row + (xa - dst_win.x0), T(0));
    if (in)
        std::copy_n(src + std::size_t(y - src_win.y0) * std::size_t(src_win.width()) + std::size_t(ov.x0 - src_win.x0),
                    ov.width(), row + (xa - dst_win.x0));
    std::fill(row + (xb - dst_win.x0), row + dst_win.width(), T(0));
}

// The one flat output part: the defocused R, G, B, A with the reference's
// types, display window, metadata and names, then the channels carried from
// `carry_from` (a single flat input; nullptr: none), zero outside its window.
// Written row by row in parallel into planes not zeroed first: at 4K a
// carried part is a dozen 33 MB planes, which one zeroing thread then a
// copying one took 0.1 s to fill.
Result<Image> output_part(Image rgba, const OutputReference& ref, const Image* carry_from, const Exec& exec) {
    const std::vector<int> carried = carry_from ? carried_channels(*carry_from, rgba) : std::vector<int>{};
    Image res;
    if (carried.empty()) {
        res = std::move(rgba);
        for (int c = 0; c < 4; ++c)
            if (Status st = res.set_channel_type(c, ref.types[std::size_t(c)]); !st) return st.prefix("defocus");
        res.set_display_window(ref.display);
    } else {
        std::vector<ChannelSpec> specs;
        for (int c = 0; c < 4; ++c) specs.push_back({rgba.channel(c).name, ref.types[std::size_t(c)]});
        for (int c : carried) specs.push_back(carry_from->channel(c));
        const Roi win = rgba.data_window();
        res = Image::uninitialized(std::move(specs), win, ref.display);
        const Roi from = carry_from->data_window();
        const bool ok = parallel_for(exec, win.height(), [&](long r0, long r1) {
            for (int y = win.y0 + int(r0); y < win.y0 + int(r1); ++y) {
                for (int c = 0; c < 4; ++c) carry_row(rgba.plane(c), win, res.plane(c), win, y);
                for (std::size_t k = 0; k < carried.size(); ++k) {
                    const int c = carried[k], dc = 4 + int(k);
                    if (carry_from->channel(c).type == PixelType::UInt)
                        carry_row(carry_from->uplane(c), from, res.uplane(dc), win, y);
                    else
                        carry_row(carry_from->plane(c), from, res.plane(dc), win, y);
                }
            }
        }, 16);
        if (!ok) return Status::cancelled("defocus");
    }
    res.metadata = *ref.metadata;
    res.name = ref.name;
    res.view = ref.view;
    res.storage = ref.storage;
    return res;
}

}  // namespace

std::size_t defocus_reference_part(const ImageSet& input) {
    for (std::size_t i = 0; i < input.size(); ++i)
        if (input.is_deep(i)) return i;
    return 0;
}

Result<ImageSet> defocus(const ImageSet& input, const BlurField& field, const Camera& camera,
                         const DefocusOptions& settings, DefocusStats* stats, const Exec& exec) {
    if (input.empty()) return Status::error("defocus: the input has no image parts");
    if (const std::vector<std::string> views = part_views(input); views.size() > 1) {
        std::string list;
        for (const std::string& v : views) list += (list.empty() ? "'" : ", '") + v + "'";
        return Status::error("defocus: the input has " + std::to_string(views.size()) + " views (" + list +
                                 "); defocus one view at a time (select_view)",
                             StatusCode::InvalidArgument, "view");
    }
    ImageSet merged;
    auto merge = with_depth_part(input, settings.source, merged);
    if (!merge) return merge.status();
    if (*merge) return defocus(merged, field, camera, settings, stats, exec);
    const InputChoice choice = choose_input(input);
    const OutputReference ref = output_reference(input, choice);

    const auto t0 = std::chrono::steady_clock::now();
    DepthCleanupStats depth_stats;
    auto layers = input_layers(input, choice, field, camera, settings, exec, depth_stats);
    const double t_layers = seconds_since(t0);
    if (!layers) return layers.status();
    if ((*layers)->size() == 0) return Status::error("defocus: the input gave no layers");

    DefocusStats local;
    DefocusStats& S = stats ? *stats : local;
    auto out = defocus_layers(**layers, field, camera, settings, &S, exec);
    S.t_layers += t_layers;  // the preparation for all layers, then each layer's making
    S.depth = depth_stats;
    if (!out) return out.status();

    const bool single_flat = choice.kind != InputKind::Deep && input.size() == 1;
    auto part = output_part(std::move(out).value(), ref, single_flat ? &input.flat(0) : nullptr, exec);
    if (!part) return part.status();
    ImageSet set;
    set.parts.emplace_back(std::move(part).value());
    return set;
}

}  // namespace gdof
