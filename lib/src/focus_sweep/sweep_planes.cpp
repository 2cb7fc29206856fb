// Planes for the sweep (sweep_planes.h).
#include "focus_sweep/sweep_planes.h"

#include <algorithm>
#include <cmath>

namespace gdof::sweep_detail {

std::array<const float*, 3> colour_planes(const Image& image) {
    const RgbaIndices ix = find_rgba(image);
    if (ix.r >= 0 && ix.g >= 0 && ix.b >= 0 && image.plane(ix.r) && image.plane(ix.g) && image.plane(ix.b))
        return {image.plane(ix.r), image.plane(ix.g), image.plane(ix.b)};
    for (int c = 0; c < image.nchannels(); ++c)
        if (const float* grey = image.plane(c)) return {grey, grey, grey};
    return {nullptr, nullptr, nullptr};
}

Result<Plane> luminance_plane(const Image& image, const std::string& what, const Exec& exec) {
    // Not a structured binding: clang 14 cannot capture one in the lambda below.
    const std::array<const float*, 3> rgb = colour_planes(image);
    const float *r = rgb[0], *g = rgb[1], *b = rgb[2];
    if (!r) return Status::error(what + ": no float colour channel", StatusCode::InvalidArgument);
    Plane p{image.width(), image.height(), std::vector<float>(image.npixels())};
    std::vector<unsigned char> bad_row(std::size_t(p.h), 0);
    parallel_for(exec, p.h, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            const std::size_t o = std::size_t(y) * std::size_t(p.w);
            for (int x = 0; x < p.w; ++x) {
                const float l = 0.2126f * r[o + x] + 0.7152f * g[o + x] + 0.0722f * b[o + x];
                if (!std::isfinite(l)) bad_row[std::size_t(y)] = 1;
                p.v[o + x] = std::isfinite(l) ? std::sqrt(std::clamp(l, 0.0f, 16.0f)) : 0.0f;
            }
        }
    });
    if (exec.is_cancelled()) return Status::cancelled(what);
    for (int y = 0; y < p.h; ++y)
        if (bad_row[std::size_t(y)])
            for (int x = 0; x < p.w; ++x) {
                const std::size_t o = std::size_t(y) * std::size_t(p.w) + std::size_t(x);
                if (!std::isfinite(r[o]) || !std::isfinite(g[o]) || !std::isfinite(b[o]))
                    return Status::error(what + ": non-finite colour at pixel (" +
                                             std::to_string(x + image.data_window().x0) + ", " +
                                             std::to_string(y + image.data_window().y0) + ")",
                                         StatusCode::InvalidArgument);
            }
    return p;
}

Plane half_size(const Plane& p, const Exec& exec) {
    Plane q{std::max(1, p.w / 2), std::max(1, p.h / 2), {}};
    q.v.resize(std::size_t(q.w) * std::size_t(q.h));
    parallel_for(exec, q.h, [&](long yb, long ye) {
        for (int y = int(yb); y < int(ye); ++y)
            for (int x = 0; x < q.w; ++x) {
                const int x0 = std::min(2 * x, p.w - 1), x1 = std::min(2 * x + 1, p.w - 1);
                const int y0 = std::min(2 * y, p.h - 1), y1 = std::min(2 * y + 1, p.h - 1);
                q.at(x, y) = 0.25f * (p.at(x0, y0) + p.at(x1, y0) + p.at(x0, y1) + p.at(x1, y1));
            }
    });
    return q;
}

void central_differences(const Plane& p, Plane& gx, Plane& gy, const Exec& exec) {
    gx = Plane{p.w, p.h, std::vector<float>(p.v.size())};
    gy = gx;
    parallel_for(exec, p.h, [&](long yb, long ye) {
        for (int y = int(yb); y < int(ye); ++y)
            for (int x = 0; x < p.w; ++x) {
                gx.at(x, y) = 0.5f * (p.at(std::min(x + 1, p.w - 1), y) - p.at(std::max(x - 1, 0), y));
                gy.at(x, y) = 0.5f * (p.at(x, std::min(y + 1, p.h - 1)) - p.at(x, std::max(y - 1, 0)));
            }
    });
}

namespace {

// v clamped to [0, hi]; NaN to 0 (a NaN position must not reach an int conversion).
inline double clamp_position(double v, double hi) { return v >= 0.0 ? (v <= hi ? v : hi) : 0.0; }

}  // namespace

