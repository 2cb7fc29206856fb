// The parameters of "gdof Defocus" and what they become: the blur-field JSON
// the library parses (BlurField::parse, so every kind behaves exactly as in a
// --blurfield file), the lens overrides of the camera, and the defocus
// settings. Parameter names are the blur-field JSON keys and the CLI flags
// (docs/ofx.md has the table).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/status.h"
#include "ofx_params.h"

namespace gdof::ofx {

inline constexpr int kMaxFocalPlanes = 6;

struct DefocusParams {
    std::string kind = "thin_lens";  // thin_lens | focal_planes | region | image_map
    double max_radius = 32;          // px at render scale 1
    // Camera and thin lens.
    double focal_length_mm = 50, sensor_width_mm = 36, f_number = 2.8, focus_distance = 2, scene_unit_mm = 1000;
    // focus_at: the thin lens focused at the depth of this point of the image
    // (canonical coordinates) instead of focus_distance (the CLI's --focus-at).
    bool use_focus_at = false;
    std::array<double, 2> focus_at{0, 0};
    // focal_planes
    std::vector<double> depths;
    double max_blur = 8, slope = 0;  // slope 0: not given
    std::string interpolation = "smooth";
    // region
    std::string shape = "sphere", mode = "focus";
    std::array<double, 3> center{0, 0, 5}, size{1, 1, 1}, normal{0, 0, 1};
    double radius = 1, thickness = 0, blur = 8, falloff = 1;
    // image_map (the Blur Map clip)
    std::string map_channel = "A";
    double map_scale = 10;
    // The Depth clip.
    std::string depth_pass = "depth";  // depth | position
    std::string depth_channel = "R";
    std::string depth_encoding = "metric";
    double depth_scale = 1, depth_near = 0.1, depth_far = 100;
    // Diffusion.
    std::string solver = to_string(DiffusionOptions{}.solver);  // the library's default (auto)
    int adi_steps = 0;
    bool pyramid = DiffusionOptions{}.pyramid;  // the library's default (on)
    int layers = 0;                 // 0: auto
    bool cut_by_blur = true;        // auto layers also cut by blur (off: auto:gaps)
    std::string analysis = "frame"; // frame | region
    // The filter (--diffuse / --bokeh / --vibrate) and the aperture
    // (--aperture: bokeh's kernel, vibrate's sample domain): image takes the
    // Aperture clip as the kernel.
    std::string filter = "diffusion";  // diffusion | bokeh | vibrate
    std::string aperture = "disc";     // disc | polygon | image
    int blades = 6;
    double rotation = 0, roundness = 0, squeeze = 1, cats_eye = 0;
    // vibrate (method 4): the PSF-field file (--psf-field; empty: the
    // default defocus field) and the aperture samples (--psf-samples).
    std::string psf_field;
    int psf_samples = 0;
};

void describe_defocus_params(ParamDefiner& d);
DefocusParams read_defocus_params(const ParamReader& r);

// Blur radii at render scale `scale`: the global clamp in pixels.
inline double max_radius_px(const DefocusParams& p, double scale) { return p.max_radius * scale; }
// {"blurfield": {...}, "max_radius": ...} with every pixel-sized value
// (max_radius, max_blur, slope, blur, map scale) multiplied by `scale`. A
// thin lens scales by itself: its radii follow the camera's image width.
std::string blur_field_json(const DefocusParams& p, double scale);
LensOverrides lens_overrides(const DefocusParams& p);
// Solver, layer split, depth source (channel "Z", decoded per the
// parameters; position passes as "P.x/y/z" with metric Z). Errors name the parameter.
// The aperture parameters (an image kernel's pixels are the effect's to add).
// vibrate: the PSF field read from the psf_field file (io::read_psf_field,
// so exactly as --psf-field; errors name the parameter, the file and the key).
Result<DefocusOptions> defocus_settings(const DefocusParams& p);

}  // namespace gdof::ofx
