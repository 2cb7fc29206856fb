// The solvers take the planes as one ImageView; tests that keep each plane
// in its own std::vector go through diffuse_vectors.
#pragma once

#include <algorithm>
#include <vector>

#include "gdof/diffusion.h"

namespace gdof::test {

// diffuse_planes on separate w x h row-major planes: packed back to back for
// a planar view, unpacked afterwards (exact copies, so the bits are the
// solver's), also when the call fails.
inline Status diffuse_vectors(const std::vector<std::vector<float>*>& planes, int w, int h,
                              const std::vector<float>& radius, const DiffusionOptions& settings, const Exec& exec = {}) {
    const Roi window{0, 0, w, h};
    const std::size_t n = window.npixels();
    std::vector<float> packed(planes.size() * n);
    for (std::size_t c = 0; c < planes.size(); ++c) std::copy_n(planes[c]->begin(), n, packed.begin() + std::ptrdiff_t(c * n));
    Status st = diffuse_planes(ImageView::planar(packed.data(), int(planes.size()), window),
                               ConstImageView::planar(radius.data(), 1, window), settings, exec);
    for (std::size_t c = 0; c < planes.size(); ++c)
        std::copy_n(packed.begin() + std::ptrdiff_t(c * n), n, planes[c]->begin());
    return st;
}

}  // namespace gdof::test
