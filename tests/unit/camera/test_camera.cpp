// Camera: projection conventions, round trips (also through EXR metadata and
// both forward-axis conventions), central rays, depth encodings, depth -> P.
#include <cmath>
#include <numbers>
#include <limits>
#include <random>

#include "gdof/camera.h"
#include "test_support.h"

using namespace gdof;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

CameraDesc base_desc(ForwardAxis axis = ForwardAxis::PosZ) {
    CameraDesc d;
    d.position = {1.0, 2.0, 3.0};
    d.look_at = {4.0, 1.5, -6.0};
    d.up = {0.1, 1.0, 0.0};
    d.focal_length_mm = 35;
    d.sensor_width_mm = 36;
    d.display_window = {-10, 20, 630, 500};  // 640 x 480, offset origin
    d.forward_axis = axis;
    d.f_number = 2.8;
    d.focus_distance = 3.5;
    return d;
}

Camera make(const CameraDesc& d) {
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c ? c.value() : Camera();
}


// world -> pixel -> world and pixel/depth -> world -> pixel/depth across the
// image and depths 1e-2 .. 1e4, relative error <= tol.
void check_round_trips(const Camera& cam, double tol = 1e-5) {
    const Roi& dw = cam.display_window();
    for (double depth : {1e-2, 0.1, 1.0, 7.5, 100.0, 1e3, 1e4})
        for (double fy : {0.0, 0.13, 0.5, 0.77, 1.0})
            for (double fx : {0.0, 0.31, 0.5, 0.9, 1.0}) {
                const double px = dw.x0 + fx * dw.width(), py = dw.y0 + fy * dw.height();
                const Vec3 w = cam.unproject(px, py, depth);
                const PixelDepth pd = cam.project(w);
                EXPECT_NEAR(pd.x, px, tol * std::max(1.0, std::fabs(px)));
                EXPECT_NEAR(pd.y, py, tol * std::max(1.0, std::fabs(py)));
                EXPECT_NEAR(pd.depth, depth, tol * depth);
                const Vec3 w2 = cam.unproject(pd.x, pd.y, pd.depth);
                EXPECT_LE(length(w2 - w), tol * std::max(depth, length(w - cam.position())))
                    << "depth " << depth << " px " << px << " py " << py;
            }
}

}  // namespace

// The camera built from lens flags for a plate: world = camera space, so
// world +x is right and +y up in the image (the OpenEXR / RenderMan
// worldToCamera convention, docs/camera.md), by hand-computed pixels.
TEST(camera, FlagsCameraShowsWorldPlusXOnTheRight) {
    LensOverrides ov;
    ov.focal_length_mm = 50.0;
    ov.sensor_width_mm = 36.0;
    auto cam = resolve_camera(Metadata{}, Roi{0, 0, 1920, 1080}, ov);
    ASSERT_TRUE(cam) << cam.message();
    const double fpx = 50.0 / 36.0 * 1920.0;  // 2666.67
    EXPECT_NEAR(cam->focal_length_px(), fpx, 1e-9);
    // (0.5, 0, 2): 0.25 focal lengths right of the centre.
    PixelDepth p = cam->project({0.5, 0.0, 2.0});
    EXPECT_NEAR(p.x, 960.0 + fpx * 0.25, 1e-6);
    EXPECT_NEAR(p.y, 540.0, 1e-6);
    EXPECT_NEAR(p.depth, 2.0, 1e-12);
    // (0, 0.3, 2): above the centre (pixel y grows downwards).
    p = cam->project({0.0, 0.3, 2.0});
    EXPECT_NEAR(p.x, 960.0, 1e-6);
    EXPECT_NEAR(p.y, 540.0 - fpx * 0.15, 1e-6);
    // Its worldToCamera is the identity.
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(cam->world_to_camera().m[i][j], i == j ? 1.0 : 0.0, 1e-12);
    // And unproject is the inverse: the right half of the image is +x.
    const Vec3 w = cam->unproject(1500.0, 540.0, 3.0);
    EXPECT_GT(w.x, 0.0);
    EXPECT_NEAR(w.z, 3.0, 1e-12);
}

