// Colour at the edges: OpenColorIO conversions for reading and writing.
// Processing is always in scene-linear float (premultiplied while blurring).
//
// Config: `--colorconfig FILE`, else $OCIO, else a built-in fallback that
// knows "linear" (aliases: "scene_linear", "Linear", "lin_rec709", "raw" is
// no conversion) and "sRGB" (IEC 61966-2-1 piecewise curve, Rec.709
// primaries; aliases "srgb", "sRGB - Texture", "srgb_texture", "Utility -
// sRGB - Texture"), which is enough for 8-bit plates and PNG previews.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gdof/image.h"
#include "gdof/status.h"

namespace gdof::io {

class ColourConfig {
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
};

}  // namespace gdof::io
