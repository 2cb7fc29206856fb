// One layer of the defocus pipeline, before diffusion: its content, the blur
// radius at each pixel's world position and the checks on those radii.
#include <chrono>
#include <cmath>
#include <limits>

#include "common/format_number.h"
#include "diffusion/defocus_internal.h"

namespace gdof::defocus_detail {

namespace {

std::string pixel_str(int x, int y) { return "(" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

std::string num(double v) { return format_number(v, 6); }

}  // namespace

Status non_finite_colour(const std::string& where, int channel, float value, int x, int y) {
    return Status::error(where + ": channel '" + std::string("RGBA").substr(std::size_t(channel), 1) + "' is " +
                         num(value) + " at pixel " + pixel_str(x, y) + " (colour must be finite)");
}

Status check_finite_colour(const Image& img, const RgbaIndices& rgba, const std::string& where, const Exec& exec) {
    const Roi win = img.data_window();
    const int w = win.width();
    const int chans[4] = {rgba.r, rgba.g, rgba.b, rgba.a};
    return parallel_run(exec, win.height(), [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            // A whole row's planes first (a reduction the compiler vectorises),
            // then, only if one is not finite, the first bad pixel in order.
            bool finite = true;
            for (int c = 0; c < 4; ++c) {
                if (chans[c] < 0) continue;
                const float* row = img.plane(chans[c]) + std::size_t(y) * std::size_t(w);
                bool ok = true;
                for (int x = 0; x < w; ++x) ok &= std::abs(row[x]) <= std::numeric_limits<float>::max();
                finite = finite && ok;
            }
            if (finite) continue;
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 4; ++c) {
                    if (chans[c] < 0) continue;
                    const float v = img.plane(chans[c])[std::size_t(y) * std::size_t(w) + std::size_t(x)];
                    if (!std::isfinite(v)) return non_finite_colour(where, c, v, win.x0 + x, win.y0 + int(y));
                }
        }
        return Status::ok();
    }, 16);
}

std::string layer_label(const Layer& layer, int index) {
    return "layer " + std::to_string(index) + (layer.name.empty() ? std::string() : " '" + layer.name + "'");
}

Result<LayerAnalysis> analyse_layer(const Layer& layer, int index, const BlurField& field, const Camera& camera,
                                    const DiffusionOptions& settings, const Exec& exec) {
    const Image& img = layer.image;
    const std::string where = layer_label(layer, index);
    LayerAnalysis a;
    a.rgba = find_rgba(img);
    for (auto [c, name] : {std::pair{a.rgba.r, "R"}, {a.rgba.g, "G"}, {a.rgba.b, "B"}, {a.rgba.a, "A"}}) {
        if (c < 0) return Status::error(where + ": no channel '" + std::string(name) + "'");
        if (img.channel(c).type == PixelType::UInt)
            return Status::error(where + ": channel '" + std::string(name) + "' is not a float channel");
    }
    const Roi win = img.data_window();
    const int w = win.width();
    if (win.empty()) return a;

    // Content: any of R, G, B, A non-zero. Colour must be finite. Rows in
    // parallel, each with its own span; the first bad pixel in row order
    // is the one reported.
    const float* planes[4] = {img.plane(a.rgba.r), img.plane(a.rgba.g), img.plane(a.rgba.b), img.plane(a.rgba.a)};
    std::vector<int> row_min(std::size_t(win.height()), w), row_max(std::size_t(win.height()), -1);
    std::vector<unsigned char> row_alpha(std::size_t(win.height()), 0);
    Status st = parallel_run(exec, win.height(), [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            int xmin = w, xmax = -1;
            bool alpha = false;
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                bool nz = false;
                for (int c = 0; c < 4; ++c) {
                    const float v = planes[c][i];
                    if (!std::isfinite(v)) return non_finite_colour(where, c, v, win.x0 + x, win.y0 + int(y));
                    nz = nz || v != 0.0f;
                }
                alpha = alpha || planes[3][i] > 0.0f;
                if (nz) {
                    xmin = std::min(xmin, x);
                    xmax = x;
                }
            }
            row_min[std::size_t(y)] = xmin;
            row_max[std::size_t(y)] = xmax;
            row_alpha[std::size_t(y)] = alpha;
        }
        return Status::ok();
    }, 16);
    if (!st) return st;
    bool any_alpha = false;
    Roi content;
    for (int y = 0; y < win.height(); ++y) {
        any_alpha = any_alpha || row_alpha[std::size_t(y)];
        if (row_max[std::size_t(y)] >= 0)
            content = unite(content, Roi{win.x0 + row_min[std::size_t(y)], win.y0 + y, win.x0 + row_max[std::size_t(y)] + 1,
                                         win.y0 + y + 1});
    }
    if (content.empty()) return a;
    a.empty = false;
    a.content = content;
    a.radius_from_alpha = any_alpha;

    a.radius.resize(img.npixels());  // every pixel written by the blur map
    // A layer's Z is decoded already (layers.h): what is not a depth there
    // (NaN, <= 0) is sky, as +inf is; holes were the input's to fill.
    PositionSource layer_z;
    layer_z.depth_decode.invalid = std::numeric_limits<double>::infinity();
    if (Status map = evaluate_blur_map(field, camera, img, layer_z, ImageView::planar(a.radius.data(), 1, win), exec); !map)
        return map.prefix(where + ": blur field");

    const int zc = img.channel_index("Z");
    std::vector<double> row_rmax(std::size_t(win.height()), 0.0);
    const KnownWeight known(a, layer);
    st = parallel_run(exec, win.height(), [&](long y0, long y1) {
        for (long yy = y0; yy < y1; ++yy)
            for (int xx = 0; xx < w; ++xx) {
                const std::size_t i = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
                if (!(known(i) > 0.0f)) continue;
                float& r = a.radius[i];
                const int x = win.x0 + xx, y = win.y0 + int(yy);
                if (!std::isfinite(r)) {
                    std::string depth;
                    if (zc >= 0 && img.plane(zc)) depth = " (depth Z = " + num(img.plane(zc)[i]) + ")";
                    return Status::error(where + ": the blur field is " + num(r) + " at covered pixel " + pixel_str(x, y) +
                                         depth + "; expected a finite radius");
                }
                if (r < 0.0f) r = 0.0f;
                if (double(r) > settings.max_radius)
                    return Status::error(where + ": blur radius " + num(r) + " px at pixel " + pixel_str(x, y) +
                                         " exceeds the diffusion max_radius " + num(settings.max_radius) +
                                         " px (clamp the blur field with \"max_radius\")");
                row_rmax[std::size_t(yy)] = std::max(row_rmax[std::size_t(yy)], double(r));
            }
        return Status::ok();
    }, 16);
    if (!st) return st;
    double rmax = 0.0;
    for (double r : row_rmax) rmax = std::max(rmax, r);
    a.max_radius = rmax;
    return a;
}

}  // namespace gdof::defocus_detail
