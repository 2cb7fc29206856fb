// Parsing a layer split and choosing depth slice boundaries (Auto
// clustering in log depth, Count in equal 1/depth extents).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "layers/layers_internal.h"

namespace gdof {

namespace {

// Strict decimal integer (no sign other than '-', no trailing characters).
bool parse_int(const std::string& s, int& out) {
    if (s.empty()) return false;
    const char* b = s.data();
    const char* e = s.data() + s.size();
    auto [p, ec] = std::from_chars(b, e, out);
    return ec == std::errc() && p == e;
}

}  // namespace

Result<LayerSplit> parse_layer_split(const std::string& text) {
    constexpr int kMaxCount = 1024;
    LayerSplit s;
    if (text == "auto") {
        s.mode = LayerSplit::Mode::Auto;
        return s;
    }
    if (text.rfind("auto:", 0) == 0) {
        s.mode = LayerSplit::Mode::Auto;
        std::stringstream ss(text.substr(5));
        for (std::string opt; std::getline(ss, opt, ':');) {
            int n = 0;
            if (opt == "gaps") {
                s.blur_cuts = LayerSplit::BlurCuts::Off;
            } else if (opt == "blur") {
                s.blur_cuts = LayerSplit::BlurCuts::On;
            } else if (opt.rfind("blur=", 0) == 0) {
                const std::string v = opt.substr(5);
                char* end = nullptr;
                const double step = std::strtod(v.c_str(), &end);
                if (v.empty() || *end != '\0' || !(step > 0.0) || !(step <= 1e6))
                    return Status::error("layer split '" + text + "': the blur step after 'blur=' must be a number of px in (0, 1e6], got '" + v + "'");
                s.blur_cuts = LayerSplit::BlurCuts::On;
                s.blur_step = step;
            } else if (parse_int(opt, n)) {
                if (n < 1 || n > kMaxCount)
                    return Status::error("layer split '" + text + "': the most layers after 'auto:' must be in 1.." +
                                         std::to_string(kMaxCount) + ", got '" + opt + "'");
                s.max_layers = n;
            } else {
                return Status::error("layer split '" + text + "': unknown auto option '" + opt +
                                     "' (expected the most layers, 'blur', 'blur=STEP' or 'gaps')");
            }
        }
        if (text.back() == ':') return Status::error("layer split '" + text + "': empty option after ':'");
        return s;
    }
    if (text == "id") {
        s.mode = LayerSplit::Mode::ById;
        s.id_channel = "id";
        return s;
    }
    if (text.rfind("id:", 0) == 0) {
        const std::string ch = text.substr(3);
        if (ch.empty()) return Status::error("layer split '" + text + "': no channel name after 'id:'");
        s.mode = LayerSplit::Mode::ById;
        s.id_channel = ch;
        return s;
    }
    int n = 0;
    if (parse_int(text, n)) {
        if (n < 1 || n > kMaxCount)
            return Status::error("layer split '" + text + "': the layer count must be in 1.." + std::to_string(kMaxCount));
        s.mode = LayerSplit::Mode::Count;
        s.count = n;
        return s;
    }
    return Status::error("layer split '" + text + "': expected 'auto', 'auto:MAX', a layer count N, 'id' or 'id:CHANNEL'");
}

namespace layers_detail {

std::string depth_range_name(double near, double far) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "depth %.4g-%.4g", near, far);
    return buf;
}

double median_finite(std::vector<float> values) {
    values.erase(std::remove_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); }), values.end());
    if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(mid), values.end());
    return values[mid];
}

