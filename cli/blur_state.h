// A parsed --blurfield (ops/blur.cpp makes it; the Frame and the session's
// cache share it).
#pragma once

#include <string>

#include "gdof/blur_field.h"

namespace gdof::cli {

struct BlurState {
    std::string path;
    BlurField field;
};

}  // namespace gdof::cli
