// Blur-field leaves: thin_lens, focal_planes, region, image_map.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "blur_field/blur_field_nodes.h"
#include "blur_field/context_image.h"

namespace gdof::bf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline double smoothstep01(double t) { return t * t * (3.0 - 2.0 * t); }

void push_if_inside(std::vector<double>& out, double d, double a, double b) {
    if (d >= a && d <= b) out.push_back(d);
}

// ---------------------------------------------------------------- thin_lens
class ThinLensNode final : public Node {
public:
    explicit ThinLensNode(const ThinLens& l) : lens_(l) {
        const double f = l.focal_length_mm, s = l.focus_distance * l.scene_unit_mm;
        // radius_px = k * W * |1 - s / z|, k = 0.5 * (f / N) * f / (s - f) / sensor_width
        k_ = 0.5 * (f / l.f_number) * f / (s - f) / l.sensor_width_mm;
        s_ = l.focus_distance;
    }
    void eval(const Batch& b, double* out) const override {
        const double kw = k_ * b.camera->image_width();
        for (std::size_t i = 0; i < b.n; ++i) {
            const double z = b.depth[i];
            const double a = std::fabs(1.0 - s_ / z);
            const double r = a == 0 ? 0.0 : kw * a;  // sharp at s even if kw overflowed (no inf * 0)
            out[i] = z > 0 ? r : (z <= 0 ? kInf : kNaN);
        }
    }
    unsigned needs() const override { return kDepth; }
    void breakpoints(const Ray&, double a, double b, std::vector<double>& out) const override {
        push_if_inside(out, s_, a, b);
    }
    bool linear_between_breakpoints() const override { return false; }
    std::string describe() const override { return "thin_lens"; }
    Result<NodePtr> refocused(double focus_distance) const override {
        ThinLens l = lens_;
        l.focus_distance = focus_distance;
        if (Status st = l.validate(); !st) return st.prefix("thin_lens refocused");
        return make_thin_lens(l);
    }

private:
    ThinLens lens_;
    double k_, s_;
};

// ------------------------------------------------------------- focal_planes
class FocalPlanesNode final : public Node {
public:
    explicit FocalPlanesNode(FocalPlanesSpec s) : s_(std::move(s)) {
        const std::size_t n = s_.depths.size();
        // Ramp length: distance from a plane at which max_blur is reached.
        auto ramp = [&](double half_gap) {
            if (s_.slope > 0) return std::isinf(s_.max_blur) ? kInf : s_.max_blur / s_.slope;
            return half_gap;
        };
        for (std::size_t i = 0; i + 1 < n; ++i) gap_ramp_.push_back(ramp(0.5 * (s_.depths[i + 1] - s_.depths[i])));
        const double fallback = gap_ramp_.empty() ? kInf : gap_ramp_.front();
        ramp_before_ = s_.slope > 0 ? ramp(0) : fallback;
        ramp_after_ = s_.slope > 0 ? ramp(0) : (gap_ramp_.empty() ? kInf : gap_ramp_.back());
    }
    double value(double d) const {
        if (std::isnan(d)) return kNaN;
        const auto& p = s_.depths;
        double dist, L;
        if (d <= p.front()) {
            dist = p.front() - d;
            L = ramp_before_;
        } else if (d >= p.back()) {
            dist = d - p.back();
            L = ramp_after_;
        } else {
            const std::size_t i = std::size_t(std::upper_bound(p.begin(), p.end(), d) - p.begin()) - 1;
            dist = std::min(d - p[i], p[i + 1] - d);
            L = gap_ramp_[i];
        }
        if (std::isinf(s_.max_blur)) return s_.slope * dist;  // linear, unbounded
        const double t = std::min(dist / L, 1.0);
        return s_.max_blur * (s_.smooth ? smoothstep01(t) : t);
    }
    void eval(const Batch& b, double* out) const override {
        for (std::size_t i = 0; i < b.n; ++i) out[i] = value(b.depth[i]);
    }
    unsigned needs() const override { return kDepth; }
    void breakpoints(const Ray&, double a, double b, std::vector<double>& out) const override {
        const auto& p = s_.depths;
        for (std::size_t i = 0; i < p.size(); ++i) {
            push_if_inside(out, p[i], a, b);
            const double before = i == 0 ? ramp_before_ : gap_ramp_[i - 1];
            const double after = i + 1 == p.size() ? ramp_after_ : gap_ramp_[i];
            if (std::isfinite(before)) push_if_inside(out, p[i] - before, a, b);
            if (std::isfinite(after)) push_if_inside(out, p[i] + after, a, b);
            if (i + 1 < p.size()) push_if_inside(out, 0.5 * (p[i] + p[i + 1]), a, b);
        }
    }
    bool linear_between_breakpoints() const override { return !s_.smooth; }
    std::string describe() const override { return "focal_planes"; }

private:
    FocalPlanesSpec s_;
    std::vector<double> gap_ramp_;
    double ramp_before_ = kInf, ramp_after_ = kInf;
};