namespace {

DepthSlices count_slices(double zmin, double zmax, bool any_inf, int count) {
    DepthSlices s;
    const int n = std::max(1, count);
    const double inv_near = 1.0 / zmin;
    const double inv_far = any_inf ? 0.0 : 1.0 / zmax;
    const double step = (inv_near - inv_far) / n;
    auto depth_at = [&](int i) {  // boundary i in 0..n (0 = nearest)
        if (i == 0) return zmin;
        if (i == n) return any_inf ? kInf : zmax;
        const double inv = inv_near - i * step;
        return inv > 0 ? 1.0 / inv : kInf;
    };
    for (int i = 1; i < n; ++i) s.bounds.push_back(depth_at(i));
    for (int k = 0; k < n; ++k) {
        s.lo.push_back(depth_at(k));
        s.hi.push_back(depth_at(k + 1));
    }
    return s;
}

// Gap splits (depths), ascending: at most max_layers - 1 of the widest gaps.
std::vector<double> gap_splits(const LogHistogram& h, std::size_t nsamples, int max_layers) {
    const std::size_t noise = std::size_t(double(nsamples) * kAutoNoiseFraction);
    struct Gap {
        double width, split;
    };
    std::vector<Gap> gaps;
    long b = 0;
    while (b < h.nbins) {
        if (h.count[std::size_t(b)] > noise) {
            ++b;
            continue;
        }
        const long start = b;
        while (b < h.nbins && h.count[std::size_t(b)] <= noise) ++b;
        const long end = b;  // run [start, end)
        if (start == 0 || end == h.nbins) continue;
        const double width = double(end - start) * h.binw;
        if (width < kAutoMinGap) continue;
        gaps.push_back({width, std::exp(h.vmin + 0.5 * double(start + end) * h.binw)});
    }
    const std::size_t keep = std::size_t(std::max(0, max_layers - 1));
    if (gaps.size() > keep) {
        std::stable_sort(gaps.begin(), gaps.end(), [](const Gap& a, const Gap& c) { return a.width > c.width; });
        gaps.resize(keep);
    }
    std::vector<double> splits;
    for (const Gap& g : gaps) splits.push_back(g.split);
    std::sort(splits.begin(), splits.end());
    return splits;
}

// Blur cuts inside the clusters between `gaps`: walking the bins front to
// back, a cut (at a bin's near edge) whenever the bin-mean radii since the
// last cut or gap would span more than `step`.
std::vector<double> blur_cuts(const LogHistogram& h, const std::vector<double>& gaps, double step) {
    std::vector<double> cuts;
    std::size_t next_gap = 0;
    bool open = false;
    double lo = 0, hi = 0;
    for (long b = 0; b < h.nbins; ++b) {
        const double centre = std::exp(h.vmin + (double(b) + 0.5) * h.binw);
        while (next_gap < gaps.size() && centre >= gaps[next_gap]) {
            ++next_gap;
            open = false;  // a new cluster
        }
        if (h.rcount[std::size_t(b)] == 0) continue;
        const double m = h.rsum[std::size_t(b)] / double(h.rcount[std::size_t(b)]);
        if (open && std::max(hi, m) - std::min(lo, m) > step) {
            cuts.push_back(h.edge_depth(b));
            open = false;
        }
        if (!open) {
            lo = hi = m;
            open = true;
        }
        lo = std::min(lo, m);
        hi = std::max(hi, m);
    }
    return cuts;
}

DepthSlices auto_slices(const std::vector<double>& logs, const std::vector<float>& radii, double zmin, double zmax,
                        bool any_inf, const LayerSplit& split, const SilhouetteGrid* grid, const Exec& exec) {
    DepthSlices single;
    single.lo = {zmin};
    single.hi = {any_inf ? kInf : zmax};
    const std::size_t n = logs.size();
    const bool cut_by_blur = !radii.empty() && split.blur_cuts != LayerSplit::BlurCuts::Off;
    if (n == 0 || split.max_layers <= 1) return single;
    LogHistogram h;
    h.vmin = std::log(zmin);
    const double range = std::log(zmax) - h.vmin;
    const bool find_gaps = range >= kAutoMinGap;
    if (!find_gaps && !(cut_by_blur && range > 0.0)) return single;
    h.nbins = std::clamp(long(std::ceil(range / (kAutoMinGap / 4.0))), 16L, 65536L);
    h.binw = range / double(h.nbins);
    h.count.assign(std::size_t(h.nbins), 0);
    h.rsum.assign(std::size_t(h.nbins), 0.0);
    h.rcount.assign(std::size_t(h.nbins), 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t b = std::size_t(h.bin_of(logs[i]));
        ++h.count[b];
        if (cut_by_blur && std::isfinite(radii[i])) {
            h.rsum[b] += double(radii[i]);
            ++h.rcount[b];
        }
    }
    std::vector<double> bounds = find_gaps ? gap_splits(h, n, split.max_layers) : std::vector<double>{};
    if (cut_by_blur) {
        double rmax = 0.0;
        for (long b = 0; b < h.nbins; ++b)
            if (h.rcount[std::size_t(b)]) rmax = std::max(rmax, h.rsum[std::size_t(b)] / double(h.rcount[std::size_t(b)]));
        const double per = grid ? kAutoBlurLayersAtSilhouettes : kAutoBlurLayers;
        double step = split.blur_step > 0.0 ? split.blur_step : std::max(kAutoBlurStepPx, rmax / per);
        std::optional<SilhouetteScan> scan;
        if (grid) scan = scan_silhouettes(h, *grid, step, rmax, exec);
        std::vector<double> cuts;
        for (int tries = 0; tries < 200; ++tries, step *= 1.25) {
            cuts = scan ? silhouette_cuts(h, *scan, bounds, step, zmax) : blur_cuts(h, bounds, step);
            if (bounds.size() + cuts.size() + 1 <= std::size_t(split.max_layers)) break;
            cuts.clear();
        }
        bounds.insert(bounds.end(), cuts.begin(), cuts.end());
        std::sort(bounds.begin(), bounds.end());
    }
    DepthSlices s;
    s.bounds = std::move(bounds);
    // Nominal intervals: the sample range of each slice.
    const int k = s.count();
    s.lo.assign(std::size_t(k), kInf);
    s.hi.assign(std::size_t(k), -kInf);
    for (double v : logs) {
        const double d = std::exp(v);
        const int i = s.slice_of(d);
        s.lo[std::size_t(i)] = std::min(s.lo[std::size_t(i)], d);
        s.hi[std::size_t(i)] = std::max(s.hi[std::size_t(i)], d);
    }
    s.lo.front() = std::min(s.lo.front(), zmin);
    if (any_inf) s.hi.back() = kInf;
    return s;
}

}  // namespace

