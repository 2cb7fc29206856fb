// Helpers for the defocus pipeline tests: hand-built layers, a pinhole
// camera looking down +z from the origin, and blur fields whose radius per
// pixel is known exactly (an image_map supplied in memory).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/deep.h"
#include "gdof/defocus.h"

namespace gdof::test {

inline Camera test_camera(const Roi& display) {
    CameraDesc d;
    d.display_window = display;
    d.focal_length_mm = 35.0;
    d.sensor_width_mm = 36.0;
    auto c = Camera::create(d);
    EXPECT_TRUE(c) << c.message();
    return c.value();
}

using Rgba = std::array<float, 4>;

// A layer with float R, G, B, A (premultiplied) and Z over `window`: the
// colour from f(x, y); Z = depth where A > 0 (or colour), NaN elsewhere.
inline Layer make_layer(const Roi& window, const Roi& display, const std::function<Rgba(int, int)>& f,
                        double depth = 5.0, const std::string& name = "") {
    Layer l;
    l.image = Image(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, window, display);
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x) {
            const Rgba v = f(x, y);
            bool any = false;
            for (int c = 0; c < 4; ++c) {
                l.image.at(c, x, y) = v[std::size_t(c)];
                any = any || v[std::size_t(c)] != 0.0f;
            }
            l.image.at(4, x, y) = any ? float(depth) : std::numeric_limits<float>::quiet_NaN();
        }
    l.name = name;
    l.depth_near = l.depth_far = depth;
    return l;
}

// B(pixel) = scale * map(x, y) at pixel centres (the map covers `display`).
inline BlurField map_field(const Roi& display, const std::function<float(int, int)>& map, double scale = 1.0) {
    auto img = std::make_shared<Image>(Image::with_channels({"Y"}, display));
    for (int y = display.y0; y < display.y1; ++y)
        for (int x = display.x0; x < display.x1; ++x) img->at(0, x, y) = map(x, y);
    BlurField::Context ctx;
    ctx.images["m"] = img;
    auto f = BlurField::parse(R"({"blurfield": {"kind": "image_map", "image": "m", "scale": )" +
                                  std::to_string(scale) + "}}",
                              ctx);
    EXPECT_TRUE(f) << f.message();
    return f.value();
}

inline BlurField constant_field(const Roi& display, double radius) {
    return map_field(display, [](int, int) { return 1.0f; }, radius);
}

// Value of channel c at (x, y), 0 outside the data window.
inline double value_at(const Image& img, int c, int x, int y) {
    return img.data_window().contains(x, y) ? double(img.at(c, x, y)) : 0.0;
}

inline double channel_sum(const Image& img, int c) {
    double s = 0;
    const float* p = img.plane(c);
    for (std::size_t i = 0; i < img.npixels(); ++i) s += p[i];
    return s;
}

// Largest |a - b| over `roi` and channels 0..3.
inline double max_abs_diff(const Image& a, const Image& b, const Roi& roi) {
    double m = 0;
    for (int c = 0; c < 4; ++c)
        for (int y = roi.y0; y < roi.y1; ++y)
            for (int x = roi.x0; x < roi.x1; ++x) m = std::max(m, std::abs(value_at(a, c, x, y) - value_at(b, c, x, y)));
    return m;
}

// A flat image as a deep one: one sample per pixel with the pixel's
// channels (the deep render of what a plate holds).
inline DeepImage deep_of(const Image& flat) {
    std::vector<ChannelSpec> chans;
    for (int c = 0; c < flat.nchannels(); ++c) chans.push_back({flat.channel(c).name, PixelType::Float});
    DeepImage d(chans, flat.data_window(), flat.display_window());
    EXPECT_TRUE(d.set_sample_counts(std::vector<std::uint32_t>(flat.npixels(), 1)));
    const Roi w = flat.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            const std::size_t k = d.first_sample(d.pixel_index(x, y));
            for (int c = 0; c < flat.nchannels(); ++c) d.samples(c)[k] = flat.at(c, x, y);
        }
    return d;
}

inline bool bit_identical(const Image& a, const Image& b) {
    if (a.data_window() != b.data_window() || a.nchannels() != b.nchannels()) return false;
    for (int c = 0; c < a.nchannels(); ++c)
        for (std::size_t i = 0; i < a.npixels(); ++i)
            if (std::memcmp(&a.plane(c)[i], &b.plane(c)[i], sizeof(float)) != 0) return false;
    return true;
}

// Coverage at distance d from the centre of an opaque disc of radius a
// blurred by a uniform disc kernel of radius R: the overlap area of the two
// circles over the kernel's area.
inline double blurred_disc_coverage(double d, double a, double R) {
    if (d >= a + R) return 0.0;
    if (d <= std::abs(a - R)) return a >= R ? 1.0 : (a * a) / (R * R);
    const double r2 = R * R, a2 = a * a, d2 = d * d;
    const double p = r2 * std::acos((d2 + r2 - a2) / (2 * d * R)) + a2 * std::acos((d2 + a2 - r2) / (2 * d * a)) -
                     0.5 * std::sqrt((-d + R + a) * (d + R - a) * (d - R + a) * (d + R + a));
    return p / (3.14159265358979323846 * r2);
}

// Deterministic smooth-ish texture in [0, 1].
inline float texture(int x, int y, int c) {
    return float(0.5 + 0.25 * std::sin(0.37 * x + 1.3 * c) * std::cos(0.23 * y - 0.7 * c) +
                 0.2 * std::sin(0.05 * (x + 2 * y) + c));
}

}  // namespace gdof::test
