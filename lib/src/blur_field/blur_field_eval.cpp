// BlurField: construction helpers and point evaluation (batch and single).
#include <algorithm>
#include <cmath>
#include <limits>

#include "blur_field/blur_field_nodes.h"

namespace gdof {

using bf::kChunk;

BlurField::BlurField() : root_(bf::make_zero()), max_radius_(std::numeric_limits<double>::infinity()) {}

BlurField::BlurField(std::shared_ptr<const bf::Node> root, double max_radius)
    : root_(std::move(root)), max_radius_(max_radius) {}

Result<BlurField> BlurField::from_thin_lens(const ThinLens& lens) {
    ThinLens l = lens;
    l.image_width_px = 1;  // the camera supplies the width
    if (auto s = l.validate(); !s) return s;
    return BlurField(bf::make_thin_lens(l), std::numeric_limits<double>::infinity());
}

bool BlurField::depth_only() const { return (root_->needs() & ~unsigned(bf::kDepth)) == 0; }

std::string BlurField::describe() const { return root_->describe(); }

Status BlurField::evaluate(const Camera& camera, std::span<const Vec3> points, std::span<float> radius_px) const {
    if (points.size() != radius_px.size())
        return Status::error("BlurField::evaluate: " + std::to_string(points.size()) + " points but " +
                             std::to_string(radius_px.size()) + " outputs");
    const unsigned needs = root_->needs();
    const bool project = (needs & (bf::kPixel | bf::kDepth)) != 0;
    double x[kChunk], y[kChunk], z[kChunk], px[kChunk], py[kChunk], depth[kChunk], out[kChunk];
    for (std::size_t base = 0; base < points.size(); base += kChunk) {
        const std::size_t n = std::min(kChunk, points.size() - base);
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3& p = points[base + i];
            x[i] = p.x, y[i] = p.y, z[i] = p.z;
        }
        if (project)
            for (std::size_t i = 0; i < n; ++i) {
                const PixelDepth pd = camera.project(points[base + i]);
                px[i] = pd.x, py[i] = pd.y, depth[i] = pd.depth;
            }
        bf::Batch b{n, x, y, z, px, py, depth, &camera};
        root_->eval(b, out);
        for (std::size_t i = 0; i < n; ++i) radius_px[base + i] = float(out[i]);
    }
    return {};
}

Status BlurField::evaluate(const Camera& camera, std::span<const PixelDepth> samples,
                           std::span<float> radius_px) const {
    if (samples.size() != radius_px.size())
        return Status::error("BlurField::evaluate: " + std::to_string(samples.size()) + " samples but " +
                             std::to_string(radius_px.size()) + " outputs");
    const bool world = (root_->needs() & bf::kWorld) != 0;
    double x[kChunk], y[kChunk], z[kChunk], px[kChunk], py[kChunk], depth[kChunk], out[kChunk];
    for (std::size_t base = 0; base < samples.size(); base += kChunk) {
        const std::size_t n = std::min(kChunk, samples.size() - base);
        for (std::size_t i = 0; i < n; ++i) {
            const PixelDepth& s = samples[base + i];
            px[i] = s.x, py[i] = s.y, depth[i] = s.depth;
        }
        if (world)
            for (std::size_t i = 0; i < n; ++i) {
                // Depth +inf (sky) has no finite world point: unproject(+inf)
                // is inf - inf = NaN, and a region field would give NaN where
                // layers promise B accepts +inf. A point this far along the
                // pixel's ray gives the limit instead: every bounded shape's
                // signed distance overflows to +inf, a plane's follows the ray.
                constexpr double kFarDepth = 1e200;
                const double d = depth[i] == std::numeric_limits<double>::infinity() ? kFarDepth : depth[i];
                const Vec3 p = camera.unproject(px[i], py[i], d);
                x[i] = p.x, y[i] = p.y, z[i] = p.z;
            }
        bf::Batch b{n, x, y, z, px, py, depth, &camera};
        root_->eval(b, out);
        for (std::size_t i = 0; i < n; ++i) radius_px[base + i] = float(out[i]);
    }
    return {};
}

float BlurField::evaluate(const Camera& camera, const Vec3& point) const {
    float r = 0;
    (void)evaluate(camera, std::span<const Vec3>(&point, 1), std::span<float>(&r, 1));
    return r;
}

float BlurField::evaluate_pixel(const Camera& camera, double px, double py, double depth) const {
    const PixelDepth s{px, py, depth};
    float r = 0;
    (void)evaluate(camera, std::span<const PixelDepth>(&s, 1), std::span<float>(&r, 1));
    return r;
}

double BlurField::evaluate_on_ray(const Camera& camera, double px, double py, double depth) const {
    bf::Ray r{&camera, camera.depth_line(px, py), px, py};
    return bf::eval_on_ray(*root_, r, depth);
}

namespace bf {

void eval_on_ray(const Node& node, const Ray& r, const double* depths, std::size_t n, double* out) {
    double x[kChunk], y[kChunk], z[kChunk], px[kChunk], py[kChunk];
    for (std::size_t base = 0; base < n; base += kChunk) {
        const std::size_t m = std::min(kChunk, n - base);
        for (std::size_t i = 0; i < m; ++i) {
            const Vec3 p = r.line.at(depths[base + i]);
            x[i] = p.x, y[i] = p.y, z[i] = p.z;
            px[i] = r.px, py[i] = r.py;
        }
        Batch b{m, x, y, z, px, py, depths + base, r.camera};
        node.eval(b, out + base);
    }
}

double eval_on_ray(const Node& node, const Ray& r, double depth) {
    double out = 0;
    eval_on_ray(node, r, &depth, 1, &out);
    return out;
}

}  // namespace bf

namespace bf {

Result<NodePtr> Node::refocused(double) const { return NodePtr(); }

}  // namespace bf

Result<BlurField> BlurField::refocused(double focus_distance) const {
    if (!(focus_distance > 0) || std::isnan(focus_distance))
        return Status::error("focus distance: must be > 0, got " + std::to_string(focus_distance),
                             StatusCode::InvalidArgument, "focus_distance");
    auto r = root_->refocused(focus_distance);
    if (!r) return r.status();
    if (!*r)
        return Status::error("the blur field " + describe() + " has no thin_lens to focus", StatusCode::InvalidArgument,
                             "focus_distance");
    return BlurField(*r, max_radius_);
}

}  // namespace gdof
