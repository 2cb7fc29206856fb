// The naive layered baseline for the method benchmark: the flat image + Z
// cut into depth slices (no hidden-surface extension), each slice blurred by
// cv::GaussianBlur with one sigma (its alpha-weighted mean blur radius / 2,
// gdof's radius-to-sigma convention), composited back to front with `over`.
// What a compositor gets from stacking per-depth Gaussian blurs.
#pragma once

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof::bench {

Result<Image> gaussian_layers(const Image& rgba_z, const BlurField& field, const Camera& camera, int slices);

}  // namespace gdof::bench
