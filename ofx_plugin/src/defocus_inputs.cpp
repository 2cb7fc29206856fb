#include "defocus_inputs.h"

#include <cmath>
#include <limits>

namespace gdof::ofx {

int component_index(const ClipImage& img, const std::string& channel) {
    static const std::string rgba = "RGBA";
    if (img.components() == kOfxImageComponentAlpha) return channel == "A" ? 0 : -1;
    const auto i = rgba.find(channel);
    if (channel.size() != 1 || i == std::string::npos || int(i) >= img.ncomponents()) return -1;
    return int(i);
}

void add_depth(Image& img, const ClipImage& depth, const DefocusParams& p, const PixelFrame& f, const Camera& camera) {
    depth.require({kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const int z = img.add_channel({"Z", PixelType::Float});
    if (p.depth_pass == "depth") {
        const int comp = component_index(depth, p.depth_channel);
        if (comp < 0)
            fail("clip 'Depth': parameter 'depth_channel' is " + p.depth_channel + " but the clip has no such channel (" +
                 std::string(depth.ncomponents() == 1 ? "Alpha" : depth.ncomponents() == 3 ? "RGB" : "RGBA") + ")");
        read_components(depth, f, img, {{comp, z}}, nan);
        return;
    }
    if (depth.ncomponents() < 3) fail("clip 'Depth': a position pass needs RGB or RGBA (P.x, P.y, P.z), got Alpha");
    const int px = img.add_channel({"P.x", PixelType::Float});
    const int py = img.add_channel({"P.y", PixelType::Float});
    const int pz = img.add_channel({"P.z", PixelType::Float});
    read_components(depth, f, img, {{0, px}, {1, py}, {2, pz}}, nan);
    const Roi w = img.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            const Vec3 pw{img.at(px, x, y), img.at(py, x, y), img.at(pz, x, y)};
            const bool finite = std::isfinite(pw.x) && std::isfinite(pw.y) && std::isfinite(pw.z);
            img.at(z, x, y) = finite ? float(camera.project(pw).depth) : nan;
        }
}

void add_flat_depth(Image& img) {
    const int z = img.add_channel({"Z", PixelType::Float});
    std::fill(img.plane(z), img.plane(z) + img.npixels(), 1.0f);
}

Image map_image(const ClipImage& map, const PixelFrame& f) {
    map.require({kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha});
    std::vector<std::string> names;
    if (map.ncomponents() == 1) names = {"A"};
    else if (map.ncomponents() == 3) names = {"R", "G", "B"};
    else names = {"R", "G", "B", "A"};
    Image img = Image::with_channels(names, f.to_gdof(map.bounds()));
    img.set_display_window(f.display);
    std::vector<std::pair<int, int>> m;
    for (int c = 0; c < int(names.size()); ++c) m.push_back({c, c});
    read_components(map, f, img, m, 0.0f);
    return img;
}

}  // namespace gdof::ofx