// A scene camera (right-handed world, as OBJ files and scene JSON): looking
// down -z, world +x is on the right; looking down +z it is on the left.
TEST(camera, RightHandedSceneCameraKeepsOBJConventions) {
    CameraDesc d;
    d.display_window = Roi{0, 0, 200, 100};
    d.position = {0, 0, 5};
    d.look_at = {0, 0, 0};
    auto c = Camera::create(d);
    ASSERT_TRUE(c);
    EXPECT_GT(c->project({1, 0, 0}).x, 100.0);
    EXPECT_LT(c->project({0, 1, 0}).y, 50.0);
    d.position = {0, 0, -5};
    c = Camera::create(d);
    ASSERT_TRUE(c);
    EXPECT_LT(c->project({1, 0, 0}).x, 100.0);
    d.handedness = Handedness::Left;  // the same look in a left-handed world
    c = Camera::create(d);
    ASSERT_TRUE(c);
    EXPECT_GT(c->project({1, 0, 0}).x, 100.0);
    EXPECT_LT(c->project({0, 1, 0}).y, 50.0);
}

TEST(camera, HandProjectionLookingDownMinusZ) {
    // Camera at the origin looking down world -z, up +y: right is world +x.
    CameraDesc d;
    d.position = {0, 0, 0};
    d.look_at = {0, 0, -1};
    d.up = {0, 1, 0};
    d.focal_length_mm = 50;
    d.sensor_width_mm = 36;
    d.display_window = {0, 0, 1920, 1080};
    const Camera cam = make(d);
    // fx = 50/36 * 1920 = 2666.666...; point (0.1, 0.05, -2): x/z = 0.05, y/z = 0.025.
    // pixel x = 960 + 2666.67 * 0.05 = 1093.333; pixel y = 540 - 2666.67 * 0.025 = 473.333 (y down)
    const PixelDepth p = cam.project({0.1, 0.05, -2.0});
    EXPECT_NEAR(p.x, 960.0 + 50.0 / 36.0 * 1920.0 * 0.05, 1e-9);
    EXPECT_NEAR(p.y, 540.0 - 50.0 / 36.0 * 1920.0 * 0.025, 1e-9);
    EXPECT_NEAR(p.depth, 2.0, 1e-12);
    EXPECT_NEAR(cam.focal_length_px(), 50.0 / 36.0 * 1920.0, 1e-9);
    EXPECT_NEAR(cam.hfov_deg(), 2.0 * std::atan(18.0 / 50.0) * 180.0 / std::numbers::pi, 1e-9);
    EXPECT_NEAR(cam.pixel_footprint(2.0), 2.0 / cam.focal_length_px(), 1e-12);
    // worldToCamera (+z forward): a point in front has positive camera z.
    const Vec3 pc = cam.world_to_camera().transform_point({0.1, 0.05, -2.0});
    EXPECT_NEAR(pc.z, 2.0, 1e-12);
    EXPECT_NEAR(pc.x, 0.1, 1e-12);  // x right
    EXPECT_NEAR(pc.y, 0.05, 1e-12); // y up
    // worldToNDC: top-left corner (0,0), bottom-right (1,1), y down.
    const Vec3 tl = cam.world_to_ndc().transform_point(cam.unproject(0, 0, 3.0));
    const Vec3 br = cam.world_to_ndc().transform_point(cam.unproject(1920, 1080, 3.0));
    EXPECT_NEAR(tl.x, 0, 1e-12);
    EXPECT_NEAR(tl.y, 0, 1e-12);
    EXPECT_NEAR(br.x, 1, 1e-12);
    EXPECT_NEAR(br.y, 1, 1e-12);
    // NegZ convention: the same point has camera z = -2.
    d.forward_axis = ForwardAxis::NegZ;
    const Camera cn = make(d);
    EXPECT_NEAR(cn.world_to_camera().transform_point({0.1, 0.05, -2.0}).z, -2.0, 1e-12);
    EXPECT_NEAR(cn.project({0.1, 0.05, -2.0}).x, p.x, 1e-9);
}

