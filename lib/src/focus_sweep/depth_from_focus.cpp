// depth_from_focus (focus_sweep.h): per frame the energy of the Laplacian of
// its luminance, averaged over a window; per pixel the frame where it peaks,
// refined between frames; holes where no frame stands out, filled by the
// plate's guided fill (plate.h); the all-in-focus colour and the depth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "focus_sweep/sweep_planes.h"
#include "gdof/focus_sweep.h"
#include "gdof/plate.h"

namespace gdof {

using namespace sweep_detail;

std::string DepthFromFocusStats::report() const {
    char b[160];
    std::snprintf(b, sizeof b,
                  "depth from focus: %zu pixels, %zu holes (%.1f%%: no frame standing out, or %zu outliers against their "
                  "neighbours), filled",
                  pixels, holes, pixels ? 100.0 * double(holes) / double(pixels) : 0.0, outliers);
    return b;
}

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Below this focus measure a pixel has no texture at all, whatever its ratio:
// a Laplacian of 1e-3 in sqrt(luminance), under an 8-bit step (float
// rounding in a resampled flat area gives ratios too).
constexpr float kTextureFloor = 1e-6f;
constexpr int kOutlierRadius = 3;       // a 7x7 window
constexpr int kOutlierWideRadius = 10;  // 21x21, for sparse pixels
// A peak under this fraction of the largest peak within kContextRadius is
// noise beside texture, not texture: a flat area next to strong edges (a
// checker's dark squares) whose noise happens to peak in one frame (a ray
// tracer's noise grows with defocus, so it peaks in the blurriest frame).
constexpr float kContextFraction = 0.05f;
constexpr int kContextRadius = 16;      // a 33x33 window
constexpr float kOutlierSteps = 2.0f;   // frames from the window's median

// The focus measure of one frame: the squared 4-neighbour Laplacian of its
// luminance plane, averaged over the window.
Plane focus_measure(const Plane& l, int radius, const Exec& exec) {
    Plane e{l.w, l.h, std::vector<float>(l.v.size())};
    parallel_for(exec, l.h, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < l.w; ++x) {
                const int yi = int(y);
                const float c = l.at(x, yi);
                const float lap = 4.0f * c - l.at(std::max(x - 1, 0), yi) - l.at(std::min(x + 1, l.w - 1), yi) -
                                  l.at(x, std::max(yi - 1, 0)) - l.at(x, std::min(yi + 1, l.h - 1));
                e.at(x, yi) = lap * lap;
            }
    });
    box_mean(e, radius, exec);
    return e;
}

// Pixels whose index is more than `max_steps` frames from the median of
// the measured indices around them become holes: a lone peak in a flat area
// (a compression block, a reflection, blur spreading an edge's curvature into
// a flat area in the blurriest frame) would otherwise seed the fill with a
// wrong depth. The window is (2 r + 1)^2 with at least a quarter of it
// measured, else (2 r_wide + 1)^2 with as many (a sparse pixel is judged by
// its wider surroundings), else the pixel stays. Returns how many.
std::size_t reject_outliers(std::vector<float>& index, int W, int H, int r, int r_wide, float max_steps, const Exec& exec) {
    std::vector<float> out = index;
    const std::size_t need = std::size_t((2 * r + 1) * (2 * r + 1) / 4);
    parallel_for(exec, H, [&](long y0, long y1) {
        std::vector<float> v;
        auto gather = [&](int x, int y, int radius) {
            v.clear();
            for (int yy = std::max(0, y - radius); yy <= std::min(H - 1, y + radius); ++yy)
                for (int xx = std::max(0, x - radius); xx <= std::min(W - 1, x + radius); ++xx) {
                    const float q = index[std::size_t(yy) * std::size_t(W) + std::size_t(xx)];
                    if (!std::isnan(q)) v.push_back(q);
                }
        };
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const float c = index[std::size_t(y) * std::size_t(W) + std::size_t(x)];
                if (std::isnan(c)) continue;
                gather(x, int(y), r);
                if (v.size() < need) gather(x, int(y), r_wide);
                if (v.size() < need) continue;
                std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
                if (std::abs(c - v[v.size() / 2]) > max_steps) out[std::size_t(y) * std::size_t(W) + std::size_t(x)] = kNaN;
            }
    });
    std::size_t n = 0;
    for (std::size_t i = 0; i < index.size(); ++i) n += std::isnan(out[i]) && !std::isnan(index[i]) ? 1 : 0;
    index.swap(out);
    return n;
}

