// The camera and the blur field of an image part, shared by --eval-blur,
// --diffuse, --composite and --render (camera_field.cpp). Errors name `flag`
// and `where` (the image).
#pragma once

#include <string>

#include "frame.h"
#include "gdof/blur_field.h"
#include "gdof/camera.h"

namespace gdof::cli {

std::string image_name(const StackEntry& e);  // "'in.exr'" or "the top image"
// The camera of a part: its metadata with the --focal-length-mm ... overrides.
Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where);
// --blurfield, else a thin lens from the camera's lens data.
BlurField field_for(const Frame& f, const Camera& camera, const std::string& flag, const std::string& where);

}  // namespace gdof::cli
