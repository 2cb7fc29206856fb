// The camera and the blur field of an image part, shared by --eval-blur,
// --diffuse, --composite and --render (camera_field.cpp). Errors name `flag`
// and `where` (the image).
#pragma once

#include <string>

#include "frame.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/image_set.h"

namespace gdof::cli {

std::string image_name(const StackEntry& e);  // "'in.exr'" or "the top image"
// The camera of a part: its metadata with the --focal-length-mm ... overrides.
Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where);
// The camera of part `part` of `set`, focused at --focus-at's pixel when given
// (the depth there: of that part, else of the set's first flat part with a
// depth channel).
Camera image_camera(const Frame& f, const ImageSet& set, std::size_t part, const std::string& flag,
                    const std::string& where);
// The camera of `md` and `display` focused at --focus-at's pixel, from depth
// channel `zc` of `plate`.
Camera focus_camera(const Frame& f, const Metadata& md, const Roi& display, const Image& plate, int zc,
                    const std::string& where);
// --blurfield (refocused at the camera's focus distance after --focus-at),
// else a thin lens from the camera's lens data.
BlurField field_for(const Frame& f, const Camera& camera, const std::string& flag, const std::string& where);

}  // namespace gdof::cli
