// The Embree 3 BVH and ray queries: the only file that includes Embree.
#include "gdof/raytrace.h"

#ifdef GDOF_WITH_EMBREE
#include <embree3/rtcore.h>
#endif

#include <cmath>
#include <limits>

namespace gdof {

#ifdef GDOF_WITH_EMBREE

struct RayTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayTracer::~RayTracer() = default;

Result<std::shared_ptr<const RayTracer>> RayTracer::build(const Scene& scene) {
    std::shared_ptr<RayTracer> rt(new RayTracer());
    rt->scene_ = &scene;
    rt->impl_ = std::make_unique<Impl>();
    Impl& im = *rt->impl_;
    im.device = rtcNewDevice(nullptr);
    if (!im.device) return Status::error("Embree: cannot create a device (error " +
                                         std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    im.scene = rtcNewScene(im.device);
    rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (mesh.triangle_count() == 0) continue;
        RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.vertex_count()));
        auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(unsigned), mesh.triangle_count()));
        if (!v || !ix) {
            rtcReleaseGeometry(g);
            return Status::error("Embree: out of memory for " + mesh.name);
        }
        std::copy(mesh.positions.begin(), mesh.positions.end(), v);
        std::copy(mesh.indices.begin(), mesh.indices.end(), ix);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(im.scene, g, unsigned(m));
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(im.scene);
    if (RTCError e = rtcGetDeviceError(im.device); e != RTC_ERROR_NONE)
        return Status::error("Embree: building the BVH failed (error " + std::to_string(int(e)) + ")");
    return std::shared_ptr<const RayTracer>(std::move(rt));
}

namespace {
// Embree (Debian's build keeps its assertions) aborts on a ray with a
// non-finite origin or direction after float conversion: such rays hit nothing.
bool valid_ray(const RTCRay& r) {
    const float v[] = {r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tnear};
    for (float x : v)
        if (!std::isfinite(x)) return false;
    return r.tnear >= 0 && !(r.tfar < r.tnear) && !std::isnan(r.tfar);
}

void set_ray(RTCRay& r, const Vec3& o, const Vec3& d, double tnear, double tfar) {
    r.org_x = float(o.x), r.org_y = float(o.y), r.org_z = float(o.z);
    r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
    r.tnear = float(tnear);
    r.tfar = std::isfinite(tfar) ? float(tfar) : std::numeric_limits<float>::infinity();
    r.time = 0;
    r.mask = unsigned(-1);
    r.id = 0;
    r.flags = 0;
}
}  // namespace

RayHit RayTracer::intersect(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayhit;
    set_ray(rayhit.ray, origin, dir, tnear, tfar);
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    if (!valid_ray(rayhit.ray)) return {};
    rtcIntersect1(impl_->scene, &context, &rayhit);
    RayHit h;
    if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.t = rayhit.ray.tfar;
    h.mesh = rayhit.hit.geomID;
    h.prim = rayhit.hit.primID;
    h.u = rayhit.hit.u;
    h.v = rayhit.hit.v;
    return h;
}

bool RayTracer::occluded(const Vec3& origin, const Vec3& dir, double tnear, double tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    set_ray(ray, origin, dir, tnear, tfar);
    if (!valid_ray(ray)) return false;
    rtcOccluded1(impl_->scene, &context, &ray);
    return ray.tfar == -std::numeric_limits<float>::infinity();
}

#else  // !GDOF_WITH_EMBREE

struct RayTracer::Impl {};
RayTracer::~RayTracer() = default;
Result<std::shared_ptr<const RayTracer>> RayTracer::build(const Scene&) {
    return Status::error("the ray tracer is not available: gdof was built without Embree (GDOF_WITH_EMBREE=OFF)");
}
RayHit RayTracer::intersect(const Vec3&, const Vec3&, double, double) const { return {}; }
bool RayTracer::occluded(const Vec3&, const Vec3&, double, double) const { return false; }

#endif

}  // namespace gdof
