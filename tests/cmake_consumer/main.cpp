// Uses both installed libraries: builds an image, writes and re-reads it
// as EXR and as PNG (the installed OpenImageIO module).
#include <cstdio>
#include <string>

#include "gdof/image.h"
#include "gdof/io/image_io.h"
#include "gdof/version.h"

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    gdof::Image img = gdof::Image::with_channels({"R", "G", "B", "A"}, gdof::Roi{-2, -1, 6, 5});
    img.at(0, 1, 1) = 0.25f;
    // The image written to `name` in the folder and read back, or an error.
    auto round_trip = [&](const std::string& name) -> gdof::Result<gdof::Image> {
        const std::string path = std::string(argv[1]) + "/" + name;
        if (auto st = gdof::io::write_flat(path, img); !st) return st;
        return gdof::io::read_flat(path);
    };
    auto exr = round_trip("consumer.exr");
    auto png = round_trip("consumer.png");
    for (const auto* r : {&exr, &png})
        if (!*r) {
            std::fprintf(stderr, "%s\n", r->message().c_str());
            return 1;
        }
    const bool same = exr->data_window() == img.data_window() && exr->at(0, 1, 1) == 0.25f &&
                      png->display_window().width() == img.display_window().width();
    std::printf("gdof %s consumer: %s\n", gdof::version(), same ? "ok" : "MISMATCH");
    return same ? 0 : 1;
}
