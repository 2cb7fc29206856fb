// The parameters of "gdof Focal Stack" and what they become: the stack (a
// FocalStack from a manifest, or from the lens table through the manifest
// parser, so near/far and errors behave as for `gdof --composite`) and the
// desired focus surfaces (the surfaces JSON the library parses).
#pragma once

#include <string>
#include <vector>

#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/status.h"
#include "ofx_params.h"

namespace gdof::ofx {

inline constexpr int kMaxGrid = 4;

struct FocalStackParams {
    std::string stack_source = "frames";  // frames (of the Source clip) | files (of a manifest)
    std::string manifest;                 // JSON stack manifest (files; frames: lens per frame)
    std::string lens_table;               // frames: CSV, "frame" + lens / near / far columns
    int first_frame = 1;                  // frames + manifest: frame of the first reference
    double coc_px = 1, focal_length_mm = 50, sensor_width_mm = 36, scene_unit_mm = 1000;
    int soft = 1;
    std::string focus_source = "surfaces";  // surfaces (parameters) | surfaces_file | maps (Near / Far clips)
    std::string surfaces;                   // surfaces JSON file
    int grid = 2;                           // control points per side
    std::vector<double> near, far;          // grid x grid, top row first
    bool far_infinite = false, interpolate = false;
    std::string map_channel = "R";
};

void describe_focal_stack_params(ParamDefiner& d);
FocalStackParams read_focal_stack_params(const ParamReader& r);

// {"gdof_surfaces": 1, "interpolate": ..., "near": {"grid": ...}, "far": {"grid": ...}}.
std::string surfaces_json(const FocalStackParams& p);

// The stack of the Source clip's frames: references in order and, for each,
// its frame. From the manifest when one is given (reference i = frame
// first_frame + i; its files are not read), else from the lens table.
// `width` (pixels at full resolution) serves near/far computed from a lens.
struct FrameStack {
    FocalStack stack;
    std::vector<int> frames;
};
Result<FrameStack> frame_stack(const FocalStackParams& p, int width, int height);

}  // namespace gdof::ofx
