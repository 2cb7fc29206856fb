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

Status plate_samples(const Image& img, const SliceOptions& o, const float* r, const float* g, const float* b,
                     const float* a, PlateSamples& s) {
    const std::size_t n = img.npixels();
    s.present.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        s.present[i] = (!a || a[i] > 0.0f || r[i] != 0.0f || g[i] != 0.0f || b[i] != 0.0f) ? 1 : 0;
    if (o.depth) {
        if (!(o.depth->window == img.data_window()) || o.depth->depth.size() != n)
            return Status::error("depth-map layers: the prepared depth covers " + to_string(o.depth->window) +
                                 ", the image " + to_string(img.data_window()));
        s.depth = o.depth->depth;
        for (float& d : s.depth)
            if (!std::isfinite(d)) d = float(kInf);
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

}  // namespace

Result<std::vector<Layer>> layers_from_depth_map(const Image& img, const SliceOptions& options, const Exec& exec) {
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
    if (!(options.continuity > 1.0) || !(options.continuity < 2.0))
        return Status::error("depth-map layers: continuity must be in (1, 2), got " + std::to_string(options.continuity));
    // With a prepared depth, positions come from the layers' depth and the
    // camera: a mixed pixel's position pass is as mixed as its filtered Z.
    std::optional<std::array<int, 3>> pos;
    if (!options.depth) {
        auto pr = find_position_channels(img, options.source.position_channels);
        if (!pr) return pr.status();
        pos = *pr;
    }

    const Roi win = img.data_window();
    const int W = win.width(), H = win.height();
    const std::size_t n = img.npixels();
    const float* r = img.plane(ix.r);
    const float* g = img.plane(ix.g);
    const float* b = img.plane(ix.b);
    const float* a = ix.a >= 0 ? img.plane(ix.a) : nullptr;
    PlateSamples ps;
    if (Status st = plate_samples(img, options, r, g, b, a, ps); !st) return st;
    if (!options.radius.empty() && options.radius.size() != n)
        return Status::error("depth-map layers: " + std::to_string(options.radius.size()) + " blur radii for " +
                             std::to_string(n) + " pixels");
    const std::size_t nmixed = ps.parts ? ps.parts->size() : 0;
    if (!options.fg_radius.empty() && options.fg_radius.size() != nmixed)
        return Status::error("depth-map layers: " + std::to_string(options.fg_radius.size()) +
                             " foreground blur radii for " + std::to_string(nmixed) + " mixed pixels");

    // 2. Slices over every sample.
    std::vector<float> sample_depths, sample_radii;
    sample_depths.reserve(n);
    const bool radii = !options.radius.empty();
    for (std::size_t i = 0; i < n; ++i) {
        if (!ps.present[i]) continue;
        sample_depths.push_back(ps.depth[i]);
        if (radii) sample_radii.push_back(options.radius[i]);
        if (const MixedPixel* m = ps.mixed_at(i)) {
            sample_depths.push_back(m->fg_depth);
            if (radii)
                sample_radii.push_back(options.fg_radius.empty() ? options.radius[i]
                                                                 : options.fg_radius[std::size_t(ps.mixed[i])]);
        }
    }
    const DepthSlices slices = choose_slices(sample_depths, options.split, sample_radii);
    const int ns = slices.count();
    std::vector<int> slice(n, -1), fg_slice(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        if (!ps.present[i]) continue;
        slice[i] = slices.slice_of(ps.depth[i]);
        if (const MixedPixel* m = ps.mixed_at(i)) {
            const int f = slices.slice_of(m->fg_depth);
            if (f != slice[i]) fg_slice[i] = f;  // in one slice the pixel is simply whole
        }
    }

    // Which slice continues or extends behind each pixel (the background
    // seen nearest to it).
    std::vector<int> front(n, -1);
    std::vector<std::vector<unsigned char>> owns(static_cast<std::size_t>(ns), std::vector<unsigned char>(n, 0));
    for (std::size_t i = 0; i < n; ++i) {
        if (slice[i] < 0) continue;
        owns[std::size_t(slice[i])][i] = 1;
        front[i] = slice[i];
        if (fg_slice[i] >= 0) owns[std::size_t(fg_slice[i])][i] = 1, front[i] = std::min(front[i], fg_slice[i]);
    }
    const std::vector<int> owner = background_owners(front, owns, W, H, exec);
    owns.clear();

    // 3. Per slice: own samples, continued pixels of nearer slices.
    std::vector<std::string> chan_names = {"R", "G", "B", "A", "Z"};
    if (pos) chan_names.insert(chan_names.end(), {"P.x", "P.y", "P.z"});
    const float* pp[3] = {pos ? img.plane((*pos)[0]) : nullptr, pos ? img.plane((*pos)[1]) : nullptr,
                          pos ? img.plane((*pos)[2]) : nullptr};
    const int reach = options.continue_surfaces ? int(std::ceil(options.extend_px)) : 0;
    std::vector<Layer> layers(static_cast<std::size_t>(ns));
    Status st = parallel_run(exec, ns, [&](long s0, long s1) {
        std::vector<unsigned char> cont;
        for (long sl = s0; sl < s1; ++sl) {
            const int s = int(sl);
            Layer& L = layers[std::size_t(s)];
            // Own samples and their range.
            Roi own;
            double znear = kInf, zfar = -kInf;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                    double z;
                    if (slice[i] == s) z = ps.depth[i];
                    else if (fg_slice[i] == s) z = ps.mixed_at(i)->fg_depth;
                    else continue;
                    own = unite(own, Roi{win.x0 + x, win.y0 + y, win.x0 + x + 1, win.y0 + y + 1});
                    znear = std::min(znear, z);
                    zfar = std::max(zfar, z);
                }
            const bool empty = own.empty();
            L.depth_near = empty ? std::numeric_limits<double>::quiet_NaN() : znear;
            L.depth_far = empty ? std::numeric_limits<double>::quiet_NaN() : zfar;
            L.slice_near = slices.lo[std::size_t(s)];
            L.slice_far = slices.hi[std::size_t(s)];
            L.name = empty ? depth_range_name(L.slice_near, L.slice_far) + " (empty)"
                           : depth_range_name(L.depth_near, L.depth_far);
            Roi box = own;
            if (!empty && reach > 0) box = unite(box, continue_surface(ps.depth, ps.present, slice, owner, s, W, H, win,
                                                                       options.continuity, reach, cont));
            else cont.clear();

            L.image = Image::with_channels(chan_names, box);
            L.image.set_display_window(img.display_window());
            L.image.metadata = img.metadata;
            L.image.name = L.name;
            L.image.view = img.view;
            for (int y = box.y0; y < box.y1; ++y)
                for (int x = box.x0; x < box.x1; ++x) {
                    const std::size_t o = L.image.offset(x, y);
                    const std::size_t i = std::size_t(y - win.y0) * std::size_t(W) + std::size_t(x - win.x0);
                    const bool whole = slice[i] == s || (!cont.empty() && cont[i]);
                    const bool fg = fg_slice[i] == s;
                    if (!whole && !fg) {
                        for (int c = 4; c < L.image.nchannels(); ++c) L.image.plane(c)[o] = kNaN;
                        continue;
                    }
                    // A split pixel: its foreground part in the foreground's
                    // slice, its background part where the pixel is whole.
                    // Split in two slices only: within one it is simply whole.
                    const MixedPixel* m = fg_slice[i] >= 0 ? ps.mixed_at(i) : nullptr;
                    const float alpha = a ? a[i] : 1.0f;
                    if (!whole) {
                        for (int c = 0; c < 3; ++c) L.image.plane(c)[o] = m->fg_share * m->fg_rgb[c];
                        L.image.plane(3)[o] = m->fg_share * alpha;
                        L.image.plane(4)[o] = m->fg_depth;
                    } else {
                        const float rgb[3] = {r[i], g[i], b[i]};
                        for (int c = 0; c < 3; ++c) L.image.plane(c)[o] = m ? m->bg_rgb[c] : rgb[c];
                        L.image.plane(3)[o] = alpha;
                        L.image.plane(4)[o] = ps.depth[i];
                    }
                    if (pos)
                        for (int c = 0; c < 3; ++c) L.image.plane(5 + c)[o] = pp[c][i];
                }
        }
        return Status::ok();
    });
    if (!st) return st;
    // 4. Plates: the background is everywhere, so the farthest slice fills every
    // hidden pixel; nearer slices reach extend_px behind their neighbours.
    ExtendOptions ext;
    ext.extend_px = options.extend_px;
    ext.farthest_fills_frame = true;
    ext.occluder_alpha = 0.0f;
    ext.owner = owner;
    if (Status es = extend_layers_behind(layers, win, ext, exec); !es) return es;
    return layers;
}

}  // namespace gdof
