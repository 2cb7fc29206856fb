// What both solvers do around their kernels: check the views' shapes and
// hand the kernel row-major planes (the views' own memory, or exact copies
// written back afterwards, cancelled or not, as an in-place kernel leaves them).
#pragma once

#include <span>

#include "gdof/image.h"
#include "gdof/status.h"
#include "image/row_major_planes.h"
#include "image/view_shape.h"

namespace gdof::diffusion_detail {

// kernel(std::span<float* const> planes, int width, int height, const float* diffusivity) -> Status
template <class Kernel>
Status run_solver_kernel(const ImageView& planes, const ConstImageView& diffusivity, Kernel&& kernel) {
    using namespace image_detail;
    const Roi& win = planes.window;
    if (Status st = check_view_shape(planes, kAnyChannelCount, win, "diffusion: the planes"); !st) return st;
    if (Status st = check_view_shape(diffusivity, 1, win, "diffusion: the diffusivity map"); !st) return st;
    if (win.empty() || planes.nchannels == 0) return Status::ok();
    const RowMajorPlanes<float> p(planes);
    const RowMajorPlanes<const float> d(diffusivity);
    Status st = kernel(p.planes(), win.width(), win.height(), d.plane(0));
    p.store();
    return st;
}

}  // namespace gdof::diffusion_detail
