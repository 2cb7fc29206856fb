// Colour at the edges: OpenColorIO conversions for reading and writing.
// Processing is always in scene-linear float (premultiplied while blurring).
//
// Config: `--colorconfig FILE`, else $OCIO, else a built-in fallback that
// knows "linear" (aliases: "scene_linear", "Linear", "lin_rec709", "raw" is
// no conversion) and "sRGB" (IEC 61966-2-1 piecewise curve, Rec.709
// primaries; aliases "srgb", "sRGB - Texture", "srgb_texture", "Utility -
// sRGB - Texture"), which is enough for 8-bit plates and PNG previews.
//
// What is converted: the colour channels only, that is every layer's R,G,B
// triple ("R","G","B", "diffuse.R" ..., also "r/g/b" and "red/green/blue").
// Alpha, depth, ids (UInt channels) and data layers (P, Pworld, Pref, N,
// Nworld, motion, velocity, uv, ...) are never touched, and a layer without
// all three of R,G,B is left alone.
//
// Alpha: conversions are applied to the values as stored. For premultiplied
// images (EXR) this converts premultiplied values, which is exact for linear
// (matrix) transforms and the usual compromise for curves; for PNG/JPEG input
// the stored values are unpremultiplied (straight), so the curve is applied
// to straight colour, as it should be.
//
// Thread safety: a ColourConfig is immutable after creation; processors are
// built once per (from, to) pair and cached; convert() may be called from
// any number of threads at once.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "gdof/deep.h"
#include "gdof/export.h"
#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof::io {

class GDOF_API ColourConfig {
public:
    // $OCIO if set (error if it does not load), else the built-in fallback.
    static Result<std::shared_ptr<const ColourConfig>> from_environment();
    static Result<std::shared_ptr<const ColourConfig>> from_file(const std::string& path);
    static std::shared_ptr<const ColourConfig> builtin();
    // Process-wide default used when an option leaves `colour` null:
    // from_environment() if it loads, else builtin().
    static const ColourConfig& default_config();

    virtual ~ColourConfig() = default;
    virtual std::string description() const = 0;
    virtual std::vector<std::string> colour_spaces() const = 0;
    // Canonical name in this config, or "" if unknown.
    virtual std::string resolve(const std::string& name) const = 0;
    virtual bool is_linear(const std::string& name) const = 0;
    // Converts the colour channels (R,G,B of each layer; alpha and data
    // channels such as Z, P, N, id are left alone) in place.
    virtual Status convert(Image& image, const std::string& from, const std::string& to) const = 0;

    // Converts n RGB values held in three planes (any may alias nothing else;
    // each plane has n floats) in place. Unknown names are errors naming them.
    virtual Status convert_planes(float* r, float* g, float* b, std::size_t n, const std::string& from,
                                  const std::string& to) const = 0;
    // Same rules as convert(Image&) for the samples of a deep image.
    Status convert(DeepImage& image, const std::string& from, const std::string& to) const;
};

// The colour channel triples of an image, in channel order of R: one entry
// per layer with Half/Float R, G and B channels that is not a data layer.
struct ColourTriple {
    std::string layer;  // "" for the unnamed layer
    int r = -1, g = -1, b = -1;
};
GDOF_API std::vector<ColourTriple> colour_channels(const std::vector<ChannelSpec>& channels);

// True for layers holding data rather than colour (P, N, motion, uv ...).
GDOF_API bool is_data_layer(const std::string& layer);

// The IEC 61966-2-1 sRGB transfer functions (extended past 1 by the power
// segment, linear below the knee including negative values).
GDOF_API float srgb_to_linear(float v);
GDOF_API float linear_to_srgb(float v);

}  // namespace gdof::io