// ------------------------------------------------------------------- region
class RegionNode final : public Node {
public:
    explicit RegionNode(const RegionSpec& s) : s_(s) {}

    // Signed distance (negative inside); convex in the point for every shape.
    double sdf(double x, double y, double z) const {
        switch (s_.shape) {
            case Shape::Sphere: {
                const double dx = x - s_.center.x, dy = y - s_.center.y, dz = z - s_.center.z;
                return std::sqrt(dx * dx + dy * dy + dz * dz) - s_.radius;
            }
            case Shape::Box: {
                const Vec3 d{x - s_.center.x, y - s_.center.y, z - s_.center.z};
                const double qx = std::fabs(dot(d, s_.rot_x)) - s_.half_size.x;
                const double qy = std::fabs(dot(d, s_.rot_y)) - s_.half_size.y;
                const double qz = std::fabs(dot(d, s_.rot_z)) - s_.half_size.z;
                const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
                return std::sqrt(ox * ox + oy * oy + oz * oz) + std::min(std::max(qx, std::max(qy, qz)), 0.0);
            }
            case Shape::Plane: {
                const Vec3 d{x - s_.point.x, y - s_.point.y, z - s_.point.z};
                return std::fabs(dot(d, s_.normal)) - s_.half_thickness;
            }
        }
        return kNaN;
    }
    double from_sdf(double sd) const {
        if (std::isnan(sd)) return kNaN;
        double t;
        if (s_.falloff > 0) {
            t = std::clamp(sd / s_.falloff, 0.0, 1.0);
            if (s_.smooth) t = smoothstep01(t);
        } else {
            t = sd > 0 ? 1.0 : 0.0;
        }
        return s_.blur * (s_.focus_mode ? t : 1.0 - t);
    }
    void eval(const Batch& b, double* out) const override {
        for (std::size_t i = 0; i < b.n; ++i) out[i] = from_sdf(sdf(b.x[i], b.y[i], b.z[i]));
    }
    unsigned needs() const override { return kWorld; }

