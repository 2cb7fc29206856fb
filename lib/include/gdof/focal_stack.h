// Focus/aperture stacks for method 2 (Kosloff & Barsky, section 3): a set of
// reference images of one view, each taken (rendered, photographed or
// extracted from a light field) with its own focus and aperture, and the
// depth-of-field interval [near, far] in which each is sharp.
//
// The manifest (JSON, documented in docs/compositing.md) is what every stack
// producer writes and what `gdof --composite` reads:
//
//   {
//     "gdof_stack": 1,
//     "coc_px": 1.0,               // acceptable CoC radius (output px) for near/far
//     "scene_unit_mm": 1000,       // mm per depth unit (metres)
//     "focal_length_mm": 50, "sensor_width_mm": 36,   // defaults for every reference
//     "width": 1920, "height": 1080,                  // resolution of every reference
//     "references": [
//       {"file": "ref.0001.exr", "focus_distance": 2.0, "f_number": 2.8},
//       {"file": "ref.0002.exr", "focus_distance": 4.0, "f_number": 8, "near": 3.1, "far": 5.9},
//       ...
//     ]
//   }
//
// A reference's near/far are given explicitly, or computed from its thin lens
// (focal length, f-number, focus distance, sensor width, width) for coc_px;
// one may be explicit and the other computed. With both explicit,
// focus_distance and f_number are optional.
// Light-field stacks give them explicitly (from the light field's geometry)
// and may record "focus_disparity" and "aperture_radius_views".
// Relative file names are resolved against the manifest's folder.
// "comment" (top level and per reference) and "source" (top level) are free
// text; any other unknown key is an error naming it.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

struct StackReference {
    std::string file;  // as written in the manifest
    std::string path;  // resolved against the manifest's folder
    double focus_distance = std::numeric_limits<double>::quiet_NaN();  // depth units
    double f_number = std::numeric_limits<double>::quiet_NaN();
    double focal_length_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: the stack's default
    double sensor_width_mm = std::numeric_limits<double>::quiet_NaN();
    double near = std::numeric_limits<double>::quiet_NaN();  // depth units
    double far = std::numeric_limits<double>::quiet_NaN();   // may be +inf ("inf" in JSON)
    // Light-field provenance (NaN when not from a light field).
    double focus_disparity = std::numeric_limits<double>::quiet_NaN();
    double aperture_radius_views = std::numeric_limits<double>::quiet_NaN();
};

struct FocalStack {
    std::vector<StackReference> references;
    double coc_px = 1.0;
    double scene_unit_mm = 1000.0;
    double focal_length_mm = std::numeric_limits<double>::quiet_NaN();
    double sensor_width_mm = std::numeric_limits<double>::quiet_NaN();
    int width = 0, height = 0;  // 0: unknown (taken from the first reference read)
    std::string base_dir;       // folder the manifest came from
};

// Parses a manifest; errors name the key path ("references[3].f_number: ...").
// Fills near/far from the thin lens where not given; rejects duplicate
// (focus, aperture) entries (naming both), near > far, entries without a
// "file" (only the JSON is checked here: file existence is the reader's job,
// io::check_stack_files).
GDOF_API Result<FocalStack> parse_stack_manifest(const std::string& json_text, const std::string& base_dir);
// Serialises a stack (near/far always written; "inf" for an infinite far).
GDOF_API std::string format_stack_manifest(const FocalStack& stack);

// Stack producers (light-field extraction, ray-traced stacks) call this after
// each reference is done (index, image) so a front end can write it and free
// it. A failed Status stops the producer.
using StackSink = std::function<Status(std::size_t index, Image&& image)>;

}  // namespace gdof
