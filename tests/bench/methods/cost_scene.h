// What the cost benchmarks share (bench_bokeh, bench_vibrate): timing by
// medians of repeats, and one input whose blur is set by a single number:
// two full-frame layers (a textured opaque background, a foreground disc in
// front of it) under a constant blur radius R.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "bench_cli.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/layers.h"

namespace gdof::bench {

inline double seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
inline double best_of(int n, const std::function<void()>& f) {
    double b = 1e30;
    for (int i = 0; i < n; ++i) b = std::min(b, seconds(f));
    return b;
}
inline double median_of(int n, const std::function<void()>& f) {
    std::vector<double> t;
    for (int i = 0; i < n; ++i) t.push_back(seconds(f));
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

// The two layers over `frame`: the disc (radius 0.3 of the height, depth 2)
// in front of a 16 px checker (depth 10).
inline std::vector<Layer> cost_layers(const Roi& frame) {
    std::vector<Layer> layers(2);
    const double cx = frame.width() * 0.5, cy = frame.height() * 0.5, r = frame.height() * 0.3;
    for (int k = 0; k < 2; ++k) {
        Layer& l = layers[std::size_t(k)];
        l.image = Image(std::vector<ChannelSpec>{{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, frame, frame);
        l.depth_near = l.depth_far = k == 0 ? 2.0 : 10.0;
        for (int y = frame.y0; y < frame.y1; ++y)
            for (int x = frame.x0; x < frame.x1; ++x) {
                const bool in = std::hypot(x + 0.5 - cx, y + 0.5 - cy) < r;
                if (k == 0 && !in) {
                    l.image.at(4, x, y) = std::nanf("");
                    continue;
                }
                const float t = float(((x / 16) + (y / 16)) % 2);
                l.image.at(0, x, y) = k == 0 ? 0.8f : t;
                l.image.at(1, x, y) = k == 0 ? 0.2f : 0.5f;
                l.image.at(2, x, y) = k == 0 ? 0.1f : 1.0f - t;
                l.image.at(3, x, y) = 1.0f;
                l.image.at(4, x, y) = float(l.depth_near);
            }
    }
    return layers;
}

// A 35 mm lens on a 36 mm sensor over `frame` (the field sets the blur).
inline Camera cost_camera(const Roi& frame) {
    CameraDesc d;
    d.display_window = frame;
    d.focal_length_mm = 35.0;
    d.sensor_width_mm = 36.0;
    return take(Camera::create(d), "camera");
}

// Every point in front of the camera blurred by R px.
inline BlurField constant_blur(int R) {
    char fj[256];
    std::snprintf(fj, sizeof fj,
                  R"({"blurfield": {"kind": "region", "shape": "box", "mode": "blur", "blur": %d, "min": [-1e6, -1e6, 0.1], "max": [1e6, 1e6, 1e6]}})",
                  R);
    return take(BlurField::parse(fj), "field");
}

}  // namespace gdof::bench
