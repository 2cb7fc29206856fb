// SCRATCH (not for commit): dump the layers of a plate as defocus builds them.
#include <cstdio>
#include <string>
#include "gdof/blur_field.h"
#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "gdof/plate.h"
#include "gdof/text_file.h"
using namespace gdof;
int main(int argc, char** argv) {
    if (argc < 4) return 2;
    Image img = io::read_flat(argv[1]).value();
    auto field = BlurField::parse(read_text(argv[2]).value()).value();
    auto cam = Camera::from_image(img).value();
    const int z = img.channel_index("Z");
    DepthCleanupOptions cl;
    if (getenv("NOSPECK")) cl.remove_speckles = false;
    if (getenv("NOMIXED")) cl.split_mixed = false;
    auto pd = prepare_plate_depth(img, z, DepthDecode{}, cam, cl).value();
    std::printf("%s\n", pd.stats.report().c_str());
    if (getenv("ROW")) {
        const int yy = atoi(getenv("ROW")), x0 = atoi(getenv("X0"));
        for (int x = x0; x < x0 + 14; ++x) {
            const std::size_t i = std::size_t(yy) * img.width() + x;
            const MixedPixel* m = pd.mixed_at(i);
            std::printf("x=%d raw %.4f depth %.4f fg %.4f share %.3f\n", x, img.plane(z)[i], pd.depth[i],
                        m ? m->fg_depth : -1.f, m ? m->fg_share : -1.f);
        }
    }
    std::vector<float> r(pd.depth.size()), rf;
    std::vector<PixelDepth> px;
    const Roi w = pd.window;
    for (int y = w.y0; y < w.y1; ++y) for (int x = w.x0; x < w.x1; ++x) px.push_back({x + 0.5, y + 0.5, pd.depth[px.size()]});
    (void)field.evaluate(cam, px, r);
    std::vector<PixelDepth> fpx;
    for (const MixedPixel& m : pd.mixed) fpx.push_back({px[m.index].x, px[m.index].y, m.fg_depth});
    rf.resize(fpx.size());
    (void)field.evaluate(cam, fpx, rf);
    SliceOptions so;
    so.depth = &pd;
    so.radius = r;
    so.fg_radius = rf;
    so.continue_surfaces = !getenv("NOCONT");
    double rmax = 0;
    for (float v : r) if (std::isfinite(v)) rmax = std::max(rmax, double(v));
    so.extend_px = rmax;
    auto layers = layers_from_depth_map(img, so).value();
    for (std::size_t i = 0; i < layers.size(); ++i) {
        std::printf("layer %zu %s window %s\n", i, layers[i].name.c_str(), to_string(layers[i].image.data_window()).c_str());
        ImageSet s;
        Image l = layers[i].image;
        s.parts.push_back(l);
        (void)io::write_image(std::string(argv[3]) + "/layer" + std::to_string(i) + ".exr", s);
    }
    // Speckle/mixed masks
    Image m = Image::with_channels({"R", "G", "B"}, w);
    for (std::size_t i = 0; i < pd.depth.size(); ++i) {
        m.plane(0)[i] = pd.mixed_at(i) ? 1.f : 0.f;
        m.plane(1)[i] = std::fabs(pd.depth[i] - img.plane(z)[i]) > 1e-4f * std::fabs(img.plane(z)[i]) ? 1.f : 0.f;
    }
    ImageSet s; s.parts.push_back(m);
    (void)io::write_image(std::string(argv[3]) + "/masks.exr", s);
}
