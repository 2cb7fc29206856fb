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

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gdof/camera.h"
#include "gdof/export.h"
#include "gdof/focal_stack.h"
#include "gdof/status.h"

namespace gdof::io {

GDOF_API Result<FocalStack> load_stack(const std::string& manifest_path);

// A lens table (CSV): the "table" of a manifest, or the OFX plugin's
// lens_table parameter. A header row names the columns, then one row per
// reference; blank lines and lines starting with '#' are skipped, cells are
// trimmed. Columns: the reference ("frame", or also "file" with
// LensTableKey::FrameOrFile) and any of focus_distance, f_number,
// focal_length_mm, sensor_width_mm, near, far. Number cells (frame too) are
// finite numbers; far may be "inf". Errors begin with `source` ("table
// 'lens.csv'", "parameter 'lens_table'") and name the line and column. A
// table without rows is no error here (the callers say what a row needs).
enum class LensTableKey { FrameOrFile, Frame };
struct LensTableRow {
    int line = 0;                     // 1-based line of the text
    std::optional<double> frame;      // the "frame" cell
    std::optional<std::string> file;  // the "file" cell
    // The other cells in column order, by column name; far "inf" is +inf.
    std::vector<std::pair<std::string, double>> values;
};
GDOF_API Result<std::vector<LensTableRow>> read_lens_table(const std::string& text, const std::string& source,
                                                           LensTableKey key = LensTableKey::FrameOrFile);

// The lens of frame `frame` of a sequence from a lens table keyed by frame
// (a focus pull, recorded on set or keyed by hand): the row of that frame,
// else the values interpolated between the rows before and after it (the
// focus distance linearly in 1 / distance, as a focus ring turns; the
// others linearly), else the first or last row's. Columns focus_distance,
// f_number, focal_length_mm, sensor_width_mm, each a positive number. Errors
// begin with `source` and name the line: a table without rows, two rows of
// one frame, a near or far column (a stack's), a value that is not positive.
GDOF_API Result<LensOverrides> lens_at_frame(const std::vector<LensTableRow>& rows, double frame,
                                             const std::string& source);

}  // namespace gdof::io
