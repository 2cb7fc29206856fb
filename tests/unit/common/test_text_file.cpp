// read_text(path, what): the file named as "<what> 'path'" in its errors, the
// code kept (the parsers' wording: "scene 'a.json' not found").
#include <gtest/gtest.h>

#include <fstream>

#include "gdof/text_file.h"
#include "test_support.h"

namespace gdof {
namespace {

TEST(text_file, ReadTextNamesWhatTheFileIs) {
    test::ScratchDir dir;
    const std::string f = dir.file("lens.csv");
    std::ofstream(f) << "frame,f_number\n1,2\n";
    auto t = read_text(f, "table");
    ASSERT_TRUE(t) << t.message();
    EXPECT_EQ(t.value(), "frame,f_number\n1,2\n");

    auto missing = read_text(dir.file("nope.json"), "scene");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.message(), "scene '" + dir.file("nope.json") + "' not found");
    EXPECT_EQ(missing.status().code(), StatusCode::NotFound);

    auto folder = read_text(dir.path().string(), "OBJ");
    ASSERT_FALSE(folder);
    EXPECT_EQ(folder.message(), "OBJ '" + dir.path().string() + "' is a folder");
    EXPECT_EQ(folder.status().code(), StatusCode::Io);
}

}  // namespace
}  // namespace gdof
