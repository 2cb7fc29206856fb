// Clips and the images fetched from them (the image effect suite), and the
// pixel frame: render scale and the flip between OFX pixel coordinates
// (origin bottom-left, y up) and gdof's (y down, row 0 at the top of the
// display window, as in EXR), so blur fields, cameras and B-spline surfaces
// see the same pixel grid as the CLI.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "gdof/image.h"
#include "ofx_properties.h"

namespace gdof::ofx {

struct PixelFrame;

// Defines a clip in describeInContext: label, the components it takes, tiles
// supported; `temporal`: the effect reads other frames of it.
Props define_clip(OfxImageEffectHandle descriptor, const char* name, const char* label,
                  std::initializer_list<const char*> components, bool optional, bool temporal = false);

class Clip {
public:
    Clip(OfxImageEffectHandle effect, const char* name);
    const std::string& name() const { return name_; }
    OfxImageClipHandle handle() const { return clip_; }
    Props props() const { return props_; }
    bool connected() const;
    std::string components() const;  // as mapped by the clip preferences
    std::string pixel_depth() const;
    std::string premultiplication() const;
    OfxRectD region_of_definition(double time) const;

private:
    std::string name_;
    OfxImageClipHandle clip_ = nullptr;
    Props props_;
};

// An image of a clip at a time; released when destroyed.
class ClipImage {
public:
    // region: canonical coordinates, nullptr = what the host decides (the RoI).
    ClipImage(const Clip& clip, double time, const OfxRectD* region = nullptr);
    ~ClipImage();
    ClipImage(const ClipImage&) = delete;
    ClipImage& operator=(const ClipImage&) = delete;

    bool valid() const { return props_.valid(); }
    const std::string& clip() const { return clip_; }
    const OfxRectI& bounds() const { return bounds_; }
    const std::string& components() const { return components_; }
    const std::string& pixel_depth() const { return depth_; }
    const std::string& premultiplication() const { return premult_; }
    int ncomponents() const { return ncomp_; }
    // Float pixel at OFX pixel coordinates inside bounds() (float images only).
    float* pixel(int x, int y) const {
        return reinterpret_cast<float*>(static_cast<char*>(data_) + std::ptrdiff_t(y - bounds_.y1) * rowbytes_) +
               std::ptrdiff_t(x - bounds_.x1) * ncomp_;
    }
    bool contains(int x, int y) const { return x >= bounds_.x1 && x < bounds_.x2 && y >= bounds_.y1 && y < bounds_.y2; }
    // The part of the image over `region` (OFX pixels) as a gdof view of the
    // host's memory, no copy (float images, after require()): interleaved, in
    // gdof coordinates, so rows run top-down and the row stride is negative
    // for the host's bottom-up rows.
    ImageView view(const PixelFrame& f, const OfxRectI& region) const;
    // Throws an Error naming the clip unless the image is float with one of `components`.
    void require(std::initializer_list<const char*> components) const;

private:
    std::string clip_;
    Props props_;
    void* data_ = nullptr;
    OfxRectI bounds_{0, 0, 0, 0};
    int rowbytes_ = 0;
    int ncomp_ = 0;
    std::string components_, depth_, premult_;
};

// Number of channels of an OFX component string (RGBA 4, RGB 3, Alpha 1; 0 otherwise).
int component_count(const std::string& components);

// Render scale, pixel aspect ratio and the y flip around the display window
// (the project extent in pixels).
struct PixelFrame {
    double sx = 1, sy = 1, par = 1;
    int top = 0;   // OFX pixel y just above the display window's top row
    Roi display;   // gdof coordinates

    Roi to_gdof(const OfxRectI& r) const { return {r.x1, top - r.y2, r.x2, top - r.y1}; }
    OfxRectI to_ofx(const Roi& r) const { return {r.x0, top - r.y1, r.x1, top - r.y0}; }
    int gdof_y(int ofx_y) const { return top - 1 - ofx_y; }
    OfxRectI to_pixels(const OfxRectD& canonical) const;  // outward rounding
    OfxRectD to_canonical(const OfxRectI& pixels) const;
};
// The frame of an effect instance at a render scale (from the project extent).
PixelFrame pixel_frame(OfxImageEffectHandle effect, OfxPointD render_scale);
// A canonical rectangle as gdof pixels at the frame's scale.
inline Roi gdof_pixels(const PixelFrame& f, const OfxRectD& canonical) { return f.to_gdof(f.to_pixels(canonical)); }

// Copies components of a float host image into channels of `dst` over dst's
// data window (gdof coordinates): map = (host component, dst channel) pairs.
// Pixels outside the host image get `outside`.
void read_components(const ClipImage& src, const PixelFrame& f, Image& dst,
                     const std::vector<std::pair<int, int>>& map, float outside);
// A source clip image (RGBA or RGB, float) as float R, G, B, A over
// `window` (gdof coordinates), premultiplied (an unpremultiplied source is
// premultiplied; RGB is opaque where the host gave pixels); 0 outside the
// host image. Display window: the frame's.
Image premultiplied_rgba(const ClipImage& src, const PixelFrame& f, const Roi& window);
// Writes channels R, G, B, A of `src` (gdof coordinates) into the output
// image over `window` (OFX pixels): RGBA, or RGB (alpha dropped). Pixels of
// the window outside src's data window are written as 0.
void write_rgba(const Image& src, const PixelFrame& f, const ClipImage& out, const OfxRectI& window);

}  // namespace gdof::ofx
