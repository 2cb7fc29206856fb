// Shared pieces of the OFX plugin tests: the built bundle, a host session
// with the plugin described and an instance created, a generated plate
// (RGBA + depth) written to EXR for the CLI and handed to the host as clip
// images, and comparisons between host renders and EXR files.
#pragma once

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "cli/cli_test_helpers.h"
#include "ofx/ofx_test_host.h"

namespace gdof::test {

using ofxtest::ClipFrame;
using ofxtest::Host;
using ofxtest::Instance;
using ofxtest::Rendered;

inline const char* kDefocusId = "org.gdof.Defocus";
inline const char* kFocalStackId = "org.gdof.FocalStack";

// The plugin binary inside the built bundle ($GDOF_OFX_BUNDLE overrides: the
// install test points it at the installed one).
inline std::string bundle_binary() {
    if (const char* e = std::getenv("GDOF_OFX_BUNDLE")) return e;
    return GDOF_OFX_PATH;
}

// A host with the bundle loaded, one plugin described (both contexts) and
// an instance in `context` for a project of w x h pixels.
struct Session {
    Host host;
    std::unique_ptr<Instance> fx;
    Session(const std::string& id, int w, int h, const std::string& context = kOfxImageEffectContextGeneral) {
        std::string err;
        if (!host.load(bundle_binary(), &err)) {
            ADD_FAILURE() << "loading " << bundle_binary() << ": " << err;
            return;
        }
        EXPECT_EQ(host.describe(id), kOfxStatOK);
        EXPECT_EQ(host.describe_in_context(id, kOfxImageEffectContextFilter), kOfxStatOK);
        EXPECT_EQ(host.describe_in_context(id, kOfxImageEffectContextGeneral), kOfxStatOK);
        fx = host.create_instance(id, context, w, h);
        if (!fx) {
            ADD_FAILURE() << "no instance of " << id;
            return;
        }
        EXPECT_EQ(fx->create_status(), kOfxStatOK);
    }
    bool ok() const { return fx != nullptr; }
};

// A generated live-action-like plate, top row first (as in EXR): a ground
// plane receding from depth 3 (bottom) to 25 (top) with a checker texture, a
// box at depth 6 and a disc at depth 2.2 in front, all opaque.
struct Plate {
    int w = 0, h = 0;
    std::vector<float> rgba;  // premultiplied, 4 per pixel
    std::vector<float> z;
    std::vector<float> p;     // world positions (camera at the origin looking down +z), 3 per pixel
    float at(int x, int y, int c) const { return rgba[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4 + std::size_t(c)]; }
};

inline Plate make_plate(int w, int h, double focal_length_mm = 50, double sensor_width_mm = 36) {
    Plate pl;
    pl.w = w;
    pl.h = h;
    pl.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
    pl.z.resize(std::size_t(w) * std::size_t(h));
    pl.p.resize(std::size_t(w) * std::size_t(h) * 3);
    const double fpx = focal_length_mm / sensor_width_mm * w;  // focal length in pixels
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            double z = 3.0 * std::pow(25.0 / 3.0, 1.0 - double(y) / (h - 1));
            float r = ((x / 6 + y / 4) % 2) ? 0.9f : 0.2f, g = 0.5f + 0.4f * float(x) / float(w), b = 0.3f;
            const double dx = x - 0.3 * w, dy = y - 0.55 * h;
            if (x > 0.55 * w && x < 0.8 * w && y > 0.2 * h && y < 0.6 * h) {  // a box
                z = 6.0;
                r = 0.1f, g = ((x / 3) % 2) ? 0.2f : 0.8f, b = 0.9f;
            }
            if (dx * dx + dy * dy < (0.17 * h) * (0.17 * h)) {  // a disc in front
                z = 2.2;
                r = 1.0f, g = ((y / 2) % 2) ? 0.1f : 0.6f, b = 0.1f;
            }
            pl.rgba[i * 4 + 0] = r;
            pl.rgba[i * 4 + 1] = g;
            pl.rgba[i * 4 + 2] = b;
            pl.rgba[i * 4 + 3] = 1.0f;
            pl.z[i] = float(z);
            // The camera's ray through the pixel centre (x right, y up, +z forward).
            const double cx = (x + 0.5 - 0.5 * w) / fpx, cy = -(y + 0.5 - 0.5 * h) / fpx;
            pl.p[i * 3 + 0] = float(cx * z);
            pl.p[i * 3 + 1] = float(cy * z);
            pl.p[i * 3 + 2] = float(z);
        }
    return pl;
}

