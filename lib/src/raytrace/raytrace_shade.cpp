// Direct lighting: emission, point lights, emissive triangles (area lights)
// and a constant environment, each with shadow rays. No global illumination.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "raytrace/raytrace_internal.h"

namespace gdof::rt {

LightSampler::LightSampler(const Scene& scene) {
    double total = 0;
    for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const TriangleMesh& m = scene.meshes[mi];
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const Material& mat = scene.materials[m.material[t]];
            if (!mat.emissive()) continue;
            const Vec3 a = m.vertex(m.indices[3 * t]), b = m.vertex(m.indices[3 * t + 1]),
                       c = m.vertex(m.indices[3 * t + 2]);
            const double area = 0.5 * length(cross(b - a, c - a));
            const double w = area * std::max(luminance(mat.ke), 1e-6);
            if (!(area > 0)) continue;
            tris_.push_back({std::uint32_t(mi), std::uint32_t(t), area});
            total += w;
            cdf_.push_back(total);
        }
    }
    for (double& v : cdf_) v /= total;
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

namespace {
constexpr double kInvPi = 1.0 / std::numbers::pi;

// Offset of shadow-ray origins off the surface, relative to the scene scale.
double ray_epsilon(const Vec3& p) {
    return 1e-4 * std::max({1.0, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

// An orthonormal basis around n (Duff et al. 2017).
void basis(const Vec3& n, Vec3& t, Vec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), bb = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * bb, -sign * n.x};
    b = {bb, sign + n.y * n.y * a, -n.y};
}
}  // namespace

Vec3 LightSampler::shade(const RayTracer& rt, const SurfaceHit& s, const Vec3& dir, Rng& rng, int light_samples,
                         std::uint64_t& shadow_rays) const {
    const Scene& scene = rt.scene();
    const Material& mat = scene.materials[s.material];
    Vec3 out = mat.ke;
    const Vec3 f = mat.kd * kInvPi;  // Lambertian BRDF
    if (f.x <= 0 && f.y <= 0 && f.z <= 0) return out;
    const double eps = ray_epsilon(s.p);
    const Vec3 o = s.p + s.ng * eps;

    for (const PointLight& l : scene.point_lights) {
        Vec3 d = l.position - o;
        const double dist = length(d);
        if (!(dist > eps)) continue;
        d = d / dist;
        const double cs = dot(s.n, d);
        if (cs <= 0 || dot(s.ng, d) <= 0) continue;
        ++shadow_rays;
        if (rt.occluded(o, d, 0.0, dist * (1 - 1e-6))) continue;
        out = out + mul(f, l.intensity) * (cs / (dist * dist));
    }

    const int ns = std::max(1, light_samples);
    if (!tris_.empty()) {
        Vec3 sum{0, 0, 0};
        for (int k = 0; k < ns; ++k) {
            const double r0 = rng.next(), r1 = rng.next(), r2 = rng.next();
            const std::size_t i = std::size_t(std::lower_bound(cdf_.begin(), cdf_.end(), r0) - cdf_.begin());
            const Tri& tri = tris_[std::min(i, tris_.size() - 1)];
            const double p_tri = cdf_[i] - (i ? cdf_[i - 1] : 0.0);
            const TriangleMesh& m = scene.meshes[tri.mesh];
            const Vec3 a = m.vertex(m.indices[3 * tri.prim]), b = m.vertex(m.indices[3 * tri.prim + 1]),
                       c = m.vertex(m.indices[3 * tri.prim + 2]);
            const double su = std::sqrt(r1);
            const Vec3 q = a * (1 - su) + b * (su * (1 - r2)) + c * (su * r2);
            Vec3 d = q - o;
            const double dist2 = dot(d, d), dist = std::sqrt(dist2);
            if (!(dist > eps)) continue;
            d = d / dist;
            const double cs = dot(s.n, d);
            if (cs <= 0 || dot(s.ng, d) <= 0) continue;
            const Vec3 nl = normalize(cross(b - a, c - a));
            const double cl = std::abs(dot(nl, d));  // two-sided emitters
            if (cl <= 0) continue;
            ++shadow_rays;
            if (rt.occluded(o, d, 0.0, dist * (1 - 1e-4))) continue;
            const Vec3& ke = scene.materials[m.material[tri.prim]].ke;
            sum = sum + mul(f, ke) * (cs * cl * tri.area / (dist2 * p_tri));
        }
        out = out + sum / double(ns);
    }

    const Vec3& env = scene.environment;
    if (env.x > 0 || env.y > 0 || env.z > 0) {
        Vec3 t, b;
        basis(s.n, t, b);
        double visible = 0;
        for (int k = 0; k < ns; ++k) {  // cosine-weighted: f * L * cos / pdf = kd * L
            const double r1 = rng.next(), r2 = rng.next();
            const double rad = std::sqrt(r1), phi = 2 * std::numbers::pi * r2;
            const Vec3 d = t * (rad * std::cos(phi)) + b * (rad * std::sin(phi)) + s.n * std::sqrt(std::max(0.0, 1 - r1));
            if (dot(d, s.ng) <= 0) continue;
            ++shadow_rays;
            if (!rt.occluded(o, d, 0.0, std::numeric_limits<double>::infinity())) visible += 1;
        }
        out = out + mul(mat.kd, env) * (visible / ns);
    }
    return out;
}

}  // namespace gdof::rt
