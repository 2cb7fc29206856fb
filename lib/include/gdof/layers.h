// Depth layers for method 3 (heat diffusion): every input users have becomes
// a list of layers, front (index 0) to back, each a flat image of
// premultiplied colour, coverage and depth that can be diffused on its own
// and composited back with `over`.
#pragma once

#include <string>
#include <vector>

#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/deep.h"
#include "gdof/exec.h"
#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/status.h"

namespace gdof {

// One layer. `image` has float channels R, G, B, A (premultiplied) and Z
// (depth along the view axis), and P.x, P.y, P.z when the source had world
// positions. Its data window covers the layer's pixels (it may be smaller
// than the input's). Where the layer has no coverage, A = 0 and Z is NaN
// unless the layer was extended (see layers_from_depth_map).
struct Layer {
    Image image;
    std::string name;          // "depth 2.10-3.40", "id 12", a part or layer name
    double depth_near = 0.0;   // smallest covered depth
    double depth_far = 0.0;    // largest covered depth
};

struct LayerSplit {
    enum class Mode {
        Auto,   // split where the sorted sample depths have gaps (clusters), at most max_layers
        Count,  // `count` layers of equal extent in 1/depth (even in defocus for a thin lens)
        ById,   // one layer per value of the uint channel `id_channel` (deep inputs)
    };
    Mode mode = Mode::Auto;
    int count = 8;
    int max_layers = 32;
    std::string id_channel = "id";
};
// Parses "auto", "N" (count), "id" / "id:CHANNEL"; errors name the value.
Result<LayerSplit> parse_layer_split(const std::string& text);

// Deep image -> layers: samples grouped by depth (or id); within a layer a
// pixel's samples are composited front to back with `over`; Z of a layer
// pixel is the alpha-weighted mean depth of its samples.
Result<std::vector<Layer>> layers_from_deep(const DeepImage& deep, const LayerSplit& split, const Exec& exec = {});

// Multilayer / multipart EXR -> layers: every flat part, and every layer
// prefix inside a part ("fg.R", "fg.A", "fg.P.x" or "fg.Z" ...), that has
// R, G, B, A and a position pass or depth becomes a layer, ordered front to
// back by median depth. Positions are found as blur_map.h describes.
Result<std::vector<Layer>> layers_from_parts(const ImageSet& set, const PositionSource& source);

// Flat RGBA + depth (live action) -> depth slices. Each pixel goes to the
// slice of its depth (alpha kept). Behind nearer slices, each slice is
// extended with a push-pull fill of its own colour and depth (opaque) up to
// `extend_px` pixels beyond its coverage (the farthest slice: everywhere),
// so blurring a foreground away reveals plausible background, not black.
struct SliceOptions {
    LayerSplit split;
    PositionSource source;   // depth channel and its encoding
    double extend_px = 0.0;  // typically the largest blur radius of the image
};
Result<std::vector<Layer>> layers_from_depth_map(const Image& rgba_depth, const SliceOptions& options,
                                                 const Exec& exec = {});

// Deep image flattened front to back with `over` (premultiplied): R, G, B, A
// (float) and Z = depth of the nearest sample (NaN where there is none).
Result<Image> flatten_deep(const DeepImage& deep);

// Composites layers (front = index 0) back to front with `over` into an
// image of float R, G, B, A over `window`; layers may have any data windows.
Image composite_layers(const std::vector<const Image*>& front_to_back, const Roi& window);

}  // namespace gdof
