// The generalized PSF field: depth of field as vibrational motion blur, the
// fourth technique of Kosloff & Barsky (section 5). For a point x and an
// aperture sample u the field gives a displacement: where the motion takes
// the point (in the image plane, in pixels, and along its viewing ray, in
// scene units). Rendering (vibrate_layers) samples the aperture, moves every
// layer pixel by its displacement, composites the moved scene with
// visibility (depth after the move) and averages the samples. With the
// displacement B(x) * u it is ordinary generalized defocus; other fields give
// lens looks no lens has (docs/psf_field.md):
//
//   defocus  B(x) * scale * u           (u in the aperture's shape; image y down)
//   swirl    an arc about the frame centre whose length is
//            strength * B(x) * (rho / half diagonal)^power * u_t,
//            u_t = the sample's component along the tangent at x
//   depth    dz = offset + distance * u  (along the viewing ray: visibility only)
//   image_map  scale * M(x) * (u, -v), M a painted map's 1, 2 or 4 channels:
//            an isotropic scale, per-axis scales or a 2x2 matrix (px per unit aperture)
//   sum      the children's displacements added
//   blend    (1 - w(x)) * children[0] + w(x) * children[1], w = a blur field's
//            value at x clamped to [0, 1] (a region, an image_map, ...)
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gdof/aperture.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

namespace psf {
class Node;  // internal
}

// Where the motion takes a point: dx right and dy down in pixels, dz along
// the viewing ray in scene units (> 0: farther away).
struct PsfDisplacement {
    double dx = 0.0, dy = 0.0, dz = 0.0;
};

// What the field sees of one point: its pixel centre (absolute pixels), its
// depth, its blur radius B (px) from the blur field, and the values of the
// field's weight maps there (weight_count() of them, see evaluate_weights).
struct PsfPoint {
    double x = 0.0, y = 0.0;
    double depth = 0.0;
    double blur = 0.0;
    const float* weights = nullptr;
};

class GDOF_API PsfField {
public:
    // The `defocus` kind with scale 1: ordinary generalized defocus.
    PsfField();
    // Parses {"psf_field": {...}, "samples": N, "comment": ...}. Unknown keys
    // and bad values are errors naming the key path
    // ("psf_field.children[1].strength: must be a number, got string").
    // A blend's `weight` is a blur field node (docs/blur_field.md) read with
    // `ctx` (its image_maps).
    static Result<PsfField> parse(std::string_view json_text, const BlurField::Context& ctx = {});

    // Aperture samples asked for in the file (0: automatic).
    int samples() const { return samples_; }
    // True when some part moves points along their rays (depth order changes).
    bool moves_depth() const;
    // "sum(defocus, swirl)".
    std::string describe() const;

    // The blend weights at a point, one per blend of the tree (in the order
    // the tree lists them), each clamped to [0, 1]; `out` holds weight_count().
    int weight_count() const;
    void evaluate_weights(const Camera& camera, double px, double py, double depth, float* out) const;

    // The displacement of `point` for aperture sample (u, v) (aperture.h:
    // u right, v up, radius 1 = the blur radius). `frame` is the display
    // window (its centre and half diagonal set the swirl).
    PsfDisplacement displace(const PsfPoint& point, double u, double v, const Roi& frame) const;

private:
    std::shared_ptr<const psf::Node> root_;
    int samples_ = 0;
    int weights_ = 0;
};

// Aperture samples: a square lattice shifted by an offset drawn from `seed`,
// its points inside the aperture's shape kept, its spacing chosen near
// sqrt(area / n) so that as close to n points as possible remain (the most
// even spread: what the prefilter needs to turn N samples into one smooth
// shape). Deterministic in (aperture, n, seed). `spacing` receives the
// lattice spacing in aperture units. A cat's eye (a shape that varies across
// the frame) is an error here: vibrate_layers samples the uncut aperture and
// maps each sample onto the cut shape per source.
struct ApertureSample {
    double u = 0.0, v = 0.0;
};
GDOF_API Result<std::vector<ApertureSample>> aperture_samples(const Aperture& aperture, int n, std::uint64_t seed,
                                                              double* spacing = nullptr);

struct VibrateOptions {
    int samples = 0;          // aperture samples; 0: the field's, else automatic from the largest displacement
    std::uint64_t seed = 0;   // of the samples' jitter
    double prefilter = 0.7;   // each sample's splat: Gaussian-like, sigma = prefilter * (sample spacing in px)
};

struct GDOF_API VibrateStats {
    int samples = 0;             // aperture samples used
    double spacing = 0.0;        // their spacing, aperture units
    double max_displacement_px = 0.0;
    std::size_t splats = 0;      // source pixels x samples
    double t_prepare = 0.0, t_render = 0.0;
};

// One layer for vibrate_layers: premultiplied R, G, B, A and Z (float) at
// the given channel indices of `image` (its data window), and the blur radius
// of every pixel of `radius_window` (row-major; extrapolated beyond the
// layer's coverage, as the defocus pipeline does; covering `frame`).
struct VibrateLayer {
    const Image* image = nullptr;
    RgbaIndices rgba;
    int z = -1;
    Roi radius_window;
    const float* radius = nullptr;
};

// Renders the layers (front = index 0) through the PSF field over `output`
// (absolute pixels): for each aperture sample, every layer pixel is splatted
// at its moved position with a footprint that covers the warped pixel grid
// and the spacing of the samples (no cracks, no ghosts), normalised per layer
// by the splatted weight (a layer's transparent pixels splat weight too, so
// silhouettes blur semi-transparent); per output pixel the moved layers are
// composited front to back in the order of their moved depths; the samples
// are averaged. `frame` (the display window) sets the swirl's centre and
// half diagonal; beyond `output` sources repeat its edge (where a layer's
// content touches it). Output float R, G, B, A over `output`; bit-identical
// for any thread count.
GDOF_API Result<Image> vibrate_layers(const std::vector<VibrateLayer>& front_to_back, const PsfField& field,
                                      const Aperture& aperture, const Camera& camera, const Roi& frame,
                                      const Roi& output, const VibrateOptions& options, VibrateStats* stats = nullptr,
                                      const Exec& exec = {});

}  // namespace gdof
