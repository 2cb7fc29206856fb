// Numbers in messages, one way: printf's %g with a given count of
// significant digits ("0.5", "1e+30", "inf", "nan"). Not installed.
#pragma once

#include <string>

#include "gdof/export.h"

namespace gdof {

// `v` with `significant` significant digits (10 by default: what the
// parsers' errors show; 6 for measurements, as in "blur radius 12.3457 px").
GDOF_API std::string format_number(double v, int significant = 10);

}  // namespace gdof
