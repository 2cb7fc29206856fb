#include "common/format_number.h"

#include <cstdio>

namespace gdof {

std::string format_number(double v, int significant) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", significant, v);
    return buf;
}

}  // namespace gdof
