// Frame ranges and frame patterns (oiiotool conventions).
#include <gtest/gtest.h>

#include <fstream>

#include "gdof/io/sequence.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::io;
using V = std::vector<int>;

namespace {
V frames(const std::string& spec) {
    auto r = parse_frame_range(spec);
    EXPECT_TRUE(r) << spec << ": " << r.message();
    return r ? r.value() : V{};
}
void expect_bad(const std::string& spec) {
    auto r = parse_frame_range(spec);
    ASSERT_FALSE(r) << "'" << spec << "' should be rejected";
    EXPECT_NE(r.message().find("'" + spec + "'"), std::string::npos) << r.message();
}
std::string expand(const std::string& p, int f) {
    auto r = expand_frame_pattern(p, f);
    EXPECT_TRUE(r) << p << ": " << r.message();
    return r ? r.value() : std::string();
}
}  // namespace

TEST(sequence, Ranges) {
    EXPECT_EQ(frames("1-10"), (V{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
    EXPECT_EQ(frames("1-10x2"), (V{1, 3, 5, 7, 9}));
    EXPECT_EQ(frames("1-10x3"), (V{1, 4, 7, 10}));
    EXPECT_EQ(frames("1-10y3"), (V{2, 3, 5, 6, 8, 9}));
    EXPECT_EQ(frames("1,3,7-9"), (V{1, 3, 7, 8, 9}));
    EXPECT_EQ(frames("10-1"), (V{10, 9, 8, 7, 6, 5, 4, 3, 2, 1}));
    EXPECT_EQ(frames("10-1x4"), (V{10, 6, 2}));
    EXPECT_EQ(frames("-5--1"), (V{-5, -4, -3, -2, -1}));
    EXPECT_EQ(frames("-2-2"), (V{-2, -1, 0, 1, 2}));
    EXPECT_EQ(frames("1001"), (V{1001}));
    EXPECT_EQ(frames("-7"), (V{-7}));
    EXPECT_EQ(frames(" 1-3 , 5 "), (V{1, 2, 3, 5}));
    EXPECT_EQ(frames("1001-1100").size(), 100u);
}

TEST(sequence, BadRanges) {
    for (const char* s : {"", "abc", "1-", "1-10x", "1-10x0", "1-10x-2", "1,,3", "1-10z2", "5x2", "1..10", "1-2-3",
                          "99999999999", "1-2000000000"})
        expect_bad(s);
}

TEST(sequence, Patterns) {
    EXPECT_TRUE(has_frame_pattern("shot.####.exr"));
    EXPECT_TRUE(has_frame_pattern("shot.@@@.exr"));
    EXPECT_TRUE(has_frame_pattern("shot.%04d.exr"));
    EXPECT_TRUE(has_frame_pattern("shot.%d.exr"));
    EXPECT_FALSE(has_frame_pattern("shot.0001.exr"));
    EXPECT_FALSE(has_frame_pattern("100%.exr"));
    EXPECT_EQ(expand("shot.####.exr", 7), "shot.0007.exr");
    EXPECT_EQ(expand("shot.######.exr", 1001), "shot.001001.exr");
    EXPECT_EQ(expand("shot.#.exr", 7), "shot.0007.exr");  // a lone # is 4 digits
    EXPECT_EQ(expand("shot.##.exr", 7), "shot.07.exr");
    EXPECT_EQ(expand("shot.@@@.exr", 7), "shot.007.exr");
    EXPECT_EQ(expand("shot.@.exr", 7), "shot.7.exr");
    EXPECT_EQ(expand("shot.%04d.exr", 7), "shot.0007.exr");
    EXPECT_EQ(expand("shot.%d.exr", 7), "shot.7.exr");
    EXPECT_EQ(expand("shot.####.exr", 123456), "shot.123456.exr");  // wider than the padding
    // Negative frames as printf / oiiotool: the sign counts toward the width.
    EXPECT_EQ(expand("shot.####.exr", -5), "shot.-005.exr");
    EXPECT_EQ(expand("shot.%04d.exr", -5), "shot.-005.exr");
    EXPECT_EQ(expand("shot.@@@.exr", -5), "shot.-05.exr");
    EXPECT_EQ(expand("100%%.%03d.exr", 3), "100%.003.exr");
    auto none = expand_frame_pattern("shot.exr", 1);
    ASSERT_FALSE(none);
    EXPECT_NE(none.message().find("shot.exr"), std::string::npos);
}

TEST(sequence, FramesOnDisk) {
    gdof::test::ScratchDir dir;
    for (const char* n : {"shot.0001.exr", "shot.0002.exr", "shot.0010.exr", "shot.-003.exr", "shot.1.exr",
                          "shot.00011.exr", "shot.0005.exr.tmp", "other.0004.exr", "shot.12345.exr"})
        std::ofstream(dir.file(n)) << "x";
    auto r = frames_on_disk(dir.file("shot.####.exr"));
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r.value(), (V{-3, 1, 2, 10, 12345}));
    auto p = frames_on_disk(dir.file("shot.%d.exr"));
    ASSERT_TRUE(p) << p.message();
    EXPECT_EQ(p.value(), (V{1, 12345}));  // unpadded names only
    auto none = frames_on_disk(dir.file("nothing.####.exr"));
    ASSERT_TRUE(none);
    EXPECT_TRUE(none->empty());
    auto missing = frames_on_disk(dir.file("nope/shot.####.exr"));
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("nope"), std::string::npos);
    EXPECT_FALSE(frames_on_disk(dir.file("shot.exr")));
}