TEST(camera, RenderManStyleMatricesFromMetadata) {
    // worldToCamera = identity (camera at origin, +z forward, x right, y up),
    // worldToNDC built by hand: ndc.x = 0.5 + a x / z, ndc.y = 0.5 - a (W/H) y / z, a = 1.
    Metadata md;
    md.set_matrix("worldToCamera", Mat44::identity());
    const double a = 1.0, W = 200, H = 100;
    const double v[16] = {a, 0, 0, 0, 0, -a * W / H, 0, 0, 0.5, 0.5, 0, 1, 0, 0, 1, 0};
    md.set_matrix("worldToNDC", Mat44::from_row_major(v));
    auto cam = Camera::from_metadata(md, {0, 0, 200, 100});
    ASSERT_TRUE(cam) << cam.message();
    EXPECT_EQ(cam->forward_axis(), ForwardAxis::PosZ);
    EXPECT_EQ(cam->projection(), Projection::Perspective);
    // (0.2, 0.1, 2): ndc = (0.5 + 0.1, 0.5 - 2 * 0.05) = (0.6, 0.4) -> pixel (120, 40)
    const PixelDepth p = cam->project({0.2, 0.1, 2.0});
    EXPECT_NEAR(p.x, 120.0, 1e-12);
    EXPECT_NEAR(p.y, 40.0, 1e-12);
    EXPECT_NEAR(p.depth, 2.0, 1e-12);
    // Central ray of the centre pixel position looks along +z.
    const CameraRay r = cam->central_ray(100.0, 50.0);
    EXPECT_NEAR(r.direction.z, 1.0, 1e-12);
    check_round_trips(*cam);
}

TEST(camera, CentreRayIsLookDirection) {
    for (ForwardAxis axis : {ForwardAxis::PosZ, ForwardAxis::NegZ}) {
        CameraDesc d = base_desc(axis);
        d.display_window = {0, 0, 640, 480};
        const Camera cam = make(d);
        const CameraRay r = cam.central_ray(320.0, 240.0);
        const Vec3 look = normalize(d.look_at - d.position);
        EXPECT_LT(length(r.direction - look), 1e-12);
        EXPECT_LT(length(r.origin - d.position), 1e-12);
        EXPECT_NEAR(r.depth_per_t, 1.0, 1e-12);
        EXPECT_LT(length(cam.forward() - look), 1e-12);
        // An off-centre ray: depth = t * depth_per_t matches project().
        const CameraRay q = cam.central_ray(10.5, 470.5);
        const Vec3 p = q.at(5.0);
        const PixelDepth pd = cam.project(p);
        EXPECT_NEAR(pd.depth, 5.0 * q.depth_per_t, 1e-10);
        EXPECT_NEAR(pd.x, 10.5, 1e-9);
        EXPECT_NEAR(pd.y, 470.5, 1e-9);
        EXPECT_NEAR(length(q.direction), 1.0, 1e-12);
    }
}

TEST(camera, RoundTripsExplicitAndThroughMetadata) {
    for (ForwardAxis axis : {ForwardAxis::PosZ, ForwardAxis::NegZ}) {
        SCOPED_TRACE(to_string(axis));
        const Camera cam = make(base_desc(axis));
        check_round_trips(cam);
        Metadata md;
        cam.to_metadata(md);
        EXPECT_TRUE(md.has("worldToCamera"));
        EXPECT_TRUE(md.has("worldToNDC"));
        auto back = Camera::from_metadata(md, cam.display_window());
        ASSERT_TRUE(back) << back.message();
        EXPECT_EQ(back->forward_axis(), axis);
        check_round_trips(*back);
        // Same projection as the original.
        for (double depth : {0.05, 3.0, 5e3}) {
            const Vec3 w = cam.unproject(100.25, 300.75, depth);
            const PixelDepth a = cam.project(w), b = back->project(w);
            EXPECT_NEAR(a.x, b.x, 1e-6);
            EXPECT_NEAR(a.y, b.y, 1e-6);
            EXPECT_NEAR(a.depth, b.depth, 1e-9 * depth);
        }
        // Lens attributes survive.
        EXPECT_NEAR(back->lens().focal_length_mm, 35.0, 1e-12);
        EXPECT_NEAR(back->lens().f_number, 2.8, 1e-12);
        EXPECT_NEAR(back->lens().focus_distance, 3.5, 1e-12);
        EXPECT_NEAR(back->lens().sensor_width_mm, 36.0, 1e-12);
    }
}

