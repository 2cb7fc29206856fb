// Camera overrides (Frame::lens, a LensOverrides): the flags have the names
// of the camera JSON keys, and replace what the image's metadata says;
// --lens-table sets them per frame of a sequence (a focus pull).
#include <cmath>

#include "cli.h"
#include "gdof/io/stack_sources.h"
#include "ops/ops.h"
#include "text_input.h"

namespace gdof::cli {

namespace {

using LensField = std::optional<double> LensOverrides::*;

double positive(const Step& s) {
    const double v = parse_double(s.flag, s.args[0]);
    if (!(v > 0) || !std::isfinite(v)) usage_error(s.flag + ": expected a positive number, got '" + s.args[0] + "'");
    return v;
}

Command lens_option(const char* name, const char* args, const char* help, LensField field) {
    return {.names = {name}, .args = args, .kind = Kind::Modifier, .group = "Blur field", .help = help,
            .run = [field](Frame& f, const Step& s) { f.lens.*field = positive(s); },
            .check = [](const Step& s) { positive(s); }};
}

// The lens of `frame` from the table at `path`; runtime errors naming it.
LensOverrides table_lens(const std::string& path, double frame) {
    const std::string source = "--lens-table '" + path + "'";
    auto rows = io::read_lens_table(read_flag_file("--lens-table", "lens table", path), source, io::LensTableKey::Frame);
    if (!rows) runtime_error(rows.message());
    auto lens = io::lens_at_frame(*rows, frame, source);
    if (!lens) runtime_error(lens.message());
    return *lens;
}

void apply_lens_table(Frame& f, const Step& s) {
    if (!f.frame) usage_error("--lens-table: gives each frame's lens: needs a sequence (--frames, or a #### input)");
    const LensOverrides t = table_lens(s.args[0], *f.frame);
    for (LensField field : {&LensOverrides::focal_length_mm, &LensOverrides::sensor_width_mm, &LensOverrides::f_number,
                            &LensOverrides::focus_distance})
        if (t.*field) f.lens.*field = t.*field;
}

}  // namespace

std::vector<Command> lens_commands() {
    using L = LensOverrides;
    return {
        lens_option("--focal-length-mm", "MM", "camera focal length in mm (overrides metadata)", &L::focal_length_mm),
        lens_option("--sensor-width-mm", "MM", "camera sensor width in mm (overrides metadata)", &L::sensor_width_mm),
        lens_option("--f-number", "N", "lens f-number (overrides metadata)", &L::f_number),
        lens_option("--focus-distance", "D", "lens focus distance in scene units (overrides metadata)", &L::focus_distance),
        lens_option("--scene-unit-mm", "MM", "millimetres per scene unit (default 1000: metres)", &L::scene_unit_mm),
        {.names = {"--lens-table"}, .args = "FILE", .kind = Kind::Modifier, .group = "Blur field",
         .help = "each frame's lens (--frames) from a CSV: a header of frame and any of focus_distance, f_number, "
                 "focal_length_mm, sensor_width_mm, then rows; the frame's row, else interpolated between rows "
                 "(focus in 1/distance), else the nearest end's; a lens flag after it replaces its column",
         .run = apply_lens_table,
         // A bad table stops the run before any frame is made.
         .preflight = [](const Session&, const Step& s) { table_lens(s.args[0], 0.0); }},
    };
}

}  // namespace gdof::cli