// The largest value within a (2 r + 1)^2 window (separable).
std::vector<float> max_filter(const std::vector<float>& v, int W, int H, int r, const Exec& exec) {
    std::vector<float> tmp(v.size()), out(v.size());
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                float m = 0;
                for (int xx = std::max(0, x - r); xx <= std::min(W - 1, x + r); ++xx)
                    m = std::max(m, v[std::size_t(y) * std::size_t(W) + std::size_t(xx)]);
                tmp[std::size_t(y) * std::size_t(W) + std::size_t(x)] = m;
            }
    });
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                float m = 0;
                for (int yy = std::max(0, int(y) - r); yy <= std::min(H - 1, int(y) + r); ++yy)
                    m = std::max(m, tmp[std::size_t(yy) * std::size_t(W) + std::size_t(x)]);
                out[std::size_t(y) * std::size_t(W) + std::size_t(x)] = m;
            }
    });
    return out;
}

Status check(const std::vector<Image>& frames, const std::vector<double>& depths, const DepthFromFocusOptions& o) {
    if (frames.size() < 2)
        return Status::error("depth from focus: a sweep needs at least 2 frames, got " + std::to_string(frames.size()),
                             StatusCode::InvalidArgument);
    for (std::size_t i = 1; i < frames.size(); ++i)
        if (frames[i].data_window() != frames[0].data_window())
            return Status::error("depth from focus: frame " + std::to_string(i + 1) + " is " +
                                     to_string(frames[i].data_window()) + ", frame 1 " + to_string(frames[0].data_window()),
                                 StatusCode::InvalidArgument);
    if (!depths.empty()) {
        if (depths.size() != frames.size())
            return Status::error("depth from focus: " + std::to_string(depths.size()) + " focus distances for " +
                                     std::to_string(frames.size()) + " frames",
                                 StatusCode::InvalidArgument, "focus_distance");
        const bool up = depths[1] > depths[0];
        for (std::size_t i = 0; i < depths.size(); ++i) {
            if (!(depths[i] > 0) || !std::isfinite(depths[i]))
                return Status::error("depth from focus: frame " + std::to_string(i + 1) +
                                         "'s focus distance must be finite and > 0",
                                     StatusCode::InvalidArgument, "focus_distance");
            if (i > 0 && (up ? !(depths[i] > depths[i - 1]) : !(depths[i] < depths[i - 1])))
                return Status::error("depth from focus: focus distances must rise or fall strictly with the frames (frame " +
                                         std::to_string(i + 1) + ")",
                                     StatusCode::InvalidArgument, "focus_distance");
        }
    }
    if (o.window_radius < 1 || o.window_radius > 64)
        return Status::error("depth from focus: window_radius must be in [1, 64], got " + std::to_string(o.window_radius),
                             StatusCode::InvalidArgument, "window_radius");
    if (!(o.min_peak_ratio >= 1.0) || !(o.min_peak_ratio < 1e6))
        return Status::error("depth from focus: min_peak_ratio must be >= 1", StatusCode::InvalidArgument, "min_peak_ratio");
    return Status::ok();
}

}  // namespace