TEST(camera, FloatMatricesAndAutoDetectedForwardAxis) {
    // EXR stores M44f: round the matrices to float, drop our own
    // gdof:forwardAxis hint, and let Auto detect the convention.
    for (ForwardAxis axis : {ForwardAxis::PosZ, ForwardAxis::NegZ}) {
        SCOPED_TRACE(to_string(axis));
        const Camera cam = make(base_desc(axis));
        Metadata md;
        cam.to_metadata(md);
        md.erase("gdof:forwardAxis");
        for (const char* name : {"worldToCamera", "worldToNDC"}) {
            Mat44 m = *md.get_matrix(name);
            for (auto& row : m.m)
                for (double& v : row) v = double(float(v));
            md.set_matrix(name, m);
        }
        auto back = Camera::from_metadata(md, cam.display_window());
        ASSERT_TRUE(back) << back.message();
        EXPECT_EQ(back->forward_axis(), axis);
        check_round_trips(*back);
        // Float rounding moves the projection by a tiny amount only.
        const Vec3 w = cam.unproject(50.0, 60.0, 10.0);
        EXPECT_NEAR(back->project(w).x, 50.0, 1e-3);
        EXPECT_NEAR(back->project(w).depth, 10.0, 1e-5);
        // Forcing the wrong convention flips depth sign: the explicit option wins.
        CameraReadOptions o;
        o.forward_axis = axis == ForwardAxis::PosZ ? ForwardAxis::NegZ : ForwardAxis::PosZ;
        auto wrong = Camera::from_metadata(md, cam.display_window(), o);
        ASSERT_TRUE(wrong);
        EXPECT_NEAR(wrong->project(w).depth, -10.0, 1e-5);
    }
}

TEST(camera, Orthographic) {
    for (ForwardAxis axis : {ForwardAxis::PosZ, ForwardAxis::NegZ}) {
        CameraDesc d = base_desc(axis);
        d.projection = Projection::Orthographic;
        d.ortho_width = 8.0;
        const Camera cam = make(d);
        EXPECT_EQ(cam.projection(), Projection::Orthographic);
        check_round_trips(cam);
        // Parallel rays: pixel footprint independent of depth = width / pixels.
        EXPECT_NEAR(cam.pixel_footprint(1.0), 8.0 / 640.0, 1e-12);
        EXPECT_NEAR(cam.pixel_footprint(100.0), 8.0 / 640.0, 1e-12);
        Metadata md;
        cam.to_metadata(md);
        auto back = Camera::from_metadata(md, cam.display_window());
        ASSERT_TRUE(back) << back.message();
        EXPECT_EQ(back->projection(), Projection::Orthographic);
        EXPECT_EQ(back->forward_axis(), axis);  // from the gdof:forwardAxis hint
        check_round_trips(*back);
    }
}

