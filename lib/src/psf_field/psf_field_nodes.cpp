// The kinds of PSF field (psf_field.h has the formulas, docs/psf_field.md the
// keys).
#include <cmath>

#include "blur_field/context_image.h"
#include "psf_field/psf_field_nodes.h"

namespace gdof::psf {

namespace {

// B * scale * (u, -v): the aperture shape scaled by the blur (image y down).
class Defocus final : public Node {
public:
    explicit Defocus(double scale) : scale_(scale) {}
    PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi&) const override {
        const double b = p.blur * scale_;
        return {b * u, -b * v, 0.0};
    }
    std::string describe() const override { return scale_ == 1.0 ? "defocus" : "defocus(x" + std::to_string(scale_) + ")"; }

private:
    double scale_;
};

// A rotation about the frame centre by the angle whose arc at the point's
// distance rho is strength * B * (rho / half diagonal)^power * u_t, so the
// point sweeps an arc of the circle it lies on (Petzval-like swirl).
class Swirl final : public Node {
public:
    Swirl(double strength, double power) : strength_(strength), power_(power) {}
    PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi& frame) const override {
        const double cx = 0.5 * (frame.x0 + frame.x1), cy = 0.5 * (frame.y0 + frame.y1);
        const double half_diag = 0.5 * std::hypot(double(frame.width()), double(frame.height()));
        const double rx = p.x - cx, ry = p.y - cy;
        const double rho = std::hypot(rx, ry);
        if (!(rho > 1e-9) || !(half_diag > 0.0)) return {};
        // Tangent (counter-clockwise on screen, y down): (ry, -rx) / rho.
        const double tx = ry / rho, ty = -rx / rho;
        const double ut = u * tx + (-v) * ty;  // the sample in image axes, along the tangent
        const double arc = strength_ * p.blur * std::pow(rho / half_diag, power_) * ut;
        const double angle = arc / rho;
        const double c = std::cos(angle), s = std::sin(angle);
        // Rotating (rx, ry) towards the tangent (ry, -rx): y down, so the
        // screen rotation by `angle` is (rx c + ry s, -rx s + ry c).
        return {rx * c + ry * s - rx, -rx * s + ry * c - ry, 0.0};
    }
    std::string describe() const override { return "swirl"; }

private:
    double strength_, power_;
};

// Along the viewing ray: the image position stays, the depth changes.
class Depth final : public Node {
public:
    Depth(double offset, double distance) : offset_(offset), distance_(distance) {}
    PsfDisplacement displace(const PsfPoint&, double u, double, const Roi&) const override {
        return {0.0, 0.0, offset_ + distance_ * u};
    }
    bool moves_depth() const override { return offset_ != 0.0 || distance_ != 0.0; }
    std::string describe() const override { return "depth"; }

private:
    double offset_, distance_;
};

// A painted linear map of the aperture sample (image y down): 1 channel an
// isotropic scale, 2 per-axis scales, 4 a full 2x2 matrix, in pixels per unit
// aperture. Sampled as the blur field's image_map: the map's display window
// stretched over the frame, bilinear between pixel centres, clamped at its
// data window; a non-finite value counts as 0.
class ImageMap final : public Node {
public:
    ImageMap(std::shared_ptr<const Image> map, std::vector<int> channels, double scale, std::string name)
        : map_(std::move(map)), ch_(std::move(channels)), scale_(scale), name_(std::move(name)) {}
    PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi& frame) const override {
        double m[4] = {0, 0, 0, 0};
        sample(p.x, p.y, frame, m);
        const double ax = u, ay = -v;
        double dx = 0, dy = 0;
        if (ch_.size() == 1) {
            dx = m[0] * ax;
            dy = m[0] * ay;
        } else if (ch_.size() == 2) {
            dx = m[0] * ax;
            dy = m[1] * ay;
        } else {
            dx = m[0] * ax + m[1] * ay;
            dy = m[2] * ax + m[3] * ay;
        }
        return {scale_ * dx, scale_ * dy, 0.0};
    }
    std::string describe() const override { return "image_map(" + name_ + ")"; }

