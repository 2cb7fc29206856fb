#include "gdof/diffusion.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "diffusion/conductance.h"
#include "image/frame_buffer.h"
#include "image/row_major_planes.h"
#include "image/view_shape.h"

namespace gdof {

const char* to_string(DiffusionSolver s) {
    switch (s) {
        case DiffusionSolver::Explicit: return "explicit";
        case DiffusionSolver::Adi: return "adi";
        case DiffusionSolver::Auto: break;
    }
    return "auto";
}

Result<DiffusionSolver> parse_diffusion_solver(const char* name) {
    std::string n = name ? name : "";
    if (n == "auto") return DiffusionSolver::Auto;
    if (n == "explicit") return DiffusionSolver::Explicit;
    if (n == "adi") return DiffusionSolver::Adi;
    return Status::error("unknown diffusion solver '" + n + "' (expected 'auto', 'adi' or 'explicit')");
}

DiffusionSolver choose_solver(double max_radius_px, const DiffusionOptions& settings) {
    if (settings.solver != DiffusionSolver::Auto) return settings.solver;
    const double explicit_cost = explicit_iterations(max_radius_px, settings);
    const double adi_cost = kAdiStepCost * adi_steps_for(max_radius_px, settings);
    return explicit_cost <= adi_cost ? DiffusionSolver::Explicit : DiffusionSolver::Adi;
}

int explicit_iterations(double max_radius_px, const DiffusionOptions& settings) {
    // The 9-point stencil's weights sum to 10/3; stability needs dt * D * 10/3 <= 1.
    double d = diffusivity_from_radius(max_radius_px);
    return std::max(1, int(std::ceil(settings.explicit_safety * d * 10.0 / 3.0)));
}

Status diffuse_planes(const ImageView& planes, const ConstImageView& radius, const DiffusionOptions& settings,
                      const Exec& exec) {
    return diffusion_detail::diffuse_planes(planes, radius, settings, exec, diffusion_detail::Conductance::Min);
}

Status diffusion_detail::diffuse_planes(const ImageView& planes, const ConstImageView& radius,
                                        const DiffusionOptions& settings, const Exec& exec, Conductance conductance) {
    using namespace image_detail;
    const Roi& win = planes.window;
    if (win.x1 < win.x0 || win.y1 < win.y0) return Status::error("diffusion: inverted window " + to_string(win));
    if (Status st = check_view_shape(planes, kAnyChannelCount, win, "diffusion: the planes"); !st) return st;
    if (Status st = check_view_shape(radius, 1, win, "diffusion: the radius map"); !st) return st;
    const int width = win.width();
    const std::size_t n = win.npixels();
    if (n == 0 || planes.nchannels == 0) return Status::ok();
    if (settings.adi_steps < 0 || settings.adi_steps > 1000)
        return Status::error("diffusion: adi_steps must be in 0..1000 (0: automatic), got " + std::to_string(settings.adi_steps));
    if (!(settings.explicit_safety >= 1.0) || settings.explicit_safety > 100.0)
        return Status::error("diffusion: explicit_safety must be in 1..100");
    const RowMajorPlanes<const float> radius_plane(radius);
    const float* rp = radius_plane.plane(0);
    // Rows in parallel (a frame-sized map at 4K), each with its largest
    // diffusivity and first bad pixel; the first bad pixel of all is reported.
    const int height = win.height();
    FrameBuffer<float> d(n);  // every element set below
    std::vector<float> row_dmax(std::size_t(height), 0.0f);
    std::vector<std::size_t> row_bad(std::size_t(height), n);
    std::vector<unsigned char> row_any(std::size_t(height), 0);
    const auto valid = [&](float r) { return std::isfinite(r) && r >= 0.0f && r <= settings.max_radius; };
    const bool done = parallel_for(exec, height, [&](long y0, long y1) {
        for (long y = y0; y < y1; ++y) {
            float dm = 0.0f;
            bool any_row = false;
            for (std::size_t i = std::size_t(y) * std::size_t(width); i < std::size_t(y + 1) * std::size_t(width); ++i) {
                const float r = rp[i];
                if (!valid(r)) {
                    row_bad[std::size_t(y)] = i;
                    break;
                }
                d[i] = float(diffusivity_from_radius(r));
                dm = std::max(dm, d[i]);
                any_row = any_row || r > 0.0f;
            }
            row_dmax[std::size_t(y)] = dm;
            row_any[std::size_t(y)] = any_row;
        }
    }, 16);
    if (!done) return Status::cancelled("diffusion");
    for (std::size_t i : row_bad)
        if (i < n) {
            const float r = rp[i];
            const int x = int(i % std::size_t(width)), y = int(i / std::size_t(width));
            return Status::error("diffusion: blur radius at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                 " of the layer) is " + std::to_string(r) + "; expected a finite value in 0.." +
                                 std::to_string(settings.max_radius));
        }
    const float dmax = *std::max_element(row_dmax.begin(), row_dmax.end());
    if (std::none_of(row_any.begin(), row_any.end(), [](unsigned char v) { return v != 0; }))
        return Status::ok();  // identity, bit for bit
    const DiffusionSolver solver = choose_solver(radius_from_diffusivity(dmax), settings);
    const ConstImageView diffusivity = ConstImageView::planar(d.data(), 1, win);
    return solver == DiffusionSolver::Explicit ? diffuse_explicit(planes, diffusivity, settings, exec, conductance)
                                               : diffuse_adi(planes, diffusivity, settings, exec, conductance);
}

}  // namespace gdof
