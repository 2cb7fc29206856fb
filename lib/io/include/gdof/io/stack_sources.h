// Loading a focus/aperture stack from disk (method 2). A manifest either lists
// its references (focal_stack.h), or names them by a frame pattern and says
// where each reference's focus and aperture come from:
//
//   {"gdof_stack": 1, "coc_px": 1, "pattern": "ref.####.exr", "lens_from": "attributes"}
//       every file on disk matching the pattern; focus distance, f-number,
//       focal length and sensor width from its EXR attributes (focusDistance
//       or focus, fNumber or aperture or FNumber, focalLength, sensorWidth);
//   {"gdof_stack": 1, "coc_px": 1, "pattern": "shot_%02d.tif", "table": "lens.csv",
//    "focal_length_mm": 25, "sensor_width_mm": 12.8}
//       a CSV table with a header row: a "frame" (or "file") column and any of
//       focus_distance, f_number, focal_length_mm, sensor_width_mm, near, far.
//
// Both expand into an ordinary manifest and go through parse_stack_manifest,
// so near/far, duplicates and errors behave the same. Width and height come
// from the first reference's header when not given.
#pragma once

#include <string>

#include "gdof/focal_stack.h"
#include "gdof/status.h"

namespace gdof::io {

Result<FocalStack> load_stack(const std::string& manifest_path);

}  // namespace gdof::io
