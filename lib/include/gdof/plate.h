// Live-action plates: a colour image and its depth map as they come from set
// or from a sensor, made ready for generalized defocus (method 3).
//
// Sensor and stereo depth has holes (no measurement: value 0 in most uint16
// maps, 19% of a TUM RGB-D frame), speckles (islands of a few pixels far from
// the surface around them) and, like a renderer's filtered Z, pixels at a
// silhouette whose depth lies between the foreground's and the background's
// (anti-aliased or "flying" pixels). prepare_plate_depth decodes the depth
// channel and repairs each, in the order a compositor would:
//   1. decode (DepthDecode: encoding, invalid values -> holes, or sky when asked);
//   2. speckles: islands of at most `speckle_px` pixels that no neighbour
//      continues (depth ratio within `continuity`) become holes;
//   3. holes are filled from their surroundings, guided by the plate: each
//      hole pixel takes the colour-weighted median of the depths around it,
//      filled from the hole's edge inwards, so a fill follows the plate's
//      edges instead of blurring across a silhouette;
//   3b. noise: where the depth's measured noise (second differences of
//      inverse depth within surfaces, zero on any plane) is above
//      kNoisyDepth, each pixel takes the plane fitted in inverse depth
//      through its 5x5 neighbours that continue its surface: a noisy
//      surface near a blur cut of the layer split would otherwise fall into
//      two layers as speckle, each speck a silhouette of its own;
//   4. mixed pixels: a pixel whose depth lies between a nearer and a
//      farther surface across a discontinuity (a 3x3 neighbourhood spanning
//      `mixed_step`) takes the nearer surface's depth: part of it is the
//      foreground, whose blur must carry it, and no ring of intermediate
//      depth (a slice and a blur of its own) appears around a silhouette.
//      Each is checked again against its neighbours not so moved: one
//      within 2% of such a neighbour is on its surface and stays (beside
//      another mixed pixel, whose depth is no surface's).
//      Its parts (a foreground share and a background part, from its colour
//      between the two sides') are kept in PlateDepth::front_mixed: where the
//      blur field makes the front sharper than the background,
//      split_sharp_fronts splits it, so the background's share is blurred
//      with the background instead of staying as a sharp line of its colour
//      along the front's edge. (Split wherever the front is as blurred or
//      more, the split measured worse at the benchmark's depth edges:
//      docs/diffusion.md.)
//   5. holes at silhouettes: a sensor loses the pixels next to a depth step
//      (the projector's shadow on the far side, flying pixels filtered out),
//      which are the silhouette's mixed pixels; the fill alone makes each
//      all foreground or all background. A filled hole whose neighbourhood
//      holds both sides of a step is decided by its colour between the
//      nearest measured pixels of each side: all one side's depth, or split
//      into a foreground share (its colour's) at the foreground's depth and
//      the background part (MixedPixel; a slice that holds both parts
//      takes it whole, at the foreground's depth). Where the two sides'
//      colours are too alike, or the pixel is no mix of them, the fill
//      stays.
// The focus tools read the prepared depth: the median depth in a small
// window around a pixel (robust to noise and holes) and a probe of depth,
// world position and blur at a pixel.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/status.h"