    void breakpoints(const Ray& r, double a, double b, std::vector<double>& out) const override {
        auto sd = [&](double d) {
            const Vec3 p = r.line.at(d);
            return sdf(p.x, p.y, p.z);
        };
        // The signed distance of a convex shape is convex along a line:
        // golden-section search for its minimum, then each level (0, falloff)
        // is crossed at most once on either side of it.
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        double lo = a, hi = b;
        double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
        double f1 = sd(x1), f2 = sd(x2);
        for (int it = 0; it < 300 && hi - lo > 1e-15 * std::max(std::fabs(lo), std::fabs(hi)); ++it) {
            if (f1 <= f2) {
                hi = x2, x2 = x1, f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = sd(x1);
            } else {
                lo = x1, x1 = x2, f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = sd(x2);
            }
        }
        double dmin = 0.5 * (lo + hi);
        double fmin = sd(dmin);
        if (sd(a) < fmin) dmin = a, fmin = sd(a);
        if (sd(b) < fmin) dmin = b, fmin = sd(b);
        if (std::isnan(fmin)) return;
        const double levels[2] = {0.0, s_.falloff};
        for (int li = 0; li < (s_.falloff > 0 ? 2 : 1); ++li) {
            const double level = levels[li];
            if (!(fmin < level)) continue;
            if (sd(a) > level) level_crossings(sd, level, {a, dmin}, 1, out);
            if (sd(b) > level) level_crossings(sd, level, {dmin, b}, 1, out);
        }
    }
    bool linear_between_breakpoints() const override { return s_.falloff == 0; }
    std::string describe() const override {
        const char* shape = s_.shape == Shape::Sphere ? "sphere" : s_.shape == Shape::Box ? "box" : "plane";
        return std::string("region(") + shape + ", " + (s_.focus_mode ? "focus" : "blur") + ")";
    }

private:
    RegionSpec s_;
};

// ---------------------------------------------------------------- image_map
class ImageMapNode final : public Node {
public:
    ImageMapNode(std::shared_ptr<const Image> img, int channel, double scale, std::string name)
        : img_(std::move(img)), channel_(channel), scale_(scale), name_(std::move(name)) {}

    double value(const Camera& cam, double px, double py) const {
        if (std::isnan(px) || std::isnan(py)) return kNaN;
        // Camera display window -> map display window, then to sample space
        // (pixel centres at +0.5).
        const blur_field_detail::MapTaps taps = blur_field_detail::map_taps(*img_, cam.display_window(), px, py);
        if (!taps.ok) return 0.0;
        const int x0 = taps.x0, y0 = taps.y0, x1 = taps.x1, y1 = taps.y1;
        const double fx = taps.fx, fy = taps.fy;
        auto at = [&](int x, int y) {
            const double s = img_->sample(channel_, x, y);
            return std::isnan(s) || s < 0 ? 0.0 : s;
        };
        // A tap of weight 0 is skipped, so an infinite map value (a half
        // overflow in a painted EXR) stays +inf where it is sampled and does
        // not turn its neighbours' exact samples into inf * 0 = NaN.
        auto lerp = [](double a, double b, double t) { return t == 0 ? a : t == 1 ? b : a * (1 - t) + b * t; };
        const double top = lerp(at(x0, y0), at(x1, y0), fx);
        const double bot = lerp(at(x0, y1), at(x1, y1), fx);
        const double value = lerp(top, bot, fy);
        return scale_ == 0 ? 0.0 : scale_ * value;  // scale 0: sharp, also where the map is +inf
    }
    void eval(const Batch& b, double* out) const override {
        for (std::size_t i = 0; i < b.n; ++i) out[i] = value(*b.camera, b.px[i], b.py[i]);
    }
    unsigned needs() const override { return kPixel; }
    void breakpoints(const Ray&, double, double, std::vector<double>&) const override {}
    bool linear_between_breakpoints() const override { return true; }  // constant along a central ray
    std::string describe() const override { return "image_map(" + name_ + ")"; }

private:
    std::shared_ptr<const Image> img_;
    int channel_;
    double scale_;
    std::string name_;
};

}  // namespace

NodePtr make_thin_lens(const ThinLens& lens) { return std::make_shared<ThinLensNode>(lens); }
NodePtr make_focal_planes(const FocalPlanesSpec& s) { return std::make_shared<FocalPlanesNode>(s); }
NodePtr make_region(const RegionSpec& s) { return std::make_shared<RegionNode>(s); }
NodePtr make_image_map(std::shared_ptr<const Image> img, int channel, double scale, std::string name) {
    return std::make_shared<ImageMapNode>(std::move(img), channel, scale, std::move(name));
}

}  // namespace gdof::bf