DepthSlices choose_slices(std::span<const float> depths, const LayerSplit& split, std::span<const float> radius,
                          const Exec& exec, const SilhouetteGrid* grid) {
    const bool is_auto = split.mode == LayerSplit::Mode::Auto;
    const bool with_radius = is_auto && radius.size() == depths.size() && !depths.empty();
    // Blocks in parallel: each its range, whether it saw +inf and how many
    // positive finite depths it holds; then (auto) their logs and radii
    // written at each block's offset, in the samples' order.
    constexpr std::size_t kBlock = 1 << 16;
    const std::size_t nb = (depths.size() + kBlock - 1) / kBlock;
    struct Block {
        double zmin = kInf, zmax = 0.0;
        bool any_inf = false;
        std::size_t finite = 0;
    };
    std::vector<Block> blocks(nb);
    auto finite_positive = [](float z) { return z > 0.0f && std::isfinite(z); };
    parallel_for(exec, long(nb), [&](long b0, long b1) {
        for (long b = b0; b < b1; ++b) {
            Block& k = blocks[std::size_t(b)];
            for (std::size_t i = std::size_t(b) * kBlock; i < std::min(depths.size(), std::size_t(b + 1) * kBlock); ++i) {
                const float z = depths[i];
                if (z == float(kInf)) k.any_inf = true;
                if (!finite_positive(z)) continue;
                k.zmin = std::min(k.zmin, double(z));
                k.zmax = std::max(k.zmax, double(z));
                ++k.finite;
            }
        }
    });
    double zmin = kInf, zmax = 0.0;
    bool any_inf = false;
    std::size_t total = 0;
    std::vector<std::size_t> offset(nb);
    for (std::size_t b = 0; b < nb; ++b) {
        zmin = std::min(zmin, blocks[b].zmin);
        zmax = std::max(zmax, blocks[b].zmax);
        any_inf = any_inf || blocks[b].any_inf;
        offset[b] = total;
        total += blocks[b].finite;
    }
    std::vector<double> logs;
    std::vector<float> radii;
    if (is_auto) {
        logs.resize(total);
        if (with_radius) radii.resize(total);
        parallel_for(exec, long(nb), [&](long b0, long b1) {
            for (long b = b0; b < b1; ++b) {
                std::size_t o = offset[std::size_t(b)];
                for (std::size_t i = std::size_t(b) * kBlock; i < std::min(depths.size(), std::size_t(b + 1) * kBlock); ++i) {
                    if (!finite_positive(depths[i])) continue;
                    logs[o] = std::log(double(depths[i]));
                    if (with_radius) radii[o] = radius[i];
                    ++o;
                }
            }
        });
    }
    if (zmin == kInf) {  // no positive finite depth: one slice (Count: all in the first)
        DepthSlices s;
        const int n = split.mode == LayerSplit::Mode::Count ? std::max(1, split.count) : 1;
        for (int i = 1; i < n; ++i) s.bounds.push_back(kInf);
        s.lo.assign(std::size_t(n), any_inf ? kInf : 0.0);
        s.hi.assign(std::size_t(n), any_inf ? kInf : 0.0);
        return s;
    }
    if (split.mode == LayerSplit::Mode::Count) return count_slices(zmin, zmax, any_inf, split.count);
    return auto_slices(logs, radii, zmin, zmax, any_inf, split, with_radius ? grid : nullptr, exec);
}

}  // namespace layers_detail

}  // namespace gdof
