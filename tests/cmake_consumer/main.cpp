// Uses both installed libraries: builds an image, writes and re-reads it.
#include <cstdio>
#include <string>

#include "gdof/image.h"
#include "gdof/io/image_io.h"
#include "gdof/version.h"

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    gdof::Image img = gdof::Image::with_channels({"R", "G", "B", "A"}, gdof::Roi{-2, -1, 6, 5});
    img.at(0, 1, 1) = 0.25f;
    std::string path = std::string(argv[1]) + "/consumer.exr";
    if (auto st = gdof::io::write_flat(path, img); !st) {
        std::fprintf(stderr, "%s\n", st.message().c_str());
        return 1;
    }
    auto back = gdof::io::read_flat(path);
    if (!back) {
        std::fprintf(stderr, "%s\n", back.message().c_str());
        return 1;
    }
    bool same = back->data_window() == img.data_window() && back->at(0, 1, 1) == 0.25f;
    std::printf("gdof %s consumer: %s\n", gdof::version(), same ? "ok" : "MISMATCH");
    return same ? 0 : 1;
}
