// Camera overrides (Frame::lens, a LensOverrides): the flags have the names
// of the camera JSON keys, and replace what the image's metadata says.
#include <cmath>

#include "cli.h"
#include "ops/ops.h"

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

}  // namespace

std::vector<Command> lens_commands() {
    using L = LensOverrides;
    return {
        lens_option("--focal-length-mm", "MM", "camera focal length in mm (overrides metadata)", &L::focal_length_mm),
        lens_option("--sensor-width-mm", "MM", "camera sensor width in mm (overrides metadata)", &L::sensor_width_mm),
        lens_option("--f-number", "N", "lens f-number (overrides metadata)", &L::f_number),
        lens_option("--focus-distance", "D", "lens focus distance in scene units (overrides metadata)", &L::focus_distance),
        lens_option("--scene-unit-mm", "MM", "millimetres per scene unit (default 1000: metres)", &L::scene_unit_mm),
    };
}

}  // namespace gdof::cli
