// Reference pixels held in memory (compositing.h): images, and views of
// memory someone else owns (an OFX host's images, read without a copy).
#include <string>
#include <vector>

#include "gdof/compositing.h"

namespace gdof {

namespace {

Status out_of_range(int ref) { return Status::error("reference " + std::to_string(ref) + " out of range"); }

}  // namespace

MemoryStackPixels::MemoryStackPixels(std::vector<const Image*> images)
    : images_(std::move(images)), reads_(images_.size()) {}

long MemoryStackPixels::reads(int ref) const { return reads_[std::size_t(ref)].load(); }

Result<ReferenceInfo> MemoryStackPixels::info(int ref) {
    if (ref < 0 || ref >= size()) return out_of_range(ref);
    const Image& img = *images_[std::size_t(ref)];
    return ReferenceInfo{img.data_window(), img.display_window(), img.metadata};
}

Status MemoryStackPixels::read_tile(int ref, const Roi& tile, float* rgba) {
    if (ref < 0 || ref >= size()) return out_of_range(ref);
    reads_[std::size_t(ref)].fetch_add(1);
    const Image& img = *images_[std::size_t(ref)];
    const Image& first = *images_[0];
    if (img.width() != first.width() || img.height() != first.height())
        return Status::error("reference " + std::to_string(ref) + " is " + std::to_string(img.width()) + "x" +
                             std::to_string(img.height()) + " but reference 0 is " + std::to_string(first.width()) +
                             "x" + std::to_string(first.height()));
    if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > img.width() || tile.y1 > img.height())
        return Status::error("tile " + to_string(tile) + " outside the reference");
    const RgbaIndices c = find_rgba(img);
    const int ch[4] = {c.r, c.g, c.b, c.a};
    const Roi dw = img.data_window();
    float* out = rgba;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            for (int k = 0; k < 4; ++k) {
                const int cc = ch[k];
                *out++ = cc >= 0 ? img.sample(cc, dw.x0 + x, dw.y0 + y) : (k == 3 ? 1.0f : 0.0f);
            }
        }
    return Status::ok();
}

ViewStackPixels::ViewStackPixels(std::vector<ConstImageView> views, const Roi& grid)
    : views_(std::move(views)), grid_(grid) {}

Result<ReferenceInfo> ViewStackPixels::info(int ref) {
    if (ref < 0 || ref >= size()) return out_of_range(ref);
    return ReferenceInfo{grid_, grid_, {}};
}

Status ViewStackPixels::read_tile(int ref, const Roi& tile, float* rgba) {
    if (ref < 0 || ref >= size()) return out_of_range(ref);
    if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > grid_.width() || tile.y1 > grid_.height())
        return Status::error("tile " + to_string(tile) + " outside the reference");
    const ConstImageView& v = views_[std::size_t(ref)];
    if (!v.window.empty() && (v.nchannels < 3 || v.nchannels > 4 || !v.base))
        return Status::error("reference " + std::to_string(ref) + ": a view needs 3 or 4 channels, has " +
                             std::to_string(v.nchannels));
    float* out = rgba;
    for (int y = grid_.y0 + tile.y0; y < grid_.y0 + tile.y1; ++y)
        for (int x = grid_.x0 + tile.x0; x < grid_.x0 + tile.x1; ++x, out += 4) {
            if (!v.window.contains(x, y)) {
                out[0] = out[1] = out[2] = out[3] = 0.0f;
                continue;
            }
            for (int c = 0; c < 3; ++c) out[c] = v.at(c, x, y);
            out[3] = v.nchannels == 4 ? v.at(3, x, y) : 1.0f;
        }
    return Status::ok();
}

}  // namespace gdof
