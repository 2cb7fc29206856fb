// What the "gdof Defocus" tests share: the generated plate (96x64) in a
// test-host session with Source and Depth connected, the two-focal-planes
// field as parameters and as the CLI's JSON, and `gdof` run on the same
// plate written to EXR.
#pragma once

#include <string>

#include "ofx/ofx_test_support.h"

namespace gdof::test::defocus_fixture {

inline constexpr int W = 96, H = 64;
inline constexpr OfxPointD kFull{1, 1};

// Two focal planes (the disc at 2.2 and the far ground at 12), up to 6 px between, clamped at 8 px.
inline const char* const kPlanesJson = R"({"blurfield": {"kind": "focal_planes", "depths": [2.2, 12], "max_blur": 6, "slope": 3,
                               "interpolation": "smooth"}, "max_radius": 8})";

inline void set_planes(Instance& fx) {
    fx.set_choice("kind", "focal_planes");
    fx.set_int("depths_count", 2);
    fx.set("depths_1", 2.2);
    fx.set("depths_2", 12);
    fx.set("max_blur", 6);
    fx.set("slope", 3);
    fx.set_choice("interpolation", "smooth");
    fx.set("max_radius", 8);
}

struct Fixture {
    Plate plate = make_plate(W, H);
    Session s{kDefocusId, W, H};
    ScratchDir dir;
    Fixture() {
        if (!s.ok()) return;
        s.fx->connect("Source", plate_clip(plate, "rgba"));
        s.fx->connect("Depth", plate_clip(plate, "depth"));
        s.fx->set_choice("depth_channel", "A");
    }
    // gdof --diffuse on the plate (no camera attributes: the lens flags give the camera).
    std::string cli(const std::string& field_json, const std::string& extra = "", bool with_p = false,
                    const std::string& op = "--diffuse") {
        const std::string in = dir.file("plate.exr"), field = dir.file("field.json"), out = dir.file("cli.exr");
        write_plate(plate, in, with_p);
        write_text(field, field_json);
        auto r = run_gdof(quote(in) + " --focal-length-mm 50 --sensor-width-mm 36 " + extra + " --blurfield " +
                          quote(field) + " " + op + " -o " + quote(out));
        EXPECT_EQ(r.exit_code, 0) << r.output;
        return out;
    }
};

// The whole frame, then its four quadrants one after the other, then the
// quadrants from several threads, each render checked to succeed.
struct TiledRenders {
    Rendered whole, tiled, concurrent;
};
inline TiledRenders render_tiled(Instance& fx) {
    TiledRenders r;
    r.whole = fx.render(0, kFull);
    EXPECT_EQ(r.whole.status, kOfxStatOK) << fx.persistent_message();
    r.tiled = fx.render(0, kFull, quadrants(r.whole.bounds));
    EXPECT_EQ(r.tiled.status, kOfxStatOK) << fx.persistent_message();
    r.concurrent = fx.render(0, kFull, quadrants(r.whole.bounds), true);
    EXPECT_EQ(r.concurrent.status, kOfxStatOK) << fx.persistent_message();
    return r;
}

}  // namespace gdof::test::defocus_fixture
