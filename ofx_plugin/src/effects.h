// The effects in the bundle (one singleton each).
#pragma once

#include "ofx_effect.h"

namespace gdof::ofx {

Effect& defocus_effect();      // effect_defocus.cpp
Effect& focal_stack_effect();  // effect_focal_stack.cpp

}  // namespace gdof::ofx