namespace gdof {

// Depth whose measured relative noise (DepthCleanupStats::noise) exceeds this
// is smoothed (step 3b): a sensor's is 0.2-1%, a renderer's Z about 1e-7,
// uint16 millimetres at 5 m about 1e-4 from quantisation.
inline constexpr double kNoisyDepth = 0.001;
inline constexpr int kNoiseSmoothingRadius = 2;  // a 5x5 window

struct DepthCleanupOptions {
    bool remove_speckles = true;
    bool mixed_pixels = true;  // steps 4 and 5
    // Step 3b: where the measured noise exceeds kNoisyDepth (a sensor's
    // depth, not a renderer's Z), each pixel takes the plane fitted in inverse
    // depth through its 5x5 neighbours on the same surface.
    bool smooth_noise = true;
    // Neighbouring depths within this ratio belong to one surface; a larger
    // step is a discontinuity (speckle islands, mixed pixels).
    double continuity = 1.05;
    // The largest island removed as a speckle, pixels; 0 = automatic:
    // max(4, pixels / 250000) (4 at 1080p, 33 at 4K).
    int speckle_px = 0;
    // A mixed pixel lies between neighbours at least this ratio apart (steps 4 and 5).
    double mixed_step = 1.10;
};

struct GDOF_API DepthCleanupStats {
    std::size_t pixels = 0;
    std::size_t holes = 0;     // invalid after decoding (speckles not counted)
    std::size_t speckles = 0;  // pixels of removed islands (then filled as holes)
    std::size_t filled = 0;    // holes and speckles given a depth
    std::size_t silhouette_holes = 0;  // of them, next to a depth step and decided by their colour
    std::size_t sky = 0;       // pixels at infinite depth
    std::size_t mixed = 0;     // mixed pixels given the nearer surface's depth (step 4)
    std::size_t sharp_fronts = 0;  // of them, split where the front is sharper (split_sharp_fronts)
    double noise = 0.0;        // measured relative noise of the depth (standard deviation / depth)
    int noise_smoothing_radius = 0;  // the smoothing window's radius (0: not smoothed)
    std::string report() const;  // one line, for --stats
};

// A split silhouette pixel (step 5): `over` of the foreground part (colour
// fg_rgb, premultiplied, scaled by fg_share) on the background part (bg_rgb)
// gives the pixel's colour back.
struct MixedPixel {
    std::size_t index = 0;  // row-major over the window
    float fg_depth = 0;     // the foreground's depth (the pixel's own, in `depth`, is the background's)
    float fg_share = 0;     // the foreground's share of the pixel, in (0, 1)
    float bg_depth = 0;     // PlateDepth::front_mixed: the background's depth (else unused)
    float fg_rgb[3] = {0, 0, 0};
    float bg_rgb[3] = {0, 0, 0};
};

// The prepared depth of a plate over its data window (row-major).
struct GDOF_API PlateDepth {
    Roi window;
    // Metric depth along the viewing axis; +inf: sky. Every value is finite
    // or +inf (holes are filled). A mixed pixel's is its background's.
    std::vector<float> depth;
    std::vector<MixedPixel> mixed;  // by increasing index
    // Step 4's pixels whose colour tells their parts (by increasing index),
    // still whole at the foreground's depth: split_sharp_fronts splits them.
    std::vector<MixedPixel> front_mixed;
    DepthCleanupStats stats;
    bool has_mixed() const { return !mixed.empty(); }
    // The split of pixel `index`, or nullptr when it is not mixed.
    const MixedPixel* mixed_at(std::size_t index) const;
    // Pixel `index`'s entry of front_mixed, or nullptr.
    const MixedPixel* front_mixed_at(std::size_t index) const;
};

// Decodes channel `depth_channel` of `plate` (resolving a disparity decode
// with the camera, converting range to depth when decode.range) and cleans
// it; `plate`'s R, G, B guide the hole fill (none: the fill is unguided).
// Errors: a bad decode (naming the setting), a channel out of range, a depth
// channel with no valid value at all (nothing to fill from), every finite
// depth within the camera's focal length (a mis-scaled depth file).
GDOF_API Result<PlateDepth> prepare_plate_depth(const Image& plate, int depth_channel, const DepthDecode& decode,
                                                const Camera& camera, const DepthCleanupOptions& options = {},
                                                const Exec& exec = {});
// The same without a camera (a plate with no lens yet, probed to choose
// one): the depth as stored and decoded; a range (decode.range) or a
// disparity from a baseline needs the camera and is an error here, and no
// focal length is checked.
GDOF_API Result<PlateDepth> prepare_plate_depth(const Image& plate, int depth_channel, const DepthDecode& decode,
                                                const DepthCleanupOptions& options = {}, const Exec& exec = {});

// A front counts as sharper than its background when their blur radii
// differ by more than this, px.
inline constexpr double kSharpFrontPx = 0.5;
// Whether a step-4 pixel is split: its background blurs more than its front
// by more than min_dr px (false when either radius is NaN).
inline bool front_is_sharper(double front_radius, double bg_radius, double min_dr = kSharpFrontPx) {
    return bg_radius - front_radius > min_dr;
}

// Splits each of pd.front_mixed whose background blurs more than its front
// by more than min_dr px (bg_radius[k], px, for front_mixed[k]; `radius`
// per pixel of pd.depth, `fg_radius` per entry of pd.mixed): the pixel's
// depth becomes its background's, it joins pd.mixed (in index order, with
// its foreground's radius, the pixel's radius before, in fg_radius) and
// `radius` takes bg_radius. front_mixed is emptied. Returns how many were
// split (also in pd.stats.sharp_fronts).
GDOF_API std::size_t split_sharp_fronts(PlateDepth& pd, std::span<float> radius, std::vector<float>& fg_radius,
                                        std::span<const float> bg_radius, double min_dr = kSharpFrontPx);

// The median of the finite depths in a (2 r + 1)^2 window around pixel (x, y)
// (absolute coordinates), sky excluded; NaN when the window has none. A
// focus distance picked from the picture: robust to noise, holes and edges.
GDOF_API double depth_at(const PlateDepth& depth, int x, int y, int r = 2);

// The focus distance a pixel asks for: channel `depth_channel` decoded in
// the (2 r + 1)^2 window around (x, y) and depth_at's median of it; +inf for
// sky. Where the window holds no valid depth (a hole wider than it: a
// sensor's shadow, glass, a black surface), the depth the plate's
// preparation fills there under `cleanup`, which is the depth the defocus
// gives those pixels (`filled`; the whole plate is prepared only then).
// Errors: a pixel outside the data window (naming it), a bad decode, a plate
// without one valid depth.
struct FocusDistance {
    double distance = 0;
    bool filled = false;  // from the filled depth: nothing measured within r px
};
GDOF_API Result<FocusDistance> focus_distance_at(const Image& plate, int depth_channel, const DepthDecode& decode,
                                                 const Camera& camera, int x, int y,
                                                 const DepthCleanupOptions& cleanup = {}, const Exec& exec = {},
                                                 int r = 2);

// The camera of part `part` of `set` (resolve_camera with `lens`) focused
// at pixel (x, y): focus_distance_at on the part holding the depth (`part`
// when it has the source's depth channel, else the first flat part that
// has), decoded as `source` says and cleaned as `cleanup`, becomes the lens's
// focus distance. What --focus-at, the OFX Defocus's focus point and
// defocus(focus_at=) in Python do. Errors: no flat part with that depth
// channel, resolve_camera's, focus_distance_at's, and a depth within the
// lens's focal length, named as a depth decoding problem (almost always a
// 16-bit file, read as 0..1, decoded as millimetres: subject depth_scale).
struct FocusedCamera {
    Camera camera;
    FocusDistance focus;
};
GDOF_API Result<FocusedCamera> focus_camera_at(const ImageSet& set, std::size_t part, const LensOverrides& lens,
                                               const PositionSource& source, const DepthCleanupOptions& cleanup,
                                               int x, int y, const Exec& exec = {});
// The same for a camera from `metadata` and `display` focused on channel
// `depth_channel` of `plate`.
GDOF_API Result<FocusedCamera> focus_camera_at(const Metadata& metadata, const Roi& display, const LensOverrides& lens,
                                               const Image& plate, int depth_channel, const DepthDecode& decode,
                                               const DepthCleanupOptions& cleanup, int x, int y,
                                               const Exec& exec = {});

// What a pixel of a plate is: its depth (depth_at), world position and blur.
struct PixelProbe {
    int x = 0, y = 0;
    double depth = 0;       // NaN: no depth there; +inf: sky
    Vec3 position;          // world position at the pixel centre (NaN when no finite depth or no camera)
    double blur_px = 0;     // the field's blur radius there (NaN when no depth or no field)
    // A silhouette pixel the defocus splits into a foreground and a
    // background part: a filled hole at a silhouette (step 5), or a mixed
    // pixel at the edge of a front sharper than its background (step 4,
    // known only with a camera and a field). Its parts' share, depths and
    // blurs (NaN when not split; blurs NaN with no field).
    bool mixed = false;
    double fg_share = std::numeric_limits<double>::quiet_NaN();
    double fg_depth = std::numeric_limits<double>::quiet_NaN(), bg_depth = std::numeric_limits<double>::quiet_NaN();
    double fg_blur_px = std::numeric_limits<double>::quiet_NaN(), bg_blur_px = std::numeric_limits<double>::quiet_NaN();
};
GDOF_API Result<PixelProbe> probe_pixel(const PlateDepth& depth, const Camera& camera, const BlurField& field, int x, int y,
                                        int r = 2);
// The same with what is known: no camera (nullptr), no world position and
// no blur; no field, no blur.
GDOF_API Result<PixelProbe> probe_pixel(const PlateDepth& depth, const Camera* camera, const BlurField* field, int x,
                                        int y, int r = 2);
// A probe of pixel (x, y) of `plate` as the defocus prepares it: channel
// `depth_channel` decoded and cleaned (prepare_plate_depth, with the camera
// when there is one), then probe_pixel with what is known. What --probe and
// gdof.probe() print: a probe is how a focus is chosen, so it needs no lens.
GDOF_API Result<PixelProbe> probe_plate(const Image& plate, int depth_channel, const DepthDecode& decode,
                                        const DepthCleanupOptions& cleanup, const Camera* camera,
                                        const BlurField* field, int x, int y, const Exec& exec = {});

}  // namespace gdof
