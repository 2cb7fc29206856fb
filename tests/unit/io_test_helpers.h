// Helpers for the image I/O tests: generated images and exact comparisons.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gdof/image_set.h"

namespace gdof::test {

// A file's bytes ("" when it cannot be read).
inline std::string file_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// Bit-exact float comparison (NaN payloads and -0 included).
inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline void expect_same_metadata(const Metadata& expected, const Metadata& actual, const std::string& what) {
    for (const auto& a : expected.attributes()) {
        const Attribute* b = actual.find(a.name);
        ASSERT_NE(b, nullptr) << what << ": attribute '" << a.name << "' missing";
        EXPECT_EQ(a.type, b->type) << what << ": attribute '" << a.name << "'";
        EXPECT_EQ(a.text, b->text) << what << ": attribute '" << a.name << "'";
        ASSERT_EQ(a.numbers.size(), b->numbers.size()) << what << ": attribute '" << a.name << "'";
        for (std::size_t i = 0; i < a.numbers.size(); ++i)
            EXPECT_EQ(a.numbers[i], b->numbers[i]) << what << ": attribute '" << a.name << "' [" << i << "]";
    }
}

// Same channels (by name, any order) with the same types, windows, names and
// bit-identical pixels.
inline void expect_same_flat(const Image& a, const Image& b, const std::string& what) {
    EXPECT_EQ(a.data_window(), b.data_window()) << what;
    EXPECT_EQ(a.display_window(), b.display_window()) << what;
    EXPECT_EQ(a.name, b.name) << what;
    EXPECT_EQ(a.view, b.view) << what;
    ASSERT_EQ(a.nchannels(), b.nchannels()) << what;
    for (int c = 0; c < a.nchannels(); ++c) {
        const auto& ch = a.channel(c);
        int cb = b.channel_index(ch.name);
        ASSERT_GE(cb, 0) << what << ": channel '" << ch.name << "' missing";
        EXPECT_EQ(ch.type, b.channel(cb).type) << what << ": channel '" << ch.name << "'";
        std::size_t bad = 0, first = 0;
        for (std::size_t i = 0; i < a.npixels(); ++i) {
            bool eq = ch.type == PixelType::UInt ? a.uplane(c)[i] == b.uplane(cb)[i]
                                                  : same_bits(a.plane(c)[i], b.plane(cb)[i]);
            if (!eq && bad++ == 0) first = i;
        }
        EXPECT_EQ(bad, 0u) << what << ": channel '" << ch.name << "' differs at " << bad << " pixels, first at index "
                           << first;
    }
}

inline void expect_same_deep(const DeepImage& a, const DeepImage& b, const std::string& what) {
    EXPECT_EQ(a.data_window(), b.data_window()) << what;
    EXPECT_EQ(a.display_window(), b.display_window()) << what;
    EXPECT_EQ(a.name, b.name) << what;
    EXPECT_EQ(a.view, b.view) << what;
    ASSERT_EQ(a.sample_counts(), b.sample_counts()) << what << ": sample counts differ";
    ASSERT_EQ(a.nchannels(), b.nchannels()) << what;
    for (int c = 0; c < a.nchannels(); ++c) {
        const auto& ch = a.channel(c);
        int cb = b.channel_index(ch.name);
        ASSERT_GE(cb, 0) << what << ": channel '" << ch.name << "' missing";
        EXPECT_EQ(ch.type, b.channel(cb).type) << what << ": channel '" << ch.name << "'";
        std::size_t bad = 0;
        for (std::size_t i = 0; i < a.total_samples(); ++i) {
            bool eq = ch.type == PixelType::UInt ? a.usamples(c)[i] == b.usamples(cb)[i]
                                                  : same_bits(a.samples(c)[i], b.samples(cb)[i]);
            if (!eq) ++bad;
        }
        EXPECT_EQ(bad, 0u) << what << ": channel '" << ch.name << "' differs at " << bad << " samples";
    }
}

inline void expect_same_set(const ImageSet& a, const ImageSet& b, const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string w = what + " part " + std::to_string(i);
        ASSERT_EQ(a.is_deep(i), b.is_deep(i)) << w;
        if (a.is_deep(i)) expect_same_deep(a.deep(i), b.deep(i), w);
        else expect_same_flat(a.flat(i), b.flat(i), w);
        expect_same_metadata(a.metadata(i), b.metadata(i), w);
    }
}

// Value exactly representable as half: multiples of 1/256 below 8.
inline float half_value(std::size_t i, int salt) { return float(int((i * 37 + std::size_t(salt) * 101) % 2048)) / 256.0f; }

// A deep image with 0..5 samples per pixel (pseudo-random), Z, ZBack, RGBA
// half and an id channel with values above 2^24.
inline DeepImage make_deep(Roi data, Roi display, bool tiled) {
    DeepImage d({{"A", PixelType::Half},
                 {"B", PixelType::Half},
                 {"G", PixelType::Half},
                 {"R", PixelType::Half},
                 {"Z", PixelType::Float},
                 {"ZBack", PixelType::Float},
                 {"id", PixelType::UInt}},
                data, display);
    std::vector<std::uint32_t> counts(d.npixels());
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = std::uint32_t((i * 7 + i / 7) % 6);
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (int c = 0; c < d.nchannels(); ++c)
        for (std::size_t s = 0; s < d.total_samples(); ++s) {
            if (d.channel(c).type == PixelType::UInt) d.usamples(c)[s] = 16777216u + std::uint32_t(s) * 7919u + 1u;
            else if (d.channel(c).name == "Z") d.samples(c)[s] = 1.0f + float(s) * 0.123456789f;
            else if (d.channel(c).name == "ZBack") d.samples(c)[s] = 1.5f + float(s) * 0.123456789f;
            else d.samples(c)[s] = half_value(s, c);
        }
    if (tiled) {
        d.storage.tile_width = 16;
        d.storage.tile_height = 8;
    }
    return d;
}

}  // namespace gdof::test