TEST(camera, LensAttributesAndPartialMetadata) {
    const Camera cam = make(base_desc());
    Metadata md;
    md.set_matrix("worldToCamera", cam.world_to_camera());
    md.set_float("focalLength", 35.0);
    md.set_float("sensorWidth", 36.0);
    md.set_float("aperture", 4.0);  // OpenEXR standard: f-stops
    md.set_float("focus", 2.5);     // OpenEXR standard: metres
    // No worldToNDC: built from focal length and sensor width.
    auto c = Camera::from_metadata(md, cam.display_window());
    ASSERT_TRUE(c) << c.message();
    const Vec3 w = cam.unproject(123.0, 321.0, 4.0);
    EXPECT_NEAR(c->project(w).x, 123.0, 1e-9);
    EXPECT_NEAR(c->project(w).y, 321.0, 1e-9);
    EXPECT_NEAR(c->lens().f_number, 4.0, 0);
    EXPECT_NEAR(c->lens().focus_distance, 2.5, 1e-12);
    // Scene units in centimetres: focus 2.5 m = 250 scene units.
    CameraReadOptions cm;
    cm.scene_unit_mm = 10;
    auto c2 = Camera::from_metadata(md, cam.display_window(), cm);
    ASSERT_TRUE(c2);
    EXPECT_NEAR(c2->lens().focus_distance, 250.0, 1e-9);
    auto tl = c->thin_lens();
    ASSERT_TRUE(tl) << tl.message();
    EXPECT_EQ(tl->image_width_px, 640.0);
    // Errors name what is missing.
    Metadata empty;
    auto e = Camera::from_metadata(empty, {0, 0, 10, 10});
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("worldToCamera"), std::string::npos) << e.message();
    Metadata no_focal;
    no_focal.set_matrix("worldToCamera", Mat44::identity());
    auto e2 = Camera::from_metadata(no_focal, {0, 0, 10, 10});
    ASSERT_FALSE(e2);
    EXPECT_NE(e2.message().find("focalLength"), std::string::npos) << e2.message();
    Metadata singular;
    Mat44 z;
    z.m[0][0] = 0;
    singular.set_matrix("worldToCamera", z);
    singular.set_matrix("worldToNDC", Mat44::identity());
    auto e3 = Camera::from_metadata(singular, {0, 0, 10, 10});
    ASSERT_FALSE(e3);
    EXPECT_NE(e3.message().find("singular"), std::string::npos) << e3.message();
    Camera nolens = make(base_desc());
    nolens.set_lens({});
    EXPECT_FALSE(nolens.thin_lens());
}

TEST(camera, ExplicitDescErrors) {
    CameraDesc d = base_desc();
    d.look_at = d.position;
    EXPECT_NE(Camera::create(d).message().find("look_at"), std::string::npos);
    d = base_desc();
    d.up = d.look_at - d.position;
    EXPECT_NE(Camera::create(d).message().find("up"), std::string::npos);
    d = base_desc();
    d.focal_length_mm = -1;
    EXPECT_NE(Camera::create(d).message().find("focal_length_mm"), std::string::npos);
    d = base_desc();
    d.display_window = {0, 0, 0, 10};
    EXPECT_NE(Camera::create(d).message().find("display_window"), std::string::npos);
    d = base_desc();
    d.hfov_deg = 90;
    auto c = Camera::create(d);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->hfov_deg(), 90.0, 1e-9);
    EXPECT_NEAR(c->focal_length_px(), 320.0, 1e-9);
}

