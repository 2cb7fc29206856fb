// Flat RGBA + depth map -> depth slices with background extension.
//
// - Colour: R, G, B (premultiplied) and A; without A the image is opaque.
//   A pixel is present when A > 0 or any colour != 0; present pixels go to
//   exactly one slice (with their colour and alpha), the others to none.
// - Depth: the depth channel (SliceOptions.source.depth_channel, or Z,
//   depth.Z, Depth.Z, depth, Depth) decoded with source.depth_decode. Pixels
//   whose decoded depth is not finite (invalid samples, sky) get Z = +inf and
//   belong to the farthest slice.
// - Positions (P.x/P.y/P.z per source.position_channels) are carried when present.
// - Extension (extend_layers_behind, layers_extend.cpp): for every slice but
//   the nearest, the pixels present in nearer slices (hidden behind them)
//   within extend_px of the slice's own coverage (the farthest non-empty
//   slice: all of them) get a push-pull fill of the slice's unpremultiplied
//   colour (weights = its alpha), depth and positions, with alpha 1.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "gdof/fill.h"
#include "layers/layers_internal.h"

namespace gdof {

using namespace layers_detail;

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
    const PositionSource& src = options.source;
    auto zc = find_depth_channel(img, src.depth_channel);
    if (!zc) return zc.status();
    if (*zc < 0) return Status::error("depth-map layers: no depth channel (looked for Z, depth.Z, Depth.Z, depth, Depth)");
    if (Status st = src.depth_decode.validate(); !st) return st.prefix("depth channel '" + img.channel(*zc).name + "'");
    auto pr = find_position_channels(img, src.position_channels);
    if (!pr) return pr.status();
    const std::optional<std::array<int, 3>> pos = *pr;

    const Roi win = img.data_window();
    const int W = win.width(), H = win.height();
    const std::size_t n = img.npixels();
    const float* r = img.plane(ix.r);
    const float* g = img.plane(ix.g);
    const float* b = img.plane(ix.b);
    const float* a = ix.a >= 0 ? img.plane(ix.a) : nullptr;

    // Decoded depth (+inf where invalid) and presence.
    std::vector<float> depth(n);
    std::vector<unsigned char> present(n, 0);
    if (!options.radius.empty() && options.radius.size() != n)
        return Status::error("depth-map layers: " + std::to_string(options.radius.size()) + " blur radii for " +
                             std::to_string(n) + " pixels");
    std::vector<float> present_depths, present_radii;
    present_depths.reserve(n);
    const float* zraw = img.plane(*zc);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = decode_depth(zraw[i], src.depth_decode);
        depth[i] = std::isfinite(d) ? float(d) : float(kInf);
        present[i] = (!a || a[i] > 0.0f || r[i] != 0.0f || g[i] != 0.0f || b[i] != 0.0f) ? 1 : 0;
        if (present[i]) {
            present_depths.push_back(depth[i]);
            if (!options.radius.empty()) present_radii.push_back(options.radius[i]);
        }
    }
    const DepthSlices slices = choose_slices(present_depths, options.split, present_radii);
    const int ns = slices.count();

    // Slice of each present pixel (-1: none), boxes, ranges.
    std::vector<int> slice(n, -1);
    std::vector<Roi> own_box(static_cast<std::size_t>(ns));
    std::vector<double> znear(std::size_t(ns), kInf), zfar(std::size_t(ns), -kInf);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            if (!present[i]) continue;
            const int s = slices.slice_of(depth[i]);
            slice[i] = s;
            own_box[std::size_t(s)] = unite(own_box[std::size_t(s)], Roi{win.x0 + x, win.y0 + y, win.x0 + x + 1, win.y0 + y + 1});
            znear[std::size_t(s)] = std::min(znear[std::size_t(s)], double(depth[i]));
            zfar[std::size_t(s)] = std::max(zfar[std::size_t(s)], double(depth[i]));
        }

    std::vector<std::string> chan_names = {"R", "G", "B", "A", "Z"};
    if (pos) chan_names.insert(chan_names.end(), {"P.x", "P.y", "P.z"});
    const float* pp[3] = {pos ? img.plane((*pos)[0]) : nullptr, pos ? img.plane((*pos)[1]) : nullptr,
                          pos ? img.plane((*pos)[2]) : nullptr};

    auto src_index = [&](int x, int y) {  // absolute -> index in the input
        return std::size_t(y - win.y0) * std::size_t(W) + std::size_t(x - win.x0);
    };
    std::vector<Layer> layers(static_cast<std::size_t>(ns));
    const bool ok = parallel_for(exec, ns, [&](long s0, long s1) {
        for (long sl = s0; sl < s1; ++sl) {
            const int s = int(sl);
            Layer& L = layers[std::size_t(s)];
            const Roi own = own_box[std::size_t(s)];
            const bool empty = own.empty();
            L.depth_near = empty ? std::numeric_limits<double>::quiet_NaN() : znear[std::size_t(s)];
            L.depth_far = empty ? std::numeric_limits<double>::quiet_NaN() : zfar[std::size_t(s)];
            L.slice_near = slices.lo[std::size_t(s)];
            L.slice_far = slices.hi[std::size_t(s)];
            L.name = empty ? depth_range_name(L.slice_near, L.slice_far) + " (empty)"
                           : depth_range_name(L.depth_near, L.depth_far);

            const Roi box = own;
            L.image = Image::with_channels(chan_names, box);
            L.image.set_display_window(img.display_window());
            L.image.metadata = img.metadata;
            L.image.name = L.name;
            L.image.view = img.view;
            for (int y = box.y0; y < box.y1; ++y)
                for (int x = box.x0; x < box.x1; ++x) {
                    const std::size_t o = L.image.offset(x, y);
                    const std::size_t i = src_index(x, y);
                    if (slice[i] == s) {
                        L.image.plane(0)[o] = r[i];
                        L.image.plane(1)[o] = g[i];
                        L.image.plane(2)[o] = b[i];
                        L.image.plane(3)[o] = a ? a[i] : 1.0f;
                        L.image.plane(4)[o] = depth[i];
                        if (pos)
                            for (int k = 0; k < 3; ++k) L.image.plane(5 + k)[o] = pp[k][i];
                        continue;
                    }
                    L.image.plane(4)[o] = kNaN;
                    if (pos)
                        for (int k = 0; k < 3; ++k) L.image.plane(5 + k)[o] = kNaN;
                }
        }
    });
    if (!ok) return Status::cancelled();
    // Plates: the background is everywhere, so the farthest slice fills every
    // hidden pixel; nearer slices reach extend_px behind their neighbours.
    ExtendOptions ext;
    ext.extend_px = options.extend_px;
    ext.farthest_fills_frame = true;
    ext.occluder_alpha = 0.0f;
    if (Status st = extend_layers_behind(layers, win, ext, exec); !st) return st;
    return layers;
}

}  // namespace gdof
