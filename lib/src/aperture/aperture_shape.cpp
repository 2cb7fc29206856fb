// The aperture's geometry: which (u, v) it holds, its density for image
// kernels, and the mask image the ray tracer's sampler takes.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "aperture/aperture_internal.h"

namespace gdof {

namespace aperture_detail {

Vec2d unturn(const Aperture& a, double u, double v) {
    // Squeeze divides the width: a point at u sits where u * squeeze does on
    // the unsqueezed shape. Then undo the rotation.
    u *= a.squeeze;
    if (a.rotation_deg == 0.0) return {u, v};
    const double t = -a.rotation_deg * std::numbers::pi / 180.0;
    const double c = std::cos(t), s = std::sin(t);
    return {c * u - s * v, s * u + c * v};
}

double polygon_radius(int blades, double roundness, double theta) {
    const double sector = 2.0 * std::numbers::pi / blades;
    double phi = std::fmod(theta, sector);
    if (phi < 0) phi += sector;
    const double r_poly = std::cos(std::numbers::pi / blades) / std::cos(phi - 0.5 * sector);
    return (1.0 - roundness) * r_poly + roundness;
}

double image_density(const Aperture& a, double u, double v, int c) {
    const Roi dw = a.image.data_window();
    const int w = dw.width(), h = dw.height();
    const double scale = 2.0 / double(std::max(w, h));
    // Pixel-centre coordinates of the data window.
    const double x = u / scale + 0.5 * w - 0.5, y = -v / scale + 0.5 * h - 0.5;
    if (!(x > -1.0 && y > -1.0 && x < w && y < h)) return 0.0;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int xi, int yi) {
        if (xi < 0 || yi < 0 || xi >= w || yi >= h) return 0.0;
        return double(a.image.sample(c, dw.x0 + xi, dw.y0 + yi));
    };
    return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

double density(const Aperture& a, double u, double v, int c) {
    const Vec2d p = unturn(a, u, v);
    switch (a.kind) {
        case Aperture::Kind::Disc: return p.x * p.x + p.y * p.y <= 1.0 ? 1.0 : 0.0;
        case Aperture::Kind::Polygon: {
            const double r = std::hypot(p.x, p.y);
            if (r > 1.0) return 0.0;
            return r <= polygon_radius(a.blades, a.roundness, std::atan2(p.y, p.x)) ? 1.0 : 0.0;
        }
        case Aperture::Kind::Image: {
            if (!a.colour()) return image_density(a, p.x, p.y, 0);
            if (c >= 0) return image_density(a, p.x, p.y, c);
            return (image_density(a, p.x, p.y, 0) + image_density(a, p.x, p.y, 1) + image_density(a, p.x, p.y, 2)) / 3.0;
        }
    }
    return 0.0;
}

}  // namespace aperture_detail

bool aperture_contains(const Aperture& a, double u, double v) { return aperture_detail::density(a, u, v, -1) > 0.0; }

Image aperture_mask_image(const Aperture& a, int size) {
    Image m = Image::with_channels({"A"}, Roi{0, 0, size, size});
    constexpr int S = 4;
    float* p = m.plane(0);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            double sum = 0.0;
            for (int sy = 0; sy < S; ++sy)
                for (int sx = 0; sx < S; ++sx) {
                    const double u = ((i + (sx + 0.5) / S) / size) * 2.0 - 1.0;
                    const double v = 1.0 - ((j + (sy + 0.5) / S) / size) * 2.0;
                    sum += aperture_detail::density(a, u, v, -1);
                }
            p[std::size_t(j) * std::size_t(size) + std::size_t(i)] = float(sum / (S * S));
        }
    return m;
}

}  // namespace gdof
