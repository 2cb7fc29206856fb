// Small helpers for "gdof Focal Stack": a reference source shifted to a
// sub-window of the stack (composite_stack reads tiles relative to the
// selection's window), the desired focus cropped to that window, and an
// area-average reduction (a full-resolution composite shown at a render scale).
#pragma once

#include "gdof/compositing.h"
#include "gdof/focus_surfaces.h"
#include "gdof/image.h"

namespace gdof::ofx {

// Reads tile t of `inner` at t + (dx, dy).
class ShiftedStackPixels final : public StackPixels {
public:
    ShiftedStackPixels(StackPixels& inner, int dx, int dy) : inner_(inner), dx_(dx), dy_(dy) {}
    int size() const override { return inner_.size(); }
    Result<ReferenceInfo> info(int ref) override { return inner_.info(ref); }
    Status read_tile(int ref, const Roi& tile, float* rgba) override {
        return inner_.read_tile(ref, {tile.x0 + dx_, tile.y0 + dy_, tile.x1 + dx_, tile.y1 + dy_}, rgba);
    }

private:
    StackPixels& inner_;
    int dx_, dy_;
};

// The part of `d` over `window` (in d's coordinates, inside d.window).
DesiredFocus crop(const DesiredFocus& d, const Roi& window);

// Image over `target` (pixels at scale s) whose pixel (x, y) is the mean of
// the pixels of `full` (scale 1) in [x / s, (x + 1) / s) x [y / s, (y + 1) / s).
Image reduce(const Image& full, const Roi& target, double sx, double sy);

}  // namespace gdof::ofx
