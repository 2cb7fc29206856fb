// BokehFilter: the aperture prepared once per render (its row profile, or an
// image kernel at every radius a pyramid level spreads).
#include "bokeh/bokeh_internal.h"

namespace gdof {

Result<BokehFilter> BokehFilter::create(const Aperture& aperture) {
    if (Status st = validate(aperture); !st) return st;
    if (aperture.kind == Aperture::Kind::Image && aperture.cats_eye > 0.0)
        return Status::error("aperture: cats_eye applies to disc and polygon apertures, not to an image kernel",
                             StatusCode::InvalidArgument, "cats_eye");
    auto p = std::make_shared<Prepared>();
    p->aperture = aperture;
    if (aperture.kind != Aperture::Kind::Image) {
        auto profile = ApertureProfile::create(aperture);
        if (!profile) return profile.status();
        p->profile = std::move(profile).value();
        p->spans = true;
        p->level_radius = 12;
    } else {
        // Cell by cell costs (2R + 1)^2 per pixel: a smaller level radius.
        p->spans = false;
        p->level_radius = 5;
        const int nq = 2 * p->level_radius * Prepared::kKernelSteps;
        p->kernels.reserve(std::size_t(nq) + 1);
        for (int q = 0; q <= nq; ++q) {
            auto k = rasterize_aperture(aperture, double(q) / Prepared::kKernelSteps);
            if (!k) return k.status();
            p->kernel_reach = std::max(p->kernel_reach, k->half);
            p->kernels.push_back(std::move(k).value());
        }
    }
    BokehFilter f;
    f.p_ = std::move(p);
    return f;
}

const Aperture& BokehFilter::aperture() const { return p_->aperture; }

}  // namespace gdof
