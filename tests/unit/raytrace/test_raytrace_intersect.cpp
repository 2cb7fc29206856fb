// Embree intersection and occlusion against analytic ray-plane / ray-triangle results.
#include <cmath>

#include "gdof/raytrace.h"
#include "scene_test_helpers.h"

using namespace gdof;
using gdof::test::ScratchDir;

namespace {

// The plane scene: quad.obj scaled 10x, rotated 10 deg about z, at z = -1; lamp triangle at z = 2.
Scene plane_scene(const ScratchDir& dir) {
    gdof::test::write_quad_obj(dir);
    auto r = parse_scene(gdof::test::plane_scene_json(), dir.path().string());
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r).value() : Scene{};
}

// Barycentrics (u, v) of the point q of the plane of triangle (a, b, c), by 2D projection on x, y.
bool in_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q, double* u = nullptr, double* v = nullptr) {
    const double d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    const double uu = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
    const double vv = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
    if (u) *u = uu;
    if (v) *v = vv;
    return uu >= 0 && vv >= 0 && uu + vv <= 1;
}

void lamp_vertices(const Scene& s, Vec3& a, Vec3& b, Vec3& c) {
    const TriangleMesh& m = s.meshes[0];
    a = m.vertex(m.indices[6]), b = m.vertex(m.indices[7]), c = m.vertex(m.indices[8]);
}

#define REQUIRE_TRACER(var, scene)                                                       \
    auto var##_r = RayTracer::build(scene);                                              \
    if (!var##_r && var##_r.message().find("without Embree") != std::string::npos)       \
        GDOF_SKIP_OR_FAIL(var##_r.message());                                                \
    ASSERT_TRUE(var##_r) << var##_r.message();                                            \
    const RayTracer& var = *var##_r.value()

}  // namespace

TEST(raytrace_intersect, ray_plane_matches_analytic) {
    ScratchDir dir;
    const Scene scene = plane_scene(dir);
    REQUIRE_TRACER(rt, scene);
    // Oblique rays from above the plane z = -1; some pass through the lamp at z = 2.
    Vec3 la, lb, lc;
    lamp_vertices(scene, la, lb, lc);
    for (int k = 0; k < 20; ++k) {
        const Vec3 o{-2.0 + 0.2 * k, 1.5 - 0.1 * k, 4.0};
        const Vec3 d{0.3 - 0.02 * k, -0.1 + 0.015 * k, -1.0};
        const double t_plane = (-1.0 - o.z) / d.z;
        const Vec3 p = o + d * t_plane;
        RayHit h = rt.intersect(o, d, 0, std::numeric_limits<double>::infinity());
        ASSERT_TRUE(h.hit());
        // Rays through the lamp's footprint hit the lamp first (z = 2).
        const double t_lamp = (2.0 - o.z) / d.z;
        const Vec3 q = o + d * t_lamp;
        const bool lamp = in_triangle(la, lb, lc, q);
        const double t = lamp ? t_lamp : t_plane;
        EXPECT_NEAR(h.t, t, 1e-5 * t) << k;
        const SurfaceHit s = rt.surface(h, o, d);
        EXPECT_NEAR(s.p.z, lamp ? 2.0 : -1.0, 1e-5);
        if (!lamp) {
            EXPECT_NEAR(s.p.x, p.x, 1e-5);
        }
        EXPECT_NEAR(s.ng.z, 1.0, 1e-6);  // faces the incoming ray
        EXPECT_NEAR(s.n.z, 1.0, 1e-6);
        EXPECT_EQ(s.object_id, lamp ? 2u : 1u);
        // tfar before the surface: no hit; tnear past it: no hit either (nothing behind).
        EXPECT_FALSE(rt.intersect(o, d, 0, 0.99 * t).hit());
        EXPECT_FALSE(rt.intersect(o, d, t_plane * 1.01, std::numeric_limits<double>::infinity()).hit());
    }
}

TEST(raytrace_intersect, barycentrics_of_a_triangle) {
    ScratchDir dir;
    const Scene scene = plane_scene(dir);
    REQUIRE_TRACER(rt, scene);
    // The lamp triangle (world): P = A + u (B - A) + v (C - A).
    const double u = 0.25, v = 0.35;
    Vec3 A, B, C;
    lamp_vertices(scene, A, B, C);
    EXPECT_NEAR(A.z, 2.0, 1e-6);
    const Vec3 P = A + (B - A) * u + (C - A) * v;
    const Vec3 o = P + Vec3{0.5, -0.25, 3};
    const Vec3 d = P - o;  // hits at t = 1
    RayHit h = rt.intersect(o, d, 0, 10);
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 1.0, 1e-6);
    EXPECT_NEAR(h.u, u, 1e-5);
    EXPECT_NEAR(h.v, v, 1e-5);
    EXPECT_TRUE(scene.materials[scene.meshes[h.mesh].material[h.prim]].emissive());
    // From below, the geometric normal flips to face the ray.
    const Vec3 o2 = P + Vec3{0, 0, -0.5};
    RayHit h2 = rt.intersect(o2, {0, 0, 1}, 0, 10);
    ASSERT_TRUE(h2.hit());
    EXPECT_NEAR(h2.t, 0.5, 1e-6);
    EXPECT_NEAR(rt.surface(h2, o2, {0, 0, 1}).ng.z, -1.0, 1e-9);
}

TEST(raytrace_intersect, occlusion) {
    ScratchDir dir;
    const Scene scene = plane_scene(dir);
    REQUIRE_TRACER(rt, scene);
    const Vec3 o{0.5, 0.5, 1};
    EXPECT_TRUE(rt.occluded(o, {0, 0, -1}, 0, 5));     // the plane at t = 2
    EXPECT_FALSE(rt.occluded(o, {0, 0, -1}, 0, 1.9));  // stops short of it
    EXPECT_FALSE(rt.occluded(o, {0, 0, 1}, 0, 100));   // nothing above (the lamp is at x, y near 0)
    EXPECT_TRUE(rt.occluded({0, 0, 1}, {0, 0, 1}, 0, 100));  // the lamp
}
