// The operations, one file each: its rows of the command table, the checks
// of their values and what they run (registry.cpp lists them in help order).
//   general.cpp       --help, --version, -v, --threads, --progress, --no-progress, --stats
//   sequences.cpp     --frames, --skip-bad-frames
//   colour.cpp        --colorconfig, --iscolorspace, --colorconvert, --ocolorspace
//   io.cpp            input files (-i), -o, -d, --compression, --info
//   channels.cpp      --ch, --mulc
//   render.cpp        --render and its options, --stack (method 1: ray tracing)
//   render_stack.cpp  -o after --render --stack: a rendered focus/aperture stack
//   blur.cpp          --blurfield, --eval-blur
//   depth_source.cpp  --position-channels, --depth-channel, --depth-encoding, --depth-scale/-near/-far,
//                     --depth-invalid, --depth-invalid-value, --depth-max, --baseline, --depth-range
//   lens.cpp          --focal-length-mm, --sensor-width-mm, --f-number, --focus-distance, --scene-unit-mm
//   diffuse.cpp       --diffuse, --bokeh, --solver, --layers, --adi-steps (method 3: heat diffusion; bokeh)
//   aperture.cpp      --aperture (the iris for --render and --bokeh)
//   plate.cpp         --depth, --part, --view, --depth-cleanup, --focus-at, --probe (live-action plates)
//   composite.cpp     --composite, --surfaces, --near-map, --far-map, --soft, --aovs (method 2)
//   lightfield.cpp    --lightfield, --lf (method 2: stacks extracted from a light field)
#pragma once

#include <string>
#include <vector>

#include "command.h"
#include "frame.h"
#include "gdof/aperture.h"
#include "gdof/io/colour.h"

namespace gdof::cli {

std::vector<Command> general_commands();
std::vector<Command> sequence_commands();
std::vector<Command> colour_commands();
std::vector<Command> io_commands();
std::vector<Command> channel_commands();
std::vector<Command> render_commands();
std::vector<Command> blur_commands();
std::vector<Command> depth_source_commands();
std::vector<Command> lens_commands();
std::vector<Command> diffuse_commands();
std::vector<Command> aperture_commands();
// An aperture with its image kernel read (Kind::Image with only a path), or
// as it is; errors name `context` (the flag, or the scene key).
Aperture with_kernel_image(Frame& f, Aperture a, const std::string& context);
std::vector<Command> plate_commands();
std::vector<Command> composite_commands();
std::vector<Command> lightfield_commands();
std::vector<Command> focus_sweep_commands();

// lets_wait of the options of a pending --render (which also keep a
// pending --composite waiting, as the render runs first).
inline unsigned render_option_waits(const Frame&, const Step&) { return kRenderWaits | kCompositeWaits; }

// Entry points one operation's rows use from another.
void run_pending_render(Frame& f);                                // render.cpp
void set_render_aovs(Frame& f, const Step& step);                 // render.cpp: --aovs=LIST after --render
void run_pending_composite(Frame& f);                             // composite.cpp
void do_render_stack_output(Frame& f, const std::string& pattern);  // render_stack.cpp
void do_lightfield_output(Frame& f, const std::string& pattern);    // lightfield.cpp
// Canonical name of the scene-linear working space of a config ("" if none; colour.cpp).
std::string working_space(const io::ColourConfig& config);

}  // namespace gdof::cli
