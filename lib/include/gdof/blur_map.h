// The blur field evaluated over an image: B at every pixel's world position
// (a position pass, or depth + camera), or at every deep sample. This is the
// per-pixel blur that method 3 diffuses with, that `gdof --eval-blur` writes
// for inspection and that the OFX plugin computes from its clips.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/deep.h"
#include "gdof/exec.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof {

// Which channels give a pixel's world position.
struct PositionSource {
    // "" = automatic: a position layer P, Pworld, p, position or Position with
    // .x/.y/.z, .X/.Y/.Z, .R/.G/.B, .r/.g/.b or .red/.green/.blue; else depth.
    // A layer name ("Pw") uses that layer; "a,b,c" names three channels.
    std::string position_channels;
    // "" = automatic: Z, depth.Z, Depth.Z, depth, Depth. Used when no position
    // pass is found (or always, when position_channels is "" and no P exists).
    std::string depth_channel;
    // How the depth channel's values encode depth (metric by default; inverse
    // depth, scaled integer counts, near/far-normalised: see camera.h).
    DepthDecode depth_decode;
};

// Position channels per the source, nullopt if the image has none (automatic
// mode); an error naming what is missing when they were asked for by name.
GDOF_API Result<std::optional<std::array<int, 3>>> find_position_channels(const Image& img, const std::string& spec);
// Depth channel index, -1 if none (automatic mode); an error naming it if asked for by name.
GDOF_API Result<int> find_depth_channel(const Image& img, const std::string& name);

// Evaluates B over the data window of `img` into `out` (one channel over
// exactly that window, any strides: Image::channel_view of an output channel,
// a planar view of a buffer; an error naming both shapes otherwise): from the
// position channels if found, else from depth + camera at the pixel centres.
// A sky pixel -- position not finite and depth +inf (a render under a lit
// environment: P = NaN, Z = +inf) -- takes B at infinite depth when the image
// also has a depth channel. Error if neither exists (naming the channels
// looked for). Parallel over rows; result independent of the thread count.
GDOF_API Status evaluate_blur_map(const BlurField& field, const Camera& camera, const Image& img, const PositionSource& source,
                                  const ImageView& out, const Exec& exec = {});

// Evaluates B for every sample of a deep image from its pixel centre and the
// sample's depth channel (z_channel < 0: the image's Z), into `out`, one
// value per sample in sample order (an error unless it has total_samples()).
GDOF_API Status evaluate_blur_deep(const BlurField& field, const Camera& camera, const DeepImage& img, int z_channel,
                                   std::span<float> out, const Exec& exec = {});

}  // namespace gdof
