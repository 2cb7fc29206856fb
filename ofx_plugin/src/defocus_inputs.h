// "gdof Defocus": the clips' pixels as the library's input image. The
// Source (premultiplied RGBA), and the Depth clip as Z (one channel, raw,
// decoded later by the library) or as P.x/P.y/P.z with Z computed from them
// through the camera, over a window in gdof pixel coordinates.
#pragma once

#include <string>

#include "defocus_params.h"
#include "gdof/camera.h"
#include "gdof/image.h"
#include "ofx_clips.h"

namespace gdof::ofx {

// Adds the depth of the Depth clip image to `img` (which has R, G, B, A):
// depth pass -> "Z" from the chosen channel (NaN outside the depth image:
// invalid, so far away); position pass -> "P.x", "P.y", "P.z" from R, G, B
// and "Z" their depth in `camera`. Errors name the clip and the channel.
void add_depth(Image& img, const ClipImage& depth, const DefocusParams& p, const PixelFrame& f, const Camera& camera);

// "Z" = 1 everywhere: one layer, for an image_map field without a Depth clip.
void add_flat_depth(Image& img);

// The Blur Map clip image as channels named after its components (R, G, B, A
// or A) over the image's bounds, display window = the frame's.
Image map_image(const ClipImage& map, const PixelFrame& f);

// Index of a channel name ("R", "G", "B", "A") in a clip image's components, or -1.
int component_index(const ClipImage& img, const std::string& channel);

}  // namespace gdof::ofx
