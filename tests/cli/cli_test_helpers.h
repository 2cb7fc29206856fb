// Helpers for the CLI end-to-end tests: make input files with OpenImageIO
// directly (independent of gdof::io), read outputs back, list folders.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "test_support.h"

namespace gdof::test {

// Writes a float (or half) EXR with the given channels; value(x, y, c) fills it.
// setup may add attributes or change windows before writing.
inline void write_exr(const std::string& path, int w, int h, const std::vector<std::string>& channels,
                      const std::function<float(int, int, int)>& value,
                      const std::function<void(OIIO::ImageSpec&)>& setup = {},
                      OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
    OIIO::ImageSpec spec(w, h, int(channels.size()), type);
    spec.channelnames = channels;
    spec.alpha_channel = -1;
    spec.z_channel = -1;
    for (int c = 0; c < int(channels.size()); ++c) {
        if (channels[std::size_t(c)] == "A") spec.alpha_channel = c;
        if (channels[std::size_t(c)] == "Z") spec.z_channel = c;
    }
    if (setup) setup(spec);
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * channels.size());
    for (int y = 0; y < spec.height; ++y)
        for (int x = 0; x < spec.width; ++x)
            for (int c = 0; c < int(channels.size()); ++c)
                pixels[(std::size_t(y) * std::size_t(spec.width) + std::size_t(x)) * channels.size() + std::size_t(c)] =
                    value(x + spec.x, y + spec.y, c);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << OIIO::geterror();
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

// Reads a whole file (first subimage) as float; the spec goes to *spec.
inline std::vector<float> read_pixels(const std::string& path, OIIO::ImageSpec* spec = nullptr, int subimage = 0) {
    std::vector<float> pixels;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
        return pixels;
    }
    if (subimage > 0 && !in->seek_subimage(subimage, 0)) {
        ADD_FAILURE() << "no subimage " << subimage << " in " << path;
        return pixels;
    }
    const OIIO::ImageSpec& s = in->spec();
    pixels.resize(std::size_t(s.width) * std::size_t(s.height) * std::size_t(s.nchannels));
    EXPECT_TRUE(in->read_image(subimage, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) << in->geterror();
    if (spec) *spec = s;
    return pixels;
}

// A file's first subimage as float, with its spec.
struct Pixels {
    OIIO::ImageSpec spec;
    std::vector<float> values;
    // Channel c of pixel (x, y), counted from the data window's corner.
    float at(int x, int y, int c) const {
        return values[(std::size_t(y) * std::size_t(spec.width) + std::size_t(x)) * std::size_t(spec.nchannels) +
                      std::size_t(c)];
    }
};
inline Pixels read_image_pixels(const std::string& path) {
    Pixels p;
    p.values = read_pixels(path, &p.spec);
    return p;
}

// File names in a folder (not recursive), sorted.
inline std::vector<std::string> list_dir(const std::string& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

inline void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

inline std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

}  // namespace gdof::test
