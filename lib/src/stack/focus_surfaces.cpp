// Bicubic B-spline focus surfaces (focus_surfaces.h): evaluation, the
// interpolating prefilter, the surfaces JSON (read with json_read), and
// near/far maps.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gdof/focus_surfaces.h"
#include "common/json_read.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Uniform cubic B-spline basis at t in [0, 1].
inline void basis(double t, double w[4]) {
    const double t2 = t * t, t3 = t2 * t, s = 1.0 - t;
    w[0] = s * s * s / 6.0;
    w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    w[3] = t3 / 6.0;
}

// Segment index and local parameter for n control points along [0, 1].
inline void locate(double u, int n, int& seg, double& t) {
    if (n <= 1) {
        seg = 0;
        t = 0;
        return;
    }
    u = std::clamp(u, 0.0, 1.0) * double(n - 1);
    seg = std::min(int(std::floor(u)), n - 2);
    t = u - double(seg);
}

inline double phantom(double edge, double inner) {
    if (std::isinf(edge) || std::isinf(inner)) return edge;
    return 2.0 * edge - inner;
}

// Interpolating prefilter along one line of n values (stride apart): solves
// P[0] = d[0], P[n-1] = d[n-1], (P[i-1] + 4 P[i] + P[i+1]) / 6 = d[i] (Thomas algorithm).
void prefilter_line(double* d, int n, std::ptrdiff_t stride) {
    if (n <= 2) return;
    std::vector<double> c(std::size_t(n), 0.0), r(std::size_t(n), 0.0);
    // Unknowns 1..n-2; boundary values move to the right-hand side.
    for (int i = 1; i <= n - 2; ++i) r[std::size_t(i)] = 6.0 * d[i * stride];
    r[1] -= d[0];
    r[std::size_t(n - 2)] -= d[(n - 1) * stride];
    // Forward sweep on the tridiagonal (1, 4, 1).
    double denom = 4.0;
    c[1] = 1.0 / denom;
    r[1] /= denom;
    for (int i = 2; i <= n - 2; ++i) {
        denom = 4.0 - c[std::size_t(i - 1)];
        c[std::size_t(i)] = 1.0 / denom;
        r[std::size_t(i)] = (r[std::size_t(i)] - r[std::size_t(i - 1)]) / denom;
    }
    for (int i = n - 3; i >= 1; --i) r[std::size_t(i)] -= c[std::size_t(i)] * r[std::size_t(i + 1)];
    for (int i = 1; i <= n - 2; ++i) d[i * stride] = r[std::size_t(i)];
}

using json_read::Infinity;
using json_read::Object;
using json_read::Value;

// A depth in scene units: a number >= 0, or "inf".
double depth_value(const Value& v) { return v.non_negative(Infinity::Allowed); }

BSplineSurface parse_surface(const Value& v, bool interpolate) {
    if (v.raw().is_number() || v.raw().is_string()) return BSplineSurface::constant(depth_value(v));
    if (!v.raw().is_object())
        v.fail("must be a number, \"inf\" or an object {\"grid\": [[...], ...]}, got " + json_read::type_name(v.raw()));
    const Object o = v.object({"grid", "interpolate", "comment"});
    if (const auto i = o.find("interpolate")) interpolate = i->boolean();
    const Value grid = o.get("grid");
    if (!grid.raw().is_array() || grid.raw().empty()) grid.fail("must be a non-empty array of rows (top row first)");
    int nx = -1;
    std::vector<double> values;
    for (const Value& row : grid.array()) {
        const std::vector<Value> cells = row.non_empty_array("depths");
        if (nx < 0) nx = int(cells.size());
        if (int(cells.size()) != nx)
            row.fail("has " + std::to_string(cells.size()) + " values, row 0 has " + std::to_string(nx) +
                     " (the grid must be rectangular)");
        for (const Value& c : cells) values.push_back(depth_value(c));
    }
    auto s = BSplineSurface::create(nx, int(grid.raw().size()), std::move(values), interpolate);
    if (!s) v.fail(s.message());
    return std::move(s).value();
}

}  // namespace

BSplineSurface BSplineSurface::constant(double value) {
    BSplineSurface s;
    s.cp_[0] = value;
    return s;
}

