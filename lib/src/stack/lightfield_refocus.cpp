// Shift-and-add refocusing of a light field (see gdof/lightfield.h for the
// conventions). The shift of a view is constant over the image, so the
// interpolation weights are computed once per view; each output row gathers
// its views row-major with a separable filter (vertical taps into a row
// buffer, then horizontal taps), edges clamped.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "gdof/lightfield.h"

namespace gdof {

namespace {

// Taps of a 1D resampling at position p + shift: samples floor(p + shift) +
// first + k, k < n, weighted w[k].
struct Taps {
    int n = 1;
    long first = 0;
    float w[4] = {1, 0, 0, 0};
};

Taps make_taps(double shift, LightFieldFilter filter, long extent) {
    Taps t;
    // A shift past the image (|d_f * du| > extent, up to 1e300 or +-inf)
    // puts every tap beyond the edge, where samples clamp: the sample is the
    // edge pixel. Clamping the shift to an integer just past the edge gives
    // exactly that and keeps long(i0) and x + first from overflowing.
    const double lim = double(extent) + 4.0;
    if (!(std::fabs(shift) <= lim)) shift = shift > 0 ? lim : -lim;
    const double i0 = std::floor(shift);
    const double f = shift - i0;
    if (f == 0) {  // integer shift: an exact copy
        t.n = 1;
        t.first = long(i0);
        t.w[0] = 1.0f;
        return t;
    }
    if (filter == LightFieldFilter::Bilinear) {
        t.n = 2;
        t.first = long(i0);
        t.w[0] = float(1 - f);
        t.w[1] = float(f);
        return t;
    }
    // Catmull-Rom (cubic convolution, a = -0.5): weights of samples i0-1 .. i0+2.
    const double f2 = f * f, f3 = f2 * f;
    t.n = 4;
    t.first = long(i0) - 1;
    t.w[0] = float(0.5 * (-f3 + 2 * f2 - f));
    t.w[1] = float(0.5 * (3 * f3 - 5 * f2 + 2));
    t.w[2] = float(0.5 * (-3 * f3 + 4 * f2 + f));
    t.w[3] = float(0.5 * (f3 - f2));
    return t;
}

struct ViewPlan {
    const Image* image = nullptr;
    Taps tx, ty;
};

inline long clampl(long v, long lo, long hi) { return v < lo ? lo : (v > hi ? hi : v); }

// acc[x] += sum_k tx.w[k] * row[clamp(x + tx.first + k)] over x in [0, w).
void add_horizontal(float* acc, const float* row, long w, const Taps& tx) {
    const long last = w - 1;
    // Interior: every tap inside the row.
    const long lo = std::clamp(-tx.first, 0L, w);
    const long hi = std::clamp(w - (tx.first + tx.n - 1), lo, w);
    auto edge = [&](long x0, long x1) {
        for (long x = x0; x < x1; ++x) {
            float s = 0;
            for (int k = 0; k < tx.n; ++k) s += tx.w[k] * row[clampl(x + tx.first + k, 0, last)];
            acc[x] += s;
        }
    };
    edge(0, lo);
    const float* r = row + tx.first;
    if (tx.n == 1) {
        for (long x = lo; x < hi; ++x) acc[x] += r[x];
    } else if (tx.n == 2) {
        const float w0 = tx.w[0], w1 = tx.w[1];
        for (long x = lo; x < hi; ++x) acc[x] += w0 * r[x] + w1 * r[x + 1];
    } else {
        const float w0 = tx.w[0], w1 = tx.w[1], w2 = tx.w[2], w3 = tx.w[3];
        for (long x = lo; x < hi; ++x) acc[x] += ((w0 * r[x] + w1 * r[x + 1]) + w2 * r[x + 2]) + w3 * r[x + 3];
    }
    edge(hi, w);
}

}  // namespace

Result<Image> refocus(const LightField& lf, const RefocusOptions& s, const Exec& exec) {
    if (auto st = lf.validate(); !st) return st;
    if (!std::isfinite(s.focus_disparity))
        return Status::error("refocus: focus_disparity must be finite, got " + std::to_string(s.focus_disparity));
    if (!(s.aperture_radius >= 0) || !std::isfinite(s.aperture_radius))
        return Status::error("refocus: aperture_radius must be >= 0 (view steps), got " +
                             std::to_string(s.aperture_radius));

    const Image& central = lf.central();
    std::vector<ViewPlan> plan;
    for (int row = 0; row < lf.rows; ++row)
        for (int col = 0; col < lf.cols; ++col) {
            const double du = col - lf.center_col, dv = row - lf.center_row;
            if (du * du + dv * dv > s.aperture_radius * s.aperture_radius + 1e-9) continue;
            ViewPlan p;
            p.image = &lf.view(row, col);
            p.tx = make_taps(-s.focus_disparity * du, s.filter, central.width());  // sample at x - d_f * du
            p.ty = make_taps(-s.focus_disparity * dv, s.filter, central.height());
            plan.push_back(p);
        }
    // The central view is always inside (radius >= 0), so the plan is never empty.

    std::vector<ChannelSpec> specs;
    for (const ChannelSpec& c : central.channels()) specs.push_back({c.name, PixelType::Float});
    Image out(specs, central.data_window(), central.display_window());
    out.metadata = central.metadata;
    out.metadata.set_float("gdof:focusDisparity", s.focus_disparity);
    out.metadata.set_float("gdof:apertureRadiusViews", s.aperture_radius);
    out.metadata.set_int("gdof:apertureViews", static_cast<long long>(plan.size()));

    const long w = central.width(), h = central.height();
    const int nch = central.nchannels();
    const float n_views = float(plan.size());
    std::atomic<long> rows_done{0};
    const bool ok = parallel_for(
        exec, h,
        [&](long y0, long y1) {
            std::vector<float> acc(static_cast<std::size_t>(w)), tmp(static_cast<std::size_t>(w));
            for (long y = y0; y < y1; ++y) {
                for (int c = 0; c < nch; ++c) {
                    std::fill(acc.begin(), acc.end(), 0.0f);
                    for (const ViewPlan& p : plan) {
                        const float* plane = p.image->plane(c);
                        const float* src;
                        if (p.ty.n == 1) {
                            src = plane + clampl(y + p.ty.first, 0, h - 1) * w;
                        } else {
                            const float* r[4];
                            for (int k = 0; k < p.ty.n; ++k) r[k] = plane + clampl(y + p.ty.first + k, 0, h - 1) * w;
                            if (p.ty.n == 2) {
                                const float w0 = p.ty.w[0], w1 = p.ty.w[1];
                                for (long x = 0; x < w; ++x) tmp[std::size_t(x)] = w0 * r[0][x] + w1 * r[1][x];
                            } else {
                                const float w0 = p.ty.w[0], w1 = p.ty.w[1], w2 = p.ty.w[2], w3 = p.ty.w[3];
                                for (long x = 0; x < w; ++x)
                                    tmp[std::size_t(x)] =
                                        ((w0 * r[0][x] + w1 * r[1][x]) + w2 * r[2][x]) + w3 * r[3][x];
                            }
                            src = tmp.data();
                        }
                        add_horizontal(acc.data(), src, w, p.tx);
                    }
                    float* dst = out.plane(c) + y * w;
                    if (plan.size() == 1)
                        std::copy(acc.begin(), acc.end(), dst);
                    else
                        for (long x = 0; x < w; ++x) dst[x] = acc[std::size_t(x)] / n_views;
                }
            }
            exec.report(double(rows_done += (y1 - y0)) / double(h));
        },
        8);
    if (!ok) return Status::error("refocus: cancelled", StatusCode::Cancelled);
    return out;
}

}  // namespace gdof