// A clip image of the plate, bottom row first: "rgba", "rgb", "depth"
// (Alpha: the depth), "depth_rgb" (depth in B, garbage in R and G), "position" (RGB = P).
inline ClipFrame plate_clip(const Plate& pl, const std::string& what) {
    const bool rgba = what == "rgba";
    const std::string comps = rgba ? kOfxImageComponentRGBA : what == "depth" ? kOfxImageComponentAlpha : kOfxImageComponentRGB;
    ClipFrame f = ClipFrame::make(pl.w, pl.h, comps);
    for (int oy = 0; oy < pl.h; ++oy)
        for (int x = 0; x < pl.w; ++x) {
            const int y = pl.h - 1 - oy;  // plate row
            const std::size_t i = std::size_t(y) * std::size_t(pl.w) + std::size_t(x);
            if (rgba || what == "rgb")
                for (int c = 0; c < f.ncomp(); ++c) f.at(x, oy, c) = pl.rgba[i * 4 + std::size_t(c)];
            else if (what == "depth")
                f.at(x, oy, 0) = pl.z[i];
            else if (what == "depth_rgb") {
                f.at(x, oy, 0) = -7.0f;
                f.at(x, oy, 1) = 1e6f;
                f.at(x, oy, 2) = pl.z[i];
            } else {
                for (int c = 0; c < 3; ++c) f.at(x, oy, c) = pl.p[i * 3 + std::size_t(c)];
            }
        }
    return f;
}

// Writes the plate as an EXR: R, G, B, A, Z and (with_p) P.x, P.y, P.z, float, no camera attributes.
inline void write_plate(const Plate& pl, const std::string& path, bool with_p = false) {
    std::vector<std::string> ch = {"R", "G", "B", "A", "Z"};
    if (with_p) ch.insert(ch.end(), {"P.x", "P.y", "P.z"});
    write_exr(path, pl.w, pl.h, ch, [&](int x, int y, int c) {
        const std::size_t i = std::size_t(y) * std::size_t(pl.w) + std::size_t(x);
        if (c < 4) return pl.rgba[i * 4 + std::size_t(c)];
        if (c == 4) return pl.z[i];
        return pl.p[i * 3 + std::size_t(c - 5)];
    });
}

// Largest |render - file| over the render's pixels and channels (the file:
// top row first at data window (0, 0), `nc` channels compared). Pixels
// outside either image count as 0 in it.
inline double max_diff_to_file(const Rendered& r, const std::string& path, int nc, int h_display) {
    OIIO::ImageSpec spec;
    const std::vector<float> px = read_pixels(path, &spec);
    if (px.empty()) return 1e30;
    double m = 0;
    for (int oy = r.bounds.y1; oy < r.bounds.y2; ++oy)
        for (int x = r.bounds.x1; x < r.bounds.x2; ++x) {
            const int fy = h_display - 1 - oy - spec.y, fx = x - spec.x;
            const bool in = fx >= 0 && fx < spec.width && fy >= 0 && fy < spec.height;
            for (int c = 0; c < nc; ++c) {
                const float v = in ? px[(std::size_t(fy) * std::size_t(spec.width) + std::size_t(fx)) * std::size_t(spec.nchannels) + std::size_t(c)] : 0.0f;
                const double d = std::abs(double(r.at(x, oy, c)) - double(v));
                if (!(d <= m)) m = d;  // NaN counts as the largest
            }
        }
    return m;
}

inline double max_diff(const Rendered& a, const Rendered& b) {
    if (a.bounds.x1 != b.bounds.x1 || a.bounds.y1 != b.bounds.y1 || a.bounds.x2 != b.bounds.x2 ||
        a.bounds.y2 != b.bounds.y2 || a.ncomp != b.ncomp || a.px.size() != b.px.size())
        return 1e30;
    double m = 0;
    for (std::size_t i = 0; i < a.px.size(); ++i) {
        const double d = std::abs(double(a.px[i]) - double(b.px[i]));
        if (!(d <= m)) m = d;
    }
    return m;
}

// The four quadrants of a pixel rectangle.
inline std::vector<OfxRectI> quadrants(const OfxRectI& b) {
    const int mx = (b.x1 + b.x2) / 2, my = (b.y1 + b.y2) / 2;
    return {{b.x1, b.y1, mx, my}, {mx, b.y1, b.x2, my}, {b.x1, my, mx, b.y2}, {mx, my, b.x2, b.y2}};
}

}  // namespace gdof::test
