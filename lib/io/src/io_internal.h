// Internal pieces of gdof::io shared between the image I/O source files.
// Not installed; no OIIO or OpenEXR types here.
#pragma once

#include <cstdint>
#include <functional>
#include <variant>
#include <string>
#include <vector>

#include "gdof/image_set.h"
#include "gdof/io/image_io.h"
#include "gdof/status.h"

namespace gdof::io::detail {

// "'path'" for messages.
std::string quoted(const std::string& path);

// Lower-case extension without the dot ("exr"), "" if none.
std::string extension_lower(const std::string& path);

// True if the file starts with the OpenEXR magic number.
bool has_exr_magic(const std::string& path);

// Attribute marking a part written with an empty data window (OpenEXR cannot
// store one, so a single zero pixel / zero-sample pixel is written instead).
inline constexpr const char* kEmptyDataWindowAttr = "gdof:emptyDataWindow";

// ---- OpenEXR (exr_read.cpp / exr_write.cpp) ----
// `display` is the name used in messages (the user's path, not the temp file).
Result<ImageSet> read_exr(const std::string& path);
// Parts by reference, so single images are written without a copy.
using PartRef = std::variant<const Image*, const DeepImage*>;
std::vector<PartRef> part_refs(const ImageSet& images);
Status write_exr(const std::string& file, const std::string& display, const std::vector<PartRef>& parts,
                 const WriteOptions& opts);

// ---- OpenImageIO, every other format (oiio_read.cpp / oiio_write.cpp) ----
struct OiioPartInfo {
    bool integer_data = false;       // 8/16/32-bit integer pixels (normalised to 0..1)
    int alpha_channel = -1;          // index of alpha in the part, -1 if none
    bool unassociated_alpha = false; // colour not yet multiplied by alpha
};
Result<ImageSet> read_oiio(const std::string& path, std::vector<OiioPartInfo>& info);
Status write_oiio(const std::string& file, const std::string& display, const Image& image,
                  const WriteOptions& opts);
// Clears OIIO's global (per-thread) error message so errors do not leak
// from one call into the next.
void clear_oiio_error();

// ---- Atomic writes (atomic_write.cpp) ----
// Temporary name beside the target that keeps the extension:
// "<dir>/.<name>.gdof-tmp-<pid>-<n>.<ext>".
std::string temp_path_for(const std::string& target);
// Checks the folder, runs `writer` on a temporary file, renames it over the
// target on success; removes the temporary file on any failure.
Status atomic_write(const std::string& target, const std::function<Status(const std::string& tmp)>& writer);

// ---- Colour at the edges (linearize.cpp) ----
// Converts the colour channels of `image` to scene-linear in place and sets
// oiio:ColorSpace to "linear". `source` is a colour space name known to the
// config; names that the config does not know are errors.
Status linearize(Image& image, const std::string& source, const ColourConfig& config, const std::string& path);
const ColourConfig& config_or_default(const ColourConfig* c);
// Canonical linear name used as the working space.
inline constexpr const char* kWorkingSpace = "scene_linear";  // a role in OCIO configs, known to the built-in one

// Multiplies colour channels (every channel except alpha and UInt channels)
// by alpha / divides where alpha > 0.
void premultiply(Image& image, int alpha);
void unpremultiply(Image& image, int alpha);

}  // namespace gdof::io::detail
