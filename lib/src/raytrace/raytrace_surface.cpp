// Hit -> position, normals, material and object (no Embree here).
#include "gdof/raytrace.h"

namespace gdof {

SurfaceHit RayTracer::surface(const RayHit& hit, const Vec3& origin, const Vec3& dir) const {
    SurfaceHit s;
    const TriangleMesh& m = scene_->meshes[hit.mesh];
    const std::size_t t = hit.prim;
    const Vec3 a = m.vertex(m.indices[3 * t]), b = m.vertex(m.indices[3 * t + 1]), c = m.vertex(m.indices[3 * t + 2]);
    s.p = origin + dir * hit.t;
    Vec3 ng = cross(b - a, c - a);
    double l = length(ng);
    ng = l > 0 ? ng / l : Vec3{0, 0, 1};
    if (dot(ng, dir) > 0) ng = -ng;
    s.ng = ng;
    s.n = ng;
    if (!m.normals.empty()) {
        const float* n = &m.normals[9 * t];
        const double w = 1.0 - hit.u - hit.v;
        Vec3 ns{w * n[0] + hit.u * n[3] + hit.v * n[6], w * n[1] + hit.u * n[4] + hit.v * n[7],
                w * n[2] + hit.u * n[5] + hit.v * n[8]};
        double ln = length(ns);
        if (ln > 0) {
            ns = ns / ln;
            s.n = dot(ns, ng) < 0 ? -ns : ns;
        }
    }
    s.material = m.material[t];
    s.object_id = m.object_id[t];
    return s;
}

}  // namespace gdof