Result<DepthFromFocus> depth_from_focus(const std::vector<Image>& frames, const std::vector<double>& focus_depths,
                                        const DepthFromFocusOptions& options, const Exec& exec) {
    if (Status st = check(frames, focus_depths, options); !st) return st;
    const std::size_t n = frames.size();
    const int W = frames[0].width(), H = frames[0].height();
    const std::size_t np = frames[0].npixels();
    std::vector<Plane> measure;
    measure.reserve(n);
    std::vector<const float*> rgb(n * 3, nullptr);
    for (std::size_t k = 0; k < n; ++k) {
        auto l = luminance_plane(frames[k], "depth from focus: frame " + std::to_string(k + 1), exec);
        if (!l) return l.status();
        measure.push_back(focus_measure(l.value(), options.window_radius, exec));
        const std::array<const float*, 3> c = colour_planes(frames[k]);  // luminance_plane checked them
        std::copy(c.begin(), c.end(), rgb.begin() + std::ptrdiff_t(k * 3));
        if (exec.is_cancelled()) return Status::cancelled("depth from focus");
        exec.report(0.7 * double(k + 1) / double(n));
    }

    // Per pixel: the peak, refined by a parabola through the logarithms of
    // the measures at it and its two neighbours (a Gaussian fit), and its
    // ratio to the median.
    std::vector<float> index(np), confidence(np), peaks(np);
    parallel_for(exec, H, [&](long y0, long y1) {
        std::vector<float> v(n);
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                std::size_t best = 0;
                for (std::size_t k = 0; k < n; ++k) {
                    v[k] = measure[k].v[i];
                    if (v[k] > v[best]) best = k;
                }
                const float peak = v[best];
                peaks[i] = peak;
                // The median (with two frames, the other frame).
                const std::size_t mid = n == 2 ? 0 : n / 2;
                std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
                const float median = v[mid];
                const float ratio = median > 0 ? peak / median : (peak > 0 ? 1e6f : 1.0f);
                // Three frames around the peak (moved inwards at the sweep's
                // ends, where the vertex may still lie up to half a step in).
                double frac = double(best);
                if (n >= 3) {
                    const std::size_t c = std::clamp<std::size_t>(best, 1, n - 2);
                    const double tiny = 1e-12;
                    const double l0 = std::log(double(measure[c - 1].v[i]) + tiny);
                    const double l1 = std::log(double(measure[c].v[i]) + tiny);
                    const double l2 = std::log(double(measure[c + 1].v[i]) + tiny);
                    const double den = l0 - 2 * l1 + l2;
                    if (den < 0) {
                        const double vertex = double(c) + 0.5 * (l0 - l2) / den;
                        frac = std::clamp(vertex, std::max(0.0, double(best) - 0.5), std::min(double(n - 1), double(best) + 0.5));
                    }
                }
                const bool stands_out = peak > kTextureFloor && ratio >= float(options.min_peak_ratio);
                // Depth one above the index: the plate fill wants positive depths.
                index[i] = stands_out ? float(frac + 1.0) : kNaN;
                confidence[i] = stands_out ? ratio : 0.0f;
            }
    });
    if (exec.is_cancelled()) return Status::cancelled("depth from focus");
    measure.clear();
    {
        const std::vector<float> context = max_filter(peaks, W, H, kContextRadius, exec);
        for (std::size_t i = 0; i < np; ++i)
            if (peaks[i] < kContextFraction * context[i]) index[i] = kNaN;
    }

    DepthFromFocus out;
    out.stats.pixels = np;
    out.stats.outliers = reject_outliers(index, W, H, kOutlierRadius, kOutlierWideRadius, kOutlierSteps, exec);
    if (exec.is_cancelled()) return Status::cancelled("depth from focus");
    for (std::size_t i = 0; i < np; ++i)
        if (std::isnan(index[i])) {
            ++out.stats.holes;
            confidence[i] = 0.0f;
        }
    if (out.stats.holes == np)
        return Status::error("depth from focus: no pixel is sharper in one frame than in the others (a sweep with no "
                             "texture, or frames that are all alike)",
                             StatusCode::InvalidArgument);

    // Holes filled from their surroundings, guided by the middle frame's colour.
    const Image& mid = frames[(n - 1) / 2];
    Image guide = Image::with_channels({"R", "G", "B", "Z"}, mid.data_window());
    guide.set_display_window(mid.display_window());
    for (int c = 0; c < 3; ++c) std::copy(rgb[((n - 1) / 2) * 3 + std::size_t(c)], rgb[((n - 1) / 2) * 3 + std::size_t(c)] + np, guide.plane(c));
    std::copy(index.begin(), index.end(), guide.plane(3));
    DepthCleanupOptions clean;
    clean.remove_speckles = false;  // index steps are not depth ratios
    clean.mixed_pixels = false;
    clean.smooth_noise = false;
    auto filled = prepare_plate_depth(guide, 3, DepthDecode{}, clean, exec);
    if (!filled) return Status::error("depth from focus: " + filled.message(), filled.status().code());
    const std::vector<float>& fidx = filled.value().depth;

    Image& plate = out.plate;
    plate = Image::with_channels({"R", "G", "B", "A", "Z", "focus.index", "focus.confidence"}, mid.data_window());
    plate.set_display_window(mid.display_window());
    plate.metadata = mid.metadata;
    float* o[7];
    for (int c = 0; c < 7; ++c) o[c] = plate.plane(c);
    parallel_for(exec, H, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                const double f = std::clamp(double(fidx[i]) - 1.0, 0.0, double(n - 1));
                const std::size_t k0 = std::min(std::size_t(f), n - 2);
                const double t = f - double(k0);
                for (int c = 0; c < 3; ++c)
                    o[c][i] = float((1 - t) * rgb[k0 * 3 + std::size_t(c)][i] + t * rgb[(k0 + 1) * 3 + std::size_t(c)][i]);
                o[3][i] = 1.0f;
                if (focus_depths.empty())
                    o[4][i] = float(f + 1.0);
                else
                    o[4][i] = float(1.0 / ((1 - t) / focus_depths[k0] + t / focus_depths[k0 + 1]));
                o[5][i] = float(f + 1.0);
                o[6][i] = confidence[i];
            }
    });
    if (exec.is_cancelled()) return Status::cancelled("depth from focus");
    exec.report(1.0);
    return out;
}

}  // namespace gdof
