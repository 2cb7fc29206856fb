// Light fields from files: a grid of sub-aperture views named by a pattern
// with row and column indices, or a folder named like the Stanford Light
// Field Archive; the light field's geometry (lf.json) and the list of
// (focus, aperture) references to extract (stack.json). Both JSON formats are
// documented in docs/lightfield.md; unknown keys and bad values are errors
// naming the key.
//
// Sources
// - A pattern with two printf integer fields, "views/2067_%02d_%02d.png": the
//   first is the row, the second the column. The indices present on disk are
//   discovered; they must form a full rectangle (rows min..max x columns
//   min..max): a missing view is an error naming the file expected.
// - A folder of Stanford-archive views, "out_RR_CC_<y>_<x>[_].png" (RR row,
//   CC column; the camera positions after them are not used: geometry comes
//   from lf.json). A missing view is an error naming "out_RR_CC_*".
// Views are read with gdof::io::read_image (8-bit sRGB PNG/JPEG are linearised
// by default), must be flat, and must all have the same size and channels.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/io/image_io.h"
#include "gdof/lightfield.h"
#include "gdof/status.h"

namespace gdof::io {

// lf.json.
struct LightFieldConfig {
    double disparity_at_infinity = 0.0;
    double focal_baseline = std::numeric_limits<double>::quiet_NaN();  // NaN: from baseline etc., else 1
    double baseline = std::numeric_limits<double>::quiet_NaN();         // scene units per view step (signed)
    double focal_length_mm = std::numeric_limits<double>::quiet_NaN();
    double sensor_width_mm = std::numeric_limits<double>::quiet_NaN();
    double scene_unit_mm = 1000.0;
    std::optional<std::array<int, 2>> center;  // file indices (row, column) of the central view
    std::optional<Roi> crop;                   // pixels of the views, half-open
};

GDOF_API Result<LightFieldConfig> parse_lightfield_config(const std::string& json_text, const std::string& where = "lf.json");
GDOF_API Result<LightFieldConfig> read_lightfield_config(const std::string& path);

// stack.json -> the references to extract.
GDOF_API Result<ExtractStackOptions> parse_extract_stack_options(const std::string& json_text, const std::string& where = "stack.json");
GDOF_API Result<ExtractStackOptions> read_extract_stack_options(const std::string& path);

// The files of a light field on disk (no pixels read).
struct LightFieldFiles {
    int first_row = 0, first_col = 0;  // file indices of grid view (0, 0)
    int rows = 0, cols = 0;
    std::vector<std::string> files;  // row-major
};
GDOF_API Result<LightFieldFiles> find_lightfield_views(const std::string& source);

// Finds, reads (in parallel) and checks the views; applies the config
// (geometry, central view, crop). Cancellation and progress through exec.
GDOF_API Result<LightField> load_lightfield(const std::string& source, const LightFieldConfig& config = {},
                                            const ReadOptions& read = {}, const Exec& exec = {});
// Geometry from a config for views `width_px` wide (before any crop).
GDOF_API Result<LightFieldGeometry> lightfield_geometry(const LightFieldConfig& config, int width_px);

}  // namespace gdof::io
