// Reference pixels of a focus/aperture stack read from files, tile by tile,
// through an OpenImageIO ImageCache (gdof::StackPixels for method 2;
// OpenImageIO is loaded when the first reader is made: lib/io/src/oiio).
//
// - A file is opened only when one of its tiles (or its info) is first asked
//   for, so references that no pixel selects are never opened;
//   files_opened() counts the distinct references opened so far.
// - Memory is bounded by the cache size (untiled files are read in strips of
//   `cache_tile` rows); the stack never has to fit in memory. All readers of
//   a process share one ImageCache (its size and strip height are set by the
//   last reader created); a reader releases its files when destroyed.
// - Colour is linearised as io::read_image does: EXR is scene-linear (unless
//   `colorspace` names its space); other formats use their oiio:ColorSpace
//   when the config knows it, else sRGB for integer data and linear for
//   float; straight alpha is premultiplied after linearising.
// - Channels: R, G, B, A by name (also r/g/b/a, red/green/blue/alpha); a file
//   with one channel is grey (R = G = B); missing alpha reads 1.
// - Every reference must have the stack's size (the manifest's width/height,
//   else the first reference opened) and the data window origin of the first
//   reference opened: otherwise an error naming the file and both sizes.
#pragma once

#include <memory>
#include <string>

#include "gdof/compositing.h"
#include "gdof/export.h"
#include "gdof/focal_stack.h"
#include "gdof/io/colour.h"
#include "gdof/status.h"

namespace gdof::io {

struct StackReaderOptions {
    bool linearize = true;
    std::string colorspace;                // overrides every reference's colour space
    const ColourConfig* colour = nullptr;  // nullptr: ColourConfig::default_config()
    double cache_memory_mb = 512.0;        // ImageCache budget
    int cache_tile = 64;                   // tile / strip height for untiled files
};

class GDOF_API StackReader final : public StackPixels {
public:
    static Result<std::unique_ptr<StackReader>> create(const FocalStack& stack, const StackReaderOptions& opts = {});
    ~StackReader() override;
    StackReader(const StackReader&) = delete;
    StackReader& operator=(const StackReader&) = delete;

    int size() const override;
    // Thread-safe. Tile in the stack's local coordinates ([0, w) x [0, h)).
    Status read_tile(int ref, const Roi& tile, float* rgba) override;
    // Opens reference `ref` if needed (checking its size) and describes it
    // (gdof::ReferenceInfo: windows and header).
    Result<ReferenceInfo> info(int ref) override;
    // Distinct references opened so far (by this reader).
    int files_opened() const;
    // OpenImageIO's own count of files the cache has opened since this reader
    // was created (stat:unique_files of the shared cache; files shared with
    // another live reader are not counted again).
    int cache_files_opened() const;

private:
    StackReader() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Every file listed in the stack exists and all have one size, the
// manifest's width/height when given (an error naming the first missing or
// mismatched one and its manifest entry). Reads only the headers.
GDOF_API Status check_stack_files(const FocalStack& stack);

}  // namespace gdof::io