TEST(camera, DepthEncodings) {
    DepthDecode m;  // metric; invalid values are holes (NaN) unless marked sky
    EXPECT_EQ(decode_depth(2.5, m), 2.5);
    EXPECT_TRUE(std::isnan(decode_depth(0.0, m)));
    EXPECT_TRUE(std::isinf(decode_depth(kInf, m)));  // an explicit infinity is sky
    EXPECT_TRUE(std::isnan(decode_depth(std::nan(""), m)));
    EXPECT_TRUE(std::isnan(decode_depth(-1.0, m)));
    EXPECT_TRUE(std::isnan(decode_depth(-kInf, m)));
    m.invalid = kInf;  // the user marks invalid as sky
    EXPECT_TRUE(std::isinf(decode_depth(0.0, m)));
    EXPECT_TRUE(std::isinf(decode_depth(std::nan(""), m)));
    m.invalid = std::numeric_limits<double>::quiet_NaN();
    m.invalid_value = 65.0;  // a value the user names
    EXPECT_TRUE(std::isnan(decode_depth(65.0, m)));
    EXPECT_EQ(decode_depth(64.0, m), 64.0);
    m.max_depth = 10.0;  // a sensor's range
    EXPECT_TRUE(std::isnan(decode_depth(12.0, m)));
    EXPECT_TRUE(std::isinf(decode_depth(kInf, m)));
    m.max_depth = -1.0;
    EXPECT_FALSE(m.validate());
    EXPECT_EQ(m.validate().subject(), "depth_max");

    DepthDecode tum_raw{DepthEncoding::Scaled, 1.0 / 5000.0};
    EXPECT_NEAR(decode_depth(5000.0, tum_raw), 1.0, 1e-15);  // TUM: metres = counts / 5000
    EXPECT_TRUE(std::isnan(decode_depth(0.0, tum_raw)));   // 0 = no measurement: a hole, not sky
    DepthDecode tum_norm{DepthEncoding::Scaled, 65535.0 / 5000.0};
    EXPECT_NEAR(decode_depth(5000.0 / 65535.0, tum_norm), 1.0, 1e-12);  // normalised read

    // Disparity: depth = f_px * baseline / d; 0 is unknown.
    DepthDecode disp{DepthEncoding::Disparity, 700.0 * 0.1};  // scale = f_px * baseline
    EXPECT_NEAR(decode_depth(35.0, disp), 2.0, 1e-12);
    EXPECT_TRUE(std::isnan(decode_depth(0.0, disp)));
    CameraDesc cd;
    cd.display_window = Roi{0, 0, 1400, 800};
    cd.focal_length_mm = 18.0;
    cd.sensor_width_mm = 36.0;  // f_px = 700
    cd.handedness = Handedness::Left;
    const Camera cam = Camera::create(cd).value();
    DepthDecode withb{DepthEncoding::Disparity};
    withb.baseline = 0.1;
    EXPECT_FALSE(withb.validate());  // needs the camera's focal length
    auto resolved = resolve_depth_decode(withb, cam);
    ASSERT_TRUE(resolved) << resolved.message();
    EXPECT_NEAR(resolved->focal_px, 700.0, 1e-9);
    EXPECT_NEAR(decode_depth(35.0, *resolved), 2.0, 1e-12);
    DepthDecode mb;
    mb.baseline = 0.1;
    EXPECT_FALSE(resolve_depth_decode(mb, cam));  // a baseline only with disparity
    EXPECT_EQ(*parse_depth_encoding("disparity"), DepthEncoding::Disparity);

    DepthDecode inv{DepthEncoding::Inverse, 1.0};
    EXPECT_NEAR(decode_depth(0.25, inv), 4.0, 1e-15);
    EXPECT_TRUE(std::isinf(decode_depth(0.0, inv)));
    inv.scale = 2.0;  // value = scale / Z
    EXPECT_NEAR(decode_depth(0.5, inv), 4.0, 1e-15);

    DepthDecode lin{DepthEncoding::NearFarLinear};
    lin.near = 1, lin.far = 11;
    EXPECT_TRUE(lin.validate());
    EXPECT_NEAR(decode_depth(0.0, lin), 1.0, 1e-15);
    EXPECT_NEAR(decode_depth(0.5, lin), 6.0, 1e-15);
    lin.flip = true;
    EXPECT_NEAR(decode_depth(0.0, lin), 11.0, 1e-15);
    DepthDecode invnf{DepthEncoding::NearFarInverse};
    invnf.near = 1, invnf.far = 4;
    // 1/d = 1 + 0.5 * (1/4 - 1) = 0.625 -> d = 1.6
    EXPECT_NEAR(decode_depth(0.5, invnf), 1.6, 1e-15);
    EXPECT_NEAR(decode_depth(1.0, invnf), 4.0, 1e-15);
    invnf.far = kInf;  // allowed: v = 1 is infinitely far
    EXPECT_TRUE(invnf.validate());
    EXPECT_TRUE(std::isinf(decode_depth(1.0, invnf)));
    DepthDecode bad{DepthEncoding::NearFarLinear};
    EXPECT_NE(bad.validate().message().find("near"), std::string::npos);
    EXPECT_EQ(*parse_depth_encoding("near_far_inverse"), DepthEncoding::NearFarInverse);
    EXPECT_FALSE(parse_depth_encoding("zbuffer"));
    std::vector<float> plane = {5000.f, 0.f, 10000.f};
    decode_depth(plane, tum_raw);
    EXPECT_FLOAT_EQ(plane[0], 1.f);
    EXPECT_TRUE(std::isnan(plane[1]));
    EXPECT_FLOAT_EQ(plane[2], 2.f);
}