float bilinear(const Plane& p, double x, double y) {
    const double fx = clamp_position(x - 0.5, double(p.w - 1)), fy = clamp_position(y - 0.5, double(p.h - 1));
    const int x0 = std::min(int(fx), p.w - 1), y0 = std::min(int(fy), p.h - 1);
    const int x1 = std::min(x0 + 1, p.w - 1), y1 = std::min(y0 + 1, p.h - 1);
    const float tx = float(fx - x0), ty = float(fy - y0);
    const float top = p.at(x0, y0) + tx * (p.at(x1, y0) - p.at(x0, y0));
    const float bot = p.at(x0, y1) + tx * (p.at(x1, y1) - p.at(x0, y1));
    return top + ty * (bot - top);
}

Plane binomial_blur(const Plane& p, const Exec& exec) {
    static constexpr float k[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};
    Plane tmp{p.w, p.h, std::vector<float>(p.v.size())}, out = tmp;
    parallel_for(exec, p.h, [&](long yb, long ye) {
        for (int y = int(yb); y < int(ye); ++y)
            for (int x = 0; x < p.w; ++x) {
                float s = 0;
                for (int d = -2; d <= 2; ++d) s += k[d + 2] * p.at(std::clamp(x + d, 0, p.w - 1), y);
                tmp.at(x, y) = s;
            }
    });
    parallel_for(exec, p.h, [&](long yb, long ye) {
        for (int y = int(yb); y < int(ye); ++y)
            for (int x = 0; x < p.w; ++x) {
                float s = 0;
                for (int d = -2; d <= 2; ++d) s += k[d + 2] * tmp.at(x, std::clamp(y + d, 0, p.h - 1));
                out.at(x, y) = s;
            }
    });
    return out;
}

namespace {

// Catmull-Rom weights for the four taps around a fractional offset t in [0, 1).
inline void cubic_weights(float t, float w[4]) {
    const float t2 = t * t, t3 = t2 * t;
    w[0] = 0.5f * (-t3 + 2 * t2 - t);
    w[1] = 0.5f * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5f * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5f * (t3 - t2);
}

}  // namespace

float bicubic(const float* plane, int w, int h, double x, double y) {
    const double fx = clamp_position(x - 0.5, double(w - 1)), fy = clamp_position(y - 0.5, double(h - 1));
    const int x0 = int(fx), y0 = int(fy);
    float wx[4], wy[4];
    cubic_weights(float(fx - x0), wx);
    cubic_weights(float(fy - y0), wy);
    if (x0 >= 1 && y0 >= 1 && x0 + 2 < w && y0 + 2 < h) {
        // Inside: no clamping (the same sums in the same order as below).
        const float* row = plane + std::size_t(y0 - 1) * std::size_t(w) + std::size_t(x0 - 1);
        float sum = 0;
        for (int j = 0; j < 4; ++j, row += w) sum += wy[j] * (wx[0] * row[0] + wx[1] * row[1] + wx[2] * row[2] + wx[3] * row[3]);
        return sum;
    }
    float sum = 0;
    for (int j = 0; j < 4; ++j) {
        const float* row = plane + std::size_t(std::clamp(y0 - 1 + j, 0, h - 1)) * std::size_t(w);
        float r = 0;
        for (int i = 0; i < 4; ++i) r += wx[i] * row[std::clamp(x0 - 1 + i, 0, w - 1)];
        sum += wy[j] * r;
    }
    return sum;
}

float bicubic(const Plane& p, double x, double y) { return bicubic(p.v.data(), p.w, p.h, x, y); }

namespace {

// One line's window mean: out[i] = mean of in[clamp(i - r .. i + r)].
void line_mean(const float* in, float* out, int n, std::ptrdiff_t stride, int r) {
    double sum = 0;
    for (int k = -r; k <= r; ++k) sum += in[std::ptrdiff_t(std::clamp(k, 0, n - 1)) * stride];
    const double inv = 1.0 / double(2 * r + 1);
    for (int i = 0; i < n; ++i) {
        out[std::ptrdiff_t(i) * stride] = float(sum * inv);
        sum += in[std::ptrdiff_t(std::min(i + r + 1, n - 1)) * stride] - in[std::ptrdiff_t(std::max(i - r, 0)) * stride];
    }
}

}  // namespace

void box_mean(Plane& p, int r, const Exec& exec) {
    if (r <= 0 || p.v.empty()) return;
    std::vector<float> tmp(p.v.size());
    parallel_for(exec, p.h, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y)
            line_mean(p.v.data() + y * p.w, tmp.data() + y * p.w, p.w, 1, r);
    });
    parallel_for(exec, p.w, [&](long x0, long x1) {
        for (long x = x0; x < x1; ++x) line_mean(tmp.data() + x, p.v.data() + x, p.h, p.w, r);
    });
}

}  // namespace gdof::sweep_detail
