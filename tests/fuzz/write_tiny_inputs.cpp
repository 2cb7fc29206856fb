// Writes the inputs every harness must survive whatever it parses: the empty
// input and each of the 256 one-byte inputs, one file each, into the folder
// given. The ctest fixture of the fuzz_<name>_tiny tests (an empty input had
// once been left behind as a libFuzzer finding).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s FOLDER\n", argv[0]);
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    std::ofstream(dir / "empty", std::ios::binary | std::ios::trunc);
    for (int b = 0; b < 256; ++b) {
        char name[16];
        std::snprintf(name, sizeof name, "byte_%02x", b);
        const char c = char(b);
        std::ofstream(dir / name, std::ios::binary | std::ios::trunc).write(&c, 1);
    }
    for (int b = 0; b < 256; ++b) {
        char name[16];
        std::snprintf(name, sizeof name, "byte_%02x", b);
        if (std::filesystem::file_size(dir / name, ec) != 1 || ec) {
            std::fprintf(stderr, "cannot write %s in %s\n", name, argv[1]);
            return 1;
        }
    }
    return 0;
}
