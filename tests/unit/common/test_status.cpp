// Status codes and subjects: front ends react to what failed without reading
// message text, and a library error names the setting it is about.
#include <gtest/gtest.h>

#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/status.h"

namespace gdof {
namespace {

TEST(status, ErrorCarriesCodeAndSubject) {
    EXPECT_EQ(Status::ok().code(), StatusCode::Ok);
    Status s = Status::error("bad");
    EXPECT_EQ(s.code(), StatusCode::Failed);
    EXPECT_TRUE(s.subject().empty());
    s = Status::error("depth channel 'Q' not found", StatusCode::NotFound, "depth_channel");
    EXPECT_FALSE(s);
    EXPECT_EQ(s.code(), StatusCode::NotFound);
    EXPECT_EQ(s.subject(), "depth_channel");
    // Context keeps code and subject.
    s.prefix("reading 'a.exr'");
    EXPECT_EQ(s.message(), "reading 'a.exr': depth channel 'Q' not found");
    EXPECT_EQ(s.code(), StatusCode::NotFound);
    EXPECT_EQ(s.subject(), "depth_channel");
    // An error is never Ok, whatever code it is given.
    EXPECT_FALSE(Status::error("x", StatusCode::Ok));
    EXPECT_EQ(Status::cancelled("render").message(), "render cancelled");
    EXPECT_EQ(Status::cancelled().code(), StatusCode::Cancelled);
    EXPECT_STREQ(to_string(StatusCode::NotFound), "not found");
}

TEST(status, MissingCameraNamesTheFocalLength) {
    auto cam = resolve_camera(Metadata{}, Roi{0, 0, 8, 8});
    ASSERT_FALSE(cam);
    EXPECT_EQ(cam.status().code(), StatusCode::NotFound);
    EXPECT_EQ(cam.status().subject(), "focal_length_mm");
}

TEST(status, CancelledDefocusSaysCancelled) {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, Roi{0, 0, 32, 32});
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = 1.0f + float(x) / 8.0f;
        }
    CameraDesc d;
    d.display_window = img.display_window();
    auto cam = Camera::create(d);
    ASSERT_TRUE(cam);
    ThinLens lens;
    lens.image_width_px = 32;
    lens.f_number = 1.0;
    auto field = BlurField::from_thin_lens(lens);
    ASSERT_TRUE(field);
    ImageSet set;
    set.parts.emplace_back(std::move(img));
    Exec exec;
    exec.cancelled = [] { return true; };
    auto r = defocus(set, *field, *cam, DefocusOptions{}, nullptr, exec);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::Cancelled) << r.message();
}

}  // namespace
}  // namespace gdof
