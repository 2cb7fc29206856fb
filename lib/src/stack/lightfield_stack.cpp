// Focus/aperture stacks extracted from a light field: each request becomes a
// refocused image and a StackReference with its depth of field from the
// light field's geometry.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/format_number.h"
#include "gdof/lightfield.h"

namespace gdof {

namespace {

std::string num(double v) { return format_number(v, 9); }

}  // namespace

Result<FocalStack> plan_stack(const LightField& lf, const ExtractStackOptions& spec) {
    if (auto st = lf.validate(); !st) return st;
    if (!(spec.coc_px > 0) || !std::isfinite(spec.coc_px))
        return Status::error("coc_px: must be a positive number of pixels, got " + num(spec.coc_px));
    if (spec.references.empty()) return Status::error("references: the stack is empty");
    const LightFieldGeometry& g = lf.geometry;
    FocalStack stack;
    stack.coc_px = spec.coc_px;
    stack.scene_unit_mm = spec.scene_unit_mm;
    stack.width = lf.central().width();
    stack.height = lf.central().height();
    for (std::size_t i = 0; i < spec.references.size(); ++i) {
        const StackRequest& q = spec.references[i];
        const std::string key = "references[" + std::to_string(i) + "]";
        StackReference ref;
        double d = q.focus_disparity;
        if (std::isnan(d)) {
            const double z = q.focus_depth;
            if (std::isnan(z)) return Status::error(key + ": give a focus disparity or a focus depth");
            if (!(z > 0)) return Status::error(key + ".depth: must be > 0 (or inf), got " + num(z));
            d = g.disparity_of_depth(z);
        } else if (!std::isfinite(d)) {
            return Status::error(key + ".disparity: must be finite, got " + num(d));
        }
        if (!(q.aperture_radius >= 0) || !std::isfinite(q.aperture_radius))
            return Status::error(key + ".aperture: must be >= 0 view steps, got " + num(q.aperture_radius));
        for (std::size_t j = 0; j < i; ++j) {
            const StackReference& o = stack.references[j];
            if (std::abs(o.focus_disparity - d) <= 1e-9 * (1 + std::abs(d)) &&
                std::abs(o.aperture_radius_views - q.aperture_radius) <= 1e-9)
                return Status::error(key + ": duplicate of references[" + std::to_string(j) + "] (focus disparity " +
                                     num(d) + ", aperture " + num(q.aperture_radius) + ")");
        }
        const DepthRange dof = refocus_depth_of_field(g, d, q.aperture_radius, spec.coc_px);
        if (std::isnan(dof.near) || std::isnan(dof.far) || std::isinf(dof.near))
            return Status::error(key + ": focus disparity " + num(d) + " with aperture " + num(q.aperture_radius) +
                                 " is sharp only beyond infinity (disparity_at_infinity = " +
                                 num(g.disparity_at_infinity) + ", focal_baseline = " + num(g.focal_baseline) +
                                 "): check the light field's geometry");
        ref.focus_disparity = d;
        ref.aperture_radius_views = q.aperture_radius;
        ref.near = dof.near;
        ref.far = dof.far;
        // Focus at or beyond infinity: no focus distance (the manifest's
        // near/far are explicit, so none is needed).
        const double z = g.depth_of_disparity(d);
        if (std::isfinite(z)) ref.focus_distance = z;
        stack.references.push_back(ref);
    }
    return stack;
}

Result<ExtractedStack> extract_stack(const LightField& lf, const ExtractStackOptions& spec, const StackSink& sink,
                                     const Exec& exec) {
    auto planned = plan_stack(lf, spec);
    if (!planned) return planned.status();
    ExtractedStack out;
    out.stack = std::move(planned).value();
    const std::size_t n = out.stack.references.size();
    // Work per reference is proportional to its number of views.
    std::vector<double> weight(n);
    double total = 0;
    for (std::size_t i = 0; i < n; ++i)
        total += weight[i] = lf.aperture_views(out.stack.references[i].aperture_radius_views);
    double done = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (exec.is_cancelled()) return Status::error("light-field stack: cancelled", StatusCode::Cancelled);
        Exec sub = exec;
        if (exec.progress)
            sub.progress = [&, i](double f) { exec.report((done + f * weight[i]) / total); };
        RefocusOptions rs;
        rs.focus_disparity = out.stack.references[i].focus_disparity;
        rs.aperture_radius = out.stack.references[i].aperture_radius_views;
        rs.filter = spec.filter;
        auto img = refocus(lf, rs, sub);
        if (!img) return img.status().prefix("references[" + std::to_string(i) + "]");
        if (sink) {
            if (auto st = sink(i, std::move(img).value()); !st) return st;
        } else {
            out.images.push_back(std::move(img).value());
        }
        done += weight[i];
    }
    return out;
}

}  // namespace gdof