private:
    void sample(double px, double py, const Roi& frame, double* out) const {
        const blur_field_detail::MapTaps t = blur_field_detail::map_taps(*map_, frame, px, py);
        if (!t.ok) return;
        for (std::size_t k = 0; k < ch_.size(); ++k) {
            auto at = [&](int sx, int sy) {
                const double s = map_->sample(ch_[k], sx, sy);
                return std::isfinite(s) ? s : 0.0;
            };
            const double top = at(t.x0, t.y0) * (1 - t.fx) + at(t.x1, t.y0) * t.fx;
            const double bot = at(t.x0, t.y1) * (1 - t.fx) + at(t.x1, t.y1) * t.fx;
            out[k] = top * (1 - t.fy) + bot * t.fy;
        }
    }

    std::shared_ptr<const Image> map_;
    std::vector<int> ch_;
    double scale_;
    std::string name_;
};

std::string list(const std::vector<NodePtr>& c) {
    std::string s;
    for (std::size_t i = 0; i < c.size(); ++i) s += (i ? ", " : "") + c[i]->describe();
    return s;
}

class Sum final : public Node {
public:
    explicit Sum(std::vector<NodePtr> c) : c_(std::move(c)) {}
    PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi& frame) const override {
        PsfDisplacement d;
        for (const NodePtr& n : c_) {
            const PsfDisplacement e = n->displace(p, u, v, frame);
            d.dx += e.dx;
            d.dy += e.dy;
            d.dz += e.dz;
        }
        return d;
    }
    bool moves_depth() const override {
        for (const NodePtr& n : c_)
            if (n->moves_depth()) return true;
        return false;
    }
    std::string describe() const override { return "sum(" + list(c_) + ")"; }
    void collect_weights(std::vector<const BlurField*>& out) const override {
        for (const NodePtr& n : c_) n->collect_weights(out);
    }

private:
    std::vector<NodePtr> c_;
};

class Blend final : public Node {
public:
    Blend(NodePtr a, NodePtr b, BlurField w, int index) : a_(std::move(a)), b_(std::move(b)), w_(std::move(w)), index_(index) {}
    PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi& frame) const override {
        const double w = p.weights ? double(p.weights[index_]) : 0.0;
        PsfDisplacement d;
        if (w < 1.0) {
            const PsfDisplacement e = a_->displace(p, u, v, frame);
            d.dx += (1.0 - w) * e.dx;
            d.dy += (1.0 - w) * e.dy;
            d.dz += (1.0 - w) * e.dz;
        }
        if (w > 0.0) {
            const PsfDisplacement e = b_->displace(p, u, v, frame);
            d.dx += w * e.dx;
            d.dy += w * e.dy;
            d.dz += w * e.dz;
        }
        return d;
    }
    bool moves_depth() const override { return a_->moves_depth() || b_->moves_depth(); }
    std::string describe() const override { return "blend(" + a_->describe() + ", " + b_->describe() + ")"; }
    void collect_weights(std::vector<const BlurField*>& out) const override {
        // Tree order: the children's blends come after this one's slot.
        out.push_back(&w_);
        a_->collect_weights(out);
        b_->collect_weights(out);
    }

private:
    NodePtr a_, b_;
    BlurField w_;
    int index_;
};

}  // namespace

NodePtr make_defocus(double scale) { return std::make_shared<Defocus>(scale); }
NodePtr make_swirl(double strength, double power) { return std::make_shared<Swirl>(strength, power); }
NodePtr make_depth(double offset, double distance) { return std::make_shared<Depth>(offset, distance); }
NodePtr make_image_map(std::shared_ptr<const Image> map, std::vector<int> channels, double scale, std::string name) {
    return std::make_shared<ImageMap>(std::move(map), std::move(channels), scale, std::move(name));
}
NodePtr make_sum(std::vector<NodePtr> children) { return std::make_shared<Sum>(std::move(children)); }
NodePtr make_blend(NodePtr a, NodePtr b, BlurField weight, int weight_index) {
    return std::make_shared<Blend>(std::move(a), std::move(b), std::move(weight), weight_index);
}

}  // namespace gdof::psf
