// The README's OpenFX picture: the example scene through "gdof Defocus" in
// the test host (tests/ofx), shown as a host's viewer would show it: the
// Source and the effect's output side by side, labelled.
//
//   gdof_ofx_readme_picture BUNDLE_BINARY SCENE.exr OUT.png
//
// The field is examples/scene/two_planes.json's, set through the effect's
// parameters (focal planes at depths 2.9 and 12.6, 10 px between).
#include <cstdio>
#include <string>

#include "gdof/io/image_io.h"
#include "ofx/ofx_test_host.h"

using namespace gdof;
using namespace gdof::ofxtest;

namespace {

// A 5 x 7 pixel font for the few letters of the labels (rows top first).
const char* glyph(char c) {
    switch (c) {
        case 'S': return "01111100001000001110000010000111110";
        case 'O': return "01110100011000110001100011000101110";
        case 'U': return "10001100011000110001100011000101110";
        case 'R': return "11110100011000111110101001001010001";
        case 'C': return "01110100011000010000100001000101110";
        case 'E': return "11111100001000011110100001000011111";
        case 'G': return "01110100011000010111100011000101111";
        case 'D': return "11110100011000110001100011000111110";
        case 'F': return "11111100001000011110100001000010000";
        default: return nullptr;
    }
}

void text(Image& img, int x0, int y0, const std::string& s, int scale, float value) {
    for (std::size_t k = 0; k < s.size(); ++k) {
        const char* g = glyph(s[k]);
        if (g)
            for (int r = 0; r < 7; ++r)
                for (int c = 0; c < 5; ++c)
                    if (g[r * 5 + c] == '1')
                        for (int v = 0; v < scale; ++v)
                            for (int u = 0; u < scale; ++u)
                                for (int ch = 0; ch < 3; ++ch)
                                    img.at(ch, x0 + int(k) * 6 * scale + c * scale + u, y0 + r * scale + v) = value;
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s BUNDLE_BINARY SCENE.exr OUT.png\n", argv[0]);
        return 2;
    }
    auto scene = io::read_flat(argv[2]);
    if (!scene) {
        std::fprintf(stderr, "%s: %s\n", argv[2], scene.message().c_str());
        return 1;
    }
    const Image& in = *scene;
    const int W = in.width(), H = in.height();
    const RgbaIndices rgba = find_rgba(in);
    const int zc = in.channel_index("Z");
    if (rgba.a < 0 || zc < 0) {
        std::fprintf(stderr, "%s: needs R, G, B, A and Z\n", argv[2]);
        return 1;
    }

    Host host;
    std::string err;
    if (!host.load(argv[1], &err)) {
        std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str());
        return 1;
    }
    const char* id = "org.gdof.Defocus";
    if (host.describe(id) != kOfxStatOK || host.describe_in_context(id, kOfxImageEffectContextGeneral) != kOfxStatOK) {
        std::fprintf(stderr, "describe failed\n");
        return 1;
    }
    auto fx = host.create_instance(id, kOfxImageEffectContextGeneral, W, H);
    ClipFrame src = ClipFrame::make(W, H, kOfxImageComponentRGBA), depth = ClipFrame::make(W, H, kOfxImageComponentAlpha);
    const Roi dw = in.data_window();
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int oy = H - 1 - y;  // OFX rows go up
            const int ch[4] = {rgba.r, rgba.g, rgba.b, rgba.a};
            for (int c = 0; c < 4; ++c) src.at(x, oy, c) = in.at(ch[c], dw.x0 + x, dw.y0 + y);
            depth.at(x, oy, 0) = in.at(zc, dw.x0 + x, dw.y0 + y);
        }
    fx->connect("Source", src);
    fx->connect("Depth", depth);
    fx->set_choice("depth_channel", "A");
    fx->set_choice("kind", "focal_planes");
    fx->set_int("depths_count", 2);
    fx->set("depths_1", 2.9);
    fx->set("depths_2", 12.6);
    fx->set("max_blur", 10);
    fx->set("slope", 6);
    fx->set_choice("interpolation", "smooth");
    fx->set("max_radius", 10);
    const Rendered out = fx->render(0, {1, 1});
    if (out.status != kOfxStatOK) {
        std::fprintf(stderr, "render failed: %s\n", fx->persistent_message().c_str());
        return 1;
    }

    // The "viewer": dark background, two panels with a label above each.
    const int pad = 16, label = 7 * 2 + 12;
    const Roi canvas{0, 0, 2 * W + 3 * pad, H + 2 * pad + label};
    Image pic = Image::with_channels({"R", "G", "B"}, canvas);
    for (int c = 0; c < 3; ++c) std::fill(pic.plane(c), pic.plane(c) + pic.npixels(), 0.012f);
    const int top = pad + label;
    for (int panel = 0; panel < 2; ++panel) {
        const int x0 = pad + panel * (W + pad);
        for (int y = -1; y <= H; ++y)
            for (int x = -1; x <= W; ++x) {
                const bool border = y < 0 || y >= H || x < 0 || x >= W;
                for (int c = 0; c < 3; ++c) {
                    float v = 0.08f;
                    if (!border) {
                        const float a = panel == 0 ? src.at(x, H - 1 - y, 3) : out.at(x, H - 1 - y, 3);
                        const float col = panel == 0 ? src.at(x, H - 1 - y, c) : out.at(x, H - 1 - y, c);
                        v = col + (1.0f - a) * 0.012f;  // over the viewer's background
                    }
                    pic.at(c, x0 + x, top + y) = v;
                }
            }
        text(pic, x0, pad, panel == 0 ? "SOURCE" : "GDOF DEFOCUS", 2, 0.6f);
    }
    if (Status st = io::write_flat(argv[3], pic); !st) {
        std::fprintf(stderr, "%s: %s\n", argv[3], st.message().c_str());
        return 1;
    }
    std::fprintf(stderr, "wrote %s (%dx%d)\n", argv[3], canvas.width(), canvas.height());
    return 0;
}