TEST(camera, DepthMapToPositionsMatchesGroundTruth) {
    // Camera at the origin looking down -z; a wall at world z = -5 fills the view:
    // depth is 5 everywhere and the ground-truth point of pixel (i, j) is
    // ((i + 0.5 - cx) * 5 / fx, -(j + 0.5 - cy) * 5 / fx, -5).
    CameraDesc d;
    d.position = {0, 0, 0};
    d.look_at = {0, 0, -1};
    d.display_window = {0, 0, 64, 48};
    d.focal_length_mm = 40;
    d.sensor_width_mm = 36;
    const Camera cam = make(d);
    const double fx = 40.0 / 36.0 * 64.0;
    // Data window partly outside the display window, negative origin.
    Image depth = Image::with_channels({"Z"}, {-4, -2, 70, 40});
    depth.set_display_window(d.display_window);
    for (int y = -2; y < 40; ++y)
        for (int x = -4; x < 70; ++x) depth.at(0, x, y) = 5.0f;
    depth.at(0, 3, 3) = 0.0f;  // invalid
    auto P = depth_to_positions(depth, 0, cam);
    ASSERT_TRUE(P) << P.message();
    EXPECT_EQ(P->data_window(), depth.data_window());
    EXPECT_EQ(P->display_window(), depth.display_window());
    const int ix = P->channel_index("P.x"), iy = P->channel_index("P.y"), iz = P->channel_index("P.z");
    ASSERT_GE(ix, 0);
    for (int y = -2; y < 40; y += 3)
        for (int x = -4; x < 70; x += 5) {
            if (x == 3 && y == 3) continue;
            EXPECT_NEAR(P->at(ix, x, y), (x + 0.5 - 32.0) * 5.0 / fx, 1e-5);
            EXPECT_NEAR(P->at(iy, x, y), -(y + 0.5 - 24.0) * 5.0 / fx, 1e-5);
            EXPECT_NEAR(P->at(iz, x, y), -5.0, 1e-5);
        }
    EXPECT_TRUE(std::isnan(P->at(ix, 3, 3)));
    // Range (distance along the ray) instead of planar depth: same points.
    Image range = depth;
    for (int y = -2; y < 40; ++y)
        for (int x = -4; x < 70; ++x) {
            const double u = (x + 0.5 - 32.0) / fx, v = (y + 0.5 - 24.0) / fx;
            range.at(0, x, y) = float(5.0 * std::sqrt(1 + u * u + v * v));
        }
    DepthDecode r;
    r.range = true;
    auto P2 = depth_to_positions(range, 0, cam, r);
    ASSERT_TRUE(P2);
    for (int y = -2; y < 40; y += 7)
        for (int x = -4; x < 70; x += 9) {
            if (x == 3 && y == 3) continue;
            EXPECT_NEAR(P2->at(iz, x, y), -5.0, 1e-5);
            EXPECT_NEAR(P2->at(ix, x, y), (x + 0.5 - 32.0) * 5.0 / fx, 1e-5);
        }
    EXPECT_FALSE(depth_to_positions(depth, 1, cam));
}
