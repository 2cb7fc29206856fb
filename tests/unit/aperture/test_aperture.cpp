// The aperture description: its CLI form both ways and its errors, and its
// geometry against analytic areas (the disc's pi, a regular polygon's
// N/2 sin(2 pi / N), squeeze dividing the area) and against the ray
// tracer's own sampler.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gdof/aperture.h"
#include "gdof/lens_rays.h"

using namespace gdof;

TEST(aperture, CliFormRoundTripsAndErrorsNameTheKey) {
    for (const char* spec : {"disc", "polygon:6", "polygon:5:12.5", "polygon:7:10,roundness=0.3,squeeze=1.33",
                             "disc,squeeze=2,cats_eye=0.5", "image:iris.png,rotation=30"}) {
        auto a = parse_aperture(spec);
        ASSERT_TRUE(a) << spec << ": " << a.message();
        EXPECT_EQ(format_aperture(*a), spec);
    }
    auto p = parse_aperture("polygon:7:10,roundness=0.3");
    ASSERT_TRUE(p);
    EXPECT_EQ(p->kind, Aperture::Kind::Polygon);
    EXPECT_EQ(p->blades, 7);
    EXPECT_DOUBLE_EQ(p->rotation_deg, 10.0);
    EXPECT_DOUBLE_EQ(p->roundness, 0.3);
    struct Bad {
        const char* spec;
        const char* subject;
        const char* message;
    };
    for (const Bad& b : {Bad{"polygon:2", "blades", "blades must be 3 to 64"}, Bad{"polygon:x", "blades", "not a whole number"},
                         Bad{"disc,roundness=2", "roundness", "roundness must be in [0, 1]"},
                         Bad{"disc,squeeze=nan", "squeeze", "expected key=number"},
                         Bad{"disc,cats_eye=-1", "cats_eye", "cats_eye must be in [0, 1]"},
                         Bad{"disc,petals=5", "petals", "unknown key 'petals'"}, Bad{"star", "", "unknown shape 'star'"},
                         Bad{"image:", "image", "expected image:FILE"}}) {
        auto a = parse_aperture(b.spec);
        ASSERT_FALSE(a) << b.spec;
        EXPECT_EQ(a.status().subject(), b.subject) << b.spec;
        EXPECT_NE(a.message().find(b.message), std::string::npos) << b.spec << ": " << a.message();
    }
}

TEST(aperture, ProfileAreasAreTheAnalyticOnes) {
    auto area = [](const std::string& spec) {
        auto p = ApertureProfile::create(*parse_aperture(spec));
        EXPECT_TRUE(p) << spec;
        return p->area();
    };
    EXPECT_NEAR(area("disc"), std::numbers::pi, 2e-3);
    for (int n : {3, 5, 6, 9}) {
        const double want = 0.5 * n * std::sin(2 * std::numbers::pi / n);
        EXPECT_NEAR(area("polygon:" + std::to_string(n) + ":17"), want, 3e-3) << n;
        // The ray tracer's polygon has the same area.
        EXPECT_NEAR(ApertureShape::polygon(n, 17)->area(), want, 1e-9);
    }
    EXPECT_NEAR(area("polygon:6,roundness=1"), std::numbers::pi, 2e-3);
    const double hex = 0.5 * 6 * std::sin(std::numbers::pi / 3);
    const double half = area("polygon:6,roundness=0.5");
    EXPECT_GT(half, hex);
    EXPECT_LT(half, std::numbers::pi);
    EXPECT_NEAR(area("disc,squeeze=2"), std::numbers::pi / 2, 2e-3);
    // A strip's average edges: the disc's row at v = 0 spans [-1, 1].
    auto d = ApertureProfile::create(Aperture{});
    double h, l, r;
    ASSERT_TRUE(d->strip(-0.001, 0.001, h, l, r));
    EXPECT_NEAR(l, -1.0, 1e-3);
    EXPECT_NEAR(r, 1.0, 1e-3);
    EXPECT_NEAR(h, 0.002, 1e-6);
    EXPECT_FALSE(d->strip(1.01, 1.2, h, l, r)) << "above the shape";
    // An image kernel has no row profile.
    Aperture img;
    img.kind = Aperture::Kind::Image;
    img.image = Image::with_channels({"Y"}, Roi{0, 0, 4, 4});
    img.image.at(0, 1, 1) = 1.0f;
    EXPECT_FALSE(ApertureProfile::create(img));
}

// The ray tracer's sampler of a rounded, squeezed polygon (a mask of the
// shape): every sample lies inside the shape, and they fill it uniformly
// (the mean of u^2 + v^2 matches the profile's shape integrated here).
TEST(aperture, RayTracerSamplesTheSameShape) {
    const Aperture a = *parse_aperture("polygon:5:20,roundness=0.4,squeeze=1.5");
    auto shape = aperture_shape(a);
    ASSERT_TRUE(shape) << shape.message();
    EXPECT_EQ(shape->kind(), ApertureShape::Kind::Mask);
    int outside = 0, n = 0;
    double m2 = 0;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j) {
            const Vec2 s = shape->map({(i + 0.5) / 100, (j + 0.5) / 100});
            // The mask is 512 px over [-1, 1]: allow one mask pixel.
            bool near_inside = false;
            for (double du : {-0.004, 0.0, 0.004})
                for (double dv : {-0.004, 0.0, 0.004}) near_inside |= aperture_contains(a, s.x + du, s.y + dv);
            outside += near_inside ? 0 : 1;
            m2 += s.x * s.x + s.y * s.y;
            ++n;
        }
    EXPECT_EQ(outside, 0);
    double ref = 0, cnt = 0;
    for (int i = 0; i < 800; ++i)
        for (int j = 0; j < 800; ++j) {
            const double u = -1 + (i + 0.5) / 400, v = -1 + (j + 0.5) / 400;
            if (aperture_contains(a, u, v)) ref += u * u + v * v, cnt += 1;
        }
    EXPECT_NEAR(m2 / n, ref / cnt, 0.01);
    // Disc and plain polygons keep the exact samplers; the cat's eye is an error.
    EXPECT_EQ(aperture_shape(Aperture{})->kind(), ApertureShape::Kind::Disc);
    EXPECT_EQ(aperture_shape(*parse_aperture("polygon:6:15"))->kind(), ApertureShape::Kind::Polygon);
    auto cats = aperture_shape(*parse_aperture("disc,cats_eye=0.5"));
    ASSERT_FALSE(cats);
    EXPECT_EQ(cats.status().subject(), "cats_eye");
}