Result<BSplineSurface> BSplineSurface::create(int nx, int ny, std::vector<double> values, bool interpolate) {
    if (nx < 1 || ny < 1) return Status::error("control grid must be at least 1 x 1");
    if (values.size() != std::size_t(nx) * std::size_t(ny))
        return Status::error("control grid has " + std::to_string(values.size()) + " values, expected " +
                             std::to_string(nx) + " x " + std::to_string(ny));
    for (double v : values) {
        if (std::isnan(v) || v == -kInf) return Status::error("control values must be numbers or +inf");
        if (interpolate && std::isinf(v))
            return Status::error("\"interpolate\": true cannot pass through infinite control values "
                                 "(use the default approximating surface, or finite depths)");
    }
    BSplineSurface s;
    s.nx_ = nx;
    s.ny_ = ny;
    s.interpolate_ = interpolate;
    s.cp_ = std::move(values);
    if (interpolate) {
        for (int j = 0; j < ny; ++j) prefilter_line(s.cp_.data() + std::size_t(j) * std::size_t(nx), nx, 1);
        for (int i = 0; i < nx; ++i) prefilter_line(s.cp_.data() + i, ny, nx);
    }
    return s;
}

double BSplineSurface::phantom_x(int i, int j) const {
    // Row j is inside the grid; i may be -1 or nx_.
    const double* row = cp_.data() + std::size_t(j) * std::size_t(nx_);
    if (nx_ == 1) return row[0];
    if (i < 0) return phantom(row[0], row[1]);
    if (i >= nx_) return phantom(row[nx_ - 1], row[nx_ - 2]);
    return row[i];
}

double BSplineSurface::cp(int i, int j) const {
    if (ny_ == 1) return phantom_x(i, 0);
    if (j < 0) return phantom(phantom_x(i, 0), phantom_x(i, 1));
    if (j >= ny_) return phantom(phantom_x(i, ny_ - 1), phantom_x(i, ny_ - 2));
    return phantom_x(i, j);
}

double BSplineSurface::evaluate(double u, double v) const {
    if (nx_ == 1 && ny_ == 1) return cp_[0];
    int sx, sy;
    double tx, ty, wx[4], wy[4];
    locate(u, nx_, sx, tx);
    locate(v, ny_, sy, ty);
    basis(tx, wx);
    basis(ty, wy);
    if (nx_ == 1) wx[0] = 0, wx[1] = 1, wx[2] = 0, wx[3] = 0;
    if (ny_ == 1) wy[0] = 0, wy[1] = 1, wy[2] = 0, wy[3] = 0;
    double sum = 0.0;
    for (int b = 0; b < 4; ++b) {
        if (wy[b] == 0.0) continue;
        double row = 0.0;
        for (int a = 0; a < 4; ++a) {
            if (wx[a] == 0.0) continue;
            const double p = cp(sx - 1 + a, sy - 1 + b);
            if (std::isinf(p)) return kInf;
            row += wx[a] * p;
        }
        sum += wy[b] * row;
    }
    return sum;
}

bool BSplineSurface::evaluate_pixels(int width, int height, float* out, const Exec& exec) const {
    if (width <= 0 || height <= 0) return true;
    // Per column: its segment and weights, as evaluate() finds them.
    std::vector<int> sx(std::size_t(width), 0);
    std::vector<std::array<double, 4>> wx(static_cast<std::size_t>(width));
    for (int x = 0; x < width; ++x) {
        double t = 0.0;
        locate((double(x) + 0.5) / double(width), nx_, sx[std::size_t(x)], t);
        basis(t, wx[std::size_t(x)].data());
        if (nx_ == 1) wx[std::size_t(x)] = {0, 1, 0, 0};
    }
    // Every control row j in [-1, ny] (phantoms included) combined along x for
    // every column, in evaluate()'s order; a flag where an infinite control
    // point has weight.
    const int nr = ny_ + 2;
    std::vector<double> rows(std::size_t(nr) * std::size_t(width), 0.0);
    std::vector<unsigned char> inf(rows.size(), 0);
    for (int j = -1; j <= ny_; ++j)
        for (int x = 0; x < width; ++x) {
            const std::size_t k = std::size_t(j + 1) * std::size_t(width) + std::size_t(x);
            double row = 0.0;
            for (int a = 0; a < 4; ++a) {
                const double w = wx[std::size_t(x)][std::size_t(a)];
                if (w == 0.0) continue;
                const double p = cp(sx[std::size_t(x)] - 1 + a, j);
                if (std::isinf(p)) {
                    inf[k] = 1;
                    break;
                }
                row += w * p;
            }
            rows[k] = row;
        }
    const bool single = nx_ == 1 && ny_ == 1;
    return parallel_for(exec, height, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            float* o = out + std::size_t(y) * std::size_t(width);
            if (single) {
                std::fill(o, o + width, float(cp_[0]));
                continue;
            }
            int sy = 0;
            double ty = 0.0, wy[4];
            locate((double(y) + 0.5) / double(height), ny_, sy, ty);
            basis(ty, wy);
            if (ny_ == 1) wy[0] = 0, wy[1] = 1, wy[2] = 0, wy[3] = 0;
            for (int x = 0; x < width; ++x) {
                double sum = 0.0;
                bool is_inf = false;
                for (int b = 0; b < 4 && !is_inf; ++b) {
                    if (wy[b] == 0.0) continue;
                    const std::size_t k = std::size_t(sy + b) * std::size_t(width) + std::size_t(x);  // row sy - 1 + b
                    if (inf[k]) is_inf = true;
                    else sum += wy[b] * rows[k];
                }
                o[x] = is_inf ? float(kInf) : float(sum);
            }
        }
    }, 16);
}

