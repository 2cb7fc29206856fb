// Colour at the read/write edges: conversion to the scene-linear working
// space through ColourConfig, and alpha association for straight-alpha formats.
#include <cstdint>

#include "colour/linearize.h"
#include "files/files.h"

namespace gdof::io::detail {

const ColourConfig& config_or_default(const ColourConfig* c) { return c ? *c : ColourConfig::default_config(); }

Status linearize(Image& image, const std::string& source, const ColourConfig& config, const std::string& path) {
    if (config.resolve(source).empty())
        return Status::error(quoted(path) + ": unknown colour space '" + source + "' (" + config.description() + ")");
    if (!config.is_linear(source)) {
        Status s = config.convert(image, source, kWorkingSpace);
        if (!s) return s.prefix(quoted(path));
    }
    image.metadata.set_string("oiio:ColorSpace", "linear");
    return Status::ok();
}

namespace {

// op(colour, alpha) on every float colour sample (not the alpha channel).
template <class Op>
void with_alpha(Image& image, int alpha, Op op) {
    const float* a = image.plane(alpha);
    if (!a) return;
    const std::size_t np = image.npixels();
    for (int c = 0; c < image.nchannels(); ++c) {
        float* p = image.plane(c);
        if (c == alpha || !p) continue;
        for (std::size_t i = 0; i < np; ++i) op(p[i], a[i]);
    }
}

}  // namespace

void premultiply(Image& image, int alpha) {
    with_alpha(image, alpha, [](float& v, float a) { v *= a; });
}

void unpremultiply(Image& image, int alpha) {
    with_alpha(image, alpha, [](float& v, float a) {
        if (a > 0.0f) v /= a;
    });
}

}  // namespace gdof::io::detail
