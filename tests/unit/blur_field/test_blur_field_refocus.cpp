// BlurField::refocused: a focus picked from the picture moves every thin lens
// of a field, and nothing else.
#include <gtest/gtest.h>

#include "gdof/blur_field.h"

namespace gdof {
namespace {

Camera camera() {
    CameraDesc d;
    d.display_window = Roi{0, 0, 640, 360};
    d.handedness = Handedness::Left;
    return Camera::create(d).value();
}

TEST(blur_field_refocus, MovesTheThinLensFocusInsideCombinators) {
    const Camera cam = camera();
    auto f = BlurField::parse(R"({"blurfield": {"kind": "max", "children": [
        {"kind": "scale", "factor": 2, "child": {"kind": "thin_lens", "focal_length_mm": 50, "f_number": 2, "focus_distance": 3}},
        {"kind": "focal_planes", "depths": [10], "max_blur": 4, "slope": 1}]}})");
    ASSERT_TRUE(f) << f.message();
    auto g = f->refocused(1.5);
    ASSERT_TRUE(g) << g.message();
    const BlurField planes =
        BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [10], "max_blur": 4, "slope": 1}})").value();
    ThinLens l;
    l.focal_length_mm = 50, l.f_number = 2, l.focus_distance = 1.5, l.sensor_width_mm = 36, l.image_width_px = 640;
    for (double z : {0.8, 1.5, 2.5, 6.0}) {
        const double want = std::max(2.0 * l.coc_radius_px(z), double(planes.evaluate_pixel(cam, 320, 180, z)));
        EXPECT_NEAR(g->evaluate_pixel(cam, 320, 180, z), want, 1e-4 * std::max(1.0, want)) << z;
    }
    // Sharp at the new focus (the planes' part is 4 px there at most).
    EXPECT_LE(g->evaluate_pixel(cam, 320, 180, 1.5), 4.0f + 1e-4f);
    EXPECT_GT(f->evaluate_pixel(cam, 320, 180, 1.5), g->evaluate_pixel(cam, 320, 180, 1.5));
}

TEST(blur_field_refocus, NamesWhatCannotBeRefocused) {
    auto planes = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 5], "max_blur": 6}})");
    ASSERT_TRUE(planes);
    auto r = planes->refocused(3.0);
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("no thin_lens"), std::string::npos) << r.message();
    EXPECT_EQ(r.status().subject(), "focus_distance");
    ThinLens l;
    auto lens = BlurField::from_thin_lens(l);
    ASSERT_TRUE(lens);
    EXPECT_FALSE(lens->refocused(0.01));  // not beyond the 50 mm focal length
    EXPECT_FALSE(lens->refocused(-1.0));
    EXPECT_TRUE(lens->refocused(4.0));
}

}  // namespace
}  // namespace gdof
