// Generates a small synthetic light field for examples/lightfield/run.sh when
// the real Lytro views are absent: N x N sub-aperture views (8-bit sRGB PNG,
// view_RR_CC.png) of three textured fronto-parallel planes at known depths,
// rendered analytically per view with occlusion, plus its lf.json.
//
//   gdof_example_lightfield -o DIR [--size 320x240] [--grid 5]
//
// Convention (gdof/lightfield.h): a point at central-view x appears at
// x - d * du in the view du columns to the right; d = focal_baseline / z.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/io/image_io.h"

namespace {

struct Plane {
    double depth;               // scene units
    double x0, y0, x1, y1;      // extent in central-view pixels (x1 < 0: everywhere)
    double r, g, b;             // base colour (linear)
    double period;              // texture scale, px
};

constexpr double kFocalBaseline = 8.0;  // px x scene units: d = 8 / z

void texture(const Plane& p, double x, double y, float out[3]) {
    // Checks modulated by soft rings: sharp edges show focus clearly.
    const int cx = int(std::floor(x / p.period)), cy = int(std::floor(y / p.period));
    const double check = ((cx + cy) & 1) ? 1.0 : 0.45;
    const double ring = 0.75 + 0.25 * std::sin(0.35 * std::hypot(x - 0.3 * p.x0, y - 0.2 * p.y0));
    const double k = check * ring;
    out[0] = float(p.r * k), out[1] = float(p.g * k), out[2] = float(p.b * k);
}

int usage() {
    std::cerr << "usage: gdof_example_lightfield -o DIR [--size WxH] [--grid N]\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string dir;
    int w = 320, h = 240, n = 5;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-o" && i + 1 < argc) dir = argv[++i];
        else if (a == "--size" && i + 1 < argc) {
            if (std::sscanf(argv[++i], "%dx%d", &w, &h) != 2 || w < 16 || h < 16) return usage();
        } else if (a == "--grid" && i + 1 < argc) {
            n = std::atoi(argv[++i]);
            if (n < 1 || n > 17) return usage();
        } else return usage();
    }
    if (dir.empty()) return usage();
    std::filesystem::create_directories(dir);

    // Nearest first.
    const std::vector<Plane> planes = {
        {4.0, 0.18 * w, 0.45 * h, 0.45 * w, 0.9 * h, 0.9, 0.35, 0.2, 7.0},    // near card, d = 2
        {8.0, 0.5 * w, 0.15 * h, 0.85 * w, 0.7 * h, 0.25, 0.7, 0.3, 11.0},   // middle card, d = 1
        {32.0, 0, 0, -1, -1, 0.3, 0.4, 0.85, 16.0},                          // background, d = 0.25
    };
    const int c0 = (n - 1) / 2;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const double du = col - c0, dv = row - c0;
            gdof::Image v = gdof::Image::with_channels({"R", "G", "B"}, gdof::Roi{0, 0, w, h});
            // 3 x 3 supersampling per pixel.
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    float acc[3] = {0, 0, 0};
                    for (int sy = 0; sy < 3; ++sy)
                        for (int sx = 0; sx < 3; ++sx) {
                            const double px = x + (sx - 1) / 3.0, py = y + (sy - 1) / 3.0;
                            for (const Plane& p : planes) {
                                const double d = kFocalBaseline / p.depth;
                                const double X = px + d * du, Y = py + d * dv;
                                if (p.x1 >= 0 && !(X >= p.x0 && X < p.x1 && Y >= p.y0 && Y < p.y1)) continue;
                                float t[3];
                                texture(p, X, Y, t);
                                for (int c = 0; c < 3; ++c) acc[c] += t[c] / 9.0f;
                                break;
                            }
                        }
                    for (int c = 0; c < 3; ++c) v.at(c, x, y) = acc[c];
                }
            char name[64];
            std::snprintf(name, sizeof name, "/view_%02d_%02d.png", row, col);
            if (auto st = gdof::io::write_flat(dir + name, v); !st) {
                std::cerr << "gdof_example_lightfield: " << st.message() << "\n";
                return 1;
            }
        }
    std::ofstream(dir + "/lf.json") << "{\n  \"comment\": \"generated: planes at depth 4, 8, 32 (disparity 2, 1, 0.25)\",\n"
                                    << "  \"focal_baseline\": " << kFocalBaseline << ",\n  \"disparity_at_infinity\": 0\n}\n";
    std::cerr << "wrote " << n * n << " views " << w << "x" << h << " and lf.json to " << dir << "\n";
    return 0;
}
