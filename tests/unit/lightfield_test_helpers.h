// Generated light fields for the light-field tests: fronto-parallel textured
// planes at known disparities, rendered analytically per view (each view
// point-samples the plane textures shifted by the plane's disparity times the
// view offset, nearest plane first), in the convention of gdof/lightfield.h:
// a point at central-view x appears at x - d * du in view column offset du.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "gdof/image.h"
#include "gdof/lightfield.h"

namespace gdof::test {

struct Plane {
    double disparity = 0;
    Roi region;  // in central-view coordinates; empty = everywhere (background)
    std::function<float(double x, double y, int c)> texture;
    bool covers(double x, double y) const {
        if (region.empty()) return true;
        return x >= region.x0 && x < region.x1 && y >= region.y0 && y < region.y1;
    }
};

// Smooth band-limited texture (periods >= 11 px), values in [0.1, 0.9].
inline std::function<float(double, double, int)> smooth_texture(double seed) {
    return [seed](double x, double y, int c) {
        const double a = std::sin(0.57 * x + 1.3 * seed + 0.9 * c) * std::cos(0.41 * y - 0.7 * seed);
        const double b = std::sin(0.29 * (x + y) + 2.1 * seed + 0.4 * c);
        return float(0.5 + 0.25 * a + 0.15 * b);
    };
}

// planes: nearest first (larger disparity first for a positive geometry).
inline LightField make_planes_lightfield(int rows, int cols, int w, int h, const std::vector<Plane>& planes,
                                         int nchannels = 3) {
    LightField lf;
    lf.rows = rows;
    lf.cols = cols;
    lf.center_row = (rows - 1) / 2;
    lf.center_col = (cols - 1) / 2;
    const std::vector<std::string> names = {"R", "G", "B", "A"};
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const double du = c - lf.center_col, dv = r - lf.center_row;
            Image v = Image::with_channels(std::vector<std::string>(names.begin(), names.begin() + nchannels),
                                           Roi{0, 0, w, h});
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    for (const Plane& p : planes) {
                        const double X = x + p.disparity * du, Y = y + p.disparity * dv;  // central-view point
                        if (!p.covers(X, Y)) continue;
                        for (int ch = 0; ch < nchannels; ++ch) v.at(ch, x, y) = p.texture(X, Y, ch);
                        break;
                    }
                }
            lf.views.push_back(std::move(v));
            lf.sources.push_back("view_" + std::to_string(r) + "_" + std::to_string(c));
        }
    return lf;
}

}  // namespace gdof::test
