// Pieces of the aperture's geometry shared by its sources. Not installed.
#pragma once

#include "gdof/aperture.h"

namespace gdof::aperture_detail {

struct Vec2d {
    double x = 0, y = 0;
};

// (u, v) on the unsqueezed, unrotated shape.
Vec2d unturn(const Aperture& a, double u, double v);
// Radius of a rounded regular polygon (circumradius 1, a vertex at theta 0).
double polygon_radius(int blades, double roundness, double theta);
// Density at (u, v): 0 / 1 for disc and polygon; the kernel's value for an
// image (channel c, or the mean of the colour channels for c < 0).
double density(const Aperture& a, double u, double v, int c);

}  // namespace gdof::aperture_detail