Result<FocusSurfaces> parse_focus_surfaces(const std::string& text) {
    return json_read::read_document(text, "surfaces", [](const Value& root) {
        if (!root.raw().is_object())
            root.fail("must be an object {\"near\": ..., \"far\": ...}, got " + json_read::type_name(root.raw()));
        const Object o = root.object({"gdof_surfaces", "interpolate", "near", "far", "comment"});
        if (const auto v = o.find("gdof_surfaces"); v && (!v->raw().is_number_integer() || v->raw().get<long long>() != 1))
            v->fail("unsupported version " + v->raw().dump() + " (this gdof reads version 1)");
        bool interpolate = false;
        if (const auto v = o.find("interpolate")) interpolate = v->boolean();
        o.require("near");
        o.require("far");
        FocusSurfaces s;
        s.near = parse_surface(o.get("near"), interpolate);
        s.far = parse_surface(o.get("far"), interpolate);
        return s;
    });
}

Result<DesiredFocus> desired_from_surfaces(const FocusSurfaces& s, int width, int height, const Exec& exec) {
    if (width <= 0 || height <= 0)
        return Status::error("focus surfaces: image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " is empty");
    DesiredFocus d;
    d.window = {0, 0, width, height};
    d.near.resize(d.npixels());
    d.far.resize(d.npixels());
    const bool ok = s.near.evaluate_pixels(width, height, d.near.data(), exec) &&
                    s.far.evaluate_pixels(width, height, d.far.data(), exec);
    if (!ok) return Status::cancelled();
    return d;
}

int find_focus_map_channel(const Image& img, const std::string& name) {
    for (const std::string& n : {name, std::string("Z"), std::string("Y")}) {
        const int c = img.channel_index(n);
        if (c >= 0 && img.channel(c).type != PixelType::UInt) return c;
    }
    for (int c = 0; c < img.nchannels(); ++c)
        if (img.channel(c).type != PixelType::UInt) return c;
    return -1;
}

Result<DesiredFocus> desired_from_maps(const Image& near_img, int near_channel, const Image& far_img, int far_channel) {
    if (near_channel < 0 || near_channel >= near_img.nchannels() || !near_img.plane(near_channel))
        return Status::error("near map: no float channel to read");
    if (far_channel < 0 || far_channel >= far_img.nchannels() || !far_img.plane(far_channel))
        return Status::error("far map: no float channel to read");
    if (near_img.width() != far_img.width() || near_img.height() != far_img.height())
        return Status::error("near map is " + std::to_string(near_img.width()) + "x" + std::to_string(near_img.height()) +
                             " but far map is " + std::to_string(far_img.width()) + "x" +
                             std::to_string(far_img.height()));
    DesiredFocus d;
    d.window = {0, 0, near_img.width(), near_img.height()};
    d.near.assign(near_img.plane(near_channel), near_img.plane(near_channel) + near_img.npixels());
    d.far.assign(far_img.plane(far_channel), far_img.plane(far_channel) + far_img.npixels());
    return d;
}

}  // namespace gdof
