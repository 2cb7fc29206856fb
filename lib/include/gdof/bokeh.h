// The bokeh filter: each pixel's light spread over the aperture (aperture.h)
// scaled by its own blur radius, the answer to the paper's challenge of a
// filter that "respects visibility like heat diffusion, but provides control
// over the PSF". The defocus pipeline (defocus.h) runs it per layer in place
// of the heat equation, with the same layers, extrapolation and compositing.
//
// How (docs/bokeh.md): scatter, not gather, so a sharp pixel never spreads
// into a blurred one and a blurred one spreads over its neighbours as the
// lens would. Each pixel writes one span per image row into a difference
// buffer that a running sum per row turns into the shape (Kosloff, Hensley
// & Barsky's filter spreading, row by row: O(R) per pixel, not O(R^2));
// the rows' top and bottom are anti-aliased by averaging the shape's edges
// over each row. Pixels whose radius is large are spread on a coarser level
// of a pyramid (level k for radii [12 2^k, 24 2^k)), so no pixel writes more
// than ~50 rows and the cost stops growing with R. Image kernels are
// written cell by cell at coarser levels (radii [5 2^k, 10 2^k)).
// The result is normalised by the spread of ones: where a blurred region
// meets a sharp one the blurred side stays opaque (the paper's Figure 6: no
// holes) and a constant image stays constant; in a constant blur the
// normalisation is exactly 1, so a highlight keeps its energy.
#pragma once

#include <memory>

#include "gdof/aperture.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

// An aperture prepared for spreading (its row profile or its kernels at
// every radius a level uses). Immutable, shared by the threads and layers.
class GDOF_API BokehFilter {
public:
    static Result<BokehFilter> create(const Aperture& aperture);
    const Aperture& aperture() const;
    struct Prepared;
    const Prepared& prepared() const { return *p_; }

private:
    std::shared_ptr<const Prepared> p_;
};

// Spreads the channels of `planes` in place: premultiplied colour and
// coverage (channels 0..2 take a colour kernel's R, G, B; the others its
// mean), each pixel over the aperture scaled by its radius in `radius` (one
// channel over the same window, finite and >= 0; errors name the pixel).
// `frame` is the display window, whose centre and half diagonal set the
// cat's eye (empty: the planes' window). Bit-identical for any thread count.
GDOF_API Status spread_planes(const ImageView& planes, const ConstImageView& radius, const BokehFilter& filter,
                              const Roi& frame, const Exec& exec = {});

}  // namespace gdof
