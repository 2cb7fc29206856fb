// read_lens_table: the one reader of lens tables (a manifest's "table" CSV
// and the OFX plugin's lens_table parameter): header and rows, comments,
// trimmed cells, far "inf", and errors naming the source, line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "gdof/io/stack_sources.h"

using namespace gdof;
using io::LensTableKey;

namespace {

using Values = std::vector<std::pair<std::string, double>>;

TEST(lens_table, RowsKeepTheirLineFrameAndNumberColumnsInOrder) {
    const std::string text = "# focus sweep\n\nframe, focus_distance ,f_number,far\n 1 , 0.5, 2.8, inf\r\n   # aside\n2,1e1,4,30\n";
    auto t = io::read_lens_table(text, "T");
    ASSERT_TRUE(t) << t.message();
    ASSERT_EQ(t->size(), 2u);
    const io::LensTableRow& a = (*t)[0];
    EXPECT_EQ(a.line, 4);
    ASSERT_TRUE(a.frame);
    EXPECT_EQ(*a.frame, 1.0);
    EXPECT_FALSE(a.file);
    ASSERT_EQ(a.values.size(), 3u);
    EXPECT_EQ(a.values[0], (std::pair<std::string, double>{"focus_distance", 0.5}));
    EXPECT_EQ(a.values[1], (std::pair<std::string, double>{"f_number", 2.8}));
    EXPECT_EQ(a.values[2].first, "far");
    EXPECT_TRUE(std::isinf(a.values[2].second) && a.values[2].second > 0);
    const io::LensTableRow& b = (*t)[1];
    EXPECT_EQ(b.line, 6);
    EXPECT_EQ(*b.frame, 2.0);
    EXPECT_EQ(b.values, (Values{{"focus_distance", 10}, {"f_number", 4}, {"far", 30}}));
}

TEST(lens_table, AFileColumnOnlyWhereTheKeyAllowsIt) {
    auto t = io::read_lens_table("file,f_number\n a.exr ,2\n", "T");
    ASSERT_TRUE(t) << t.message();
    ASSERT_EQ(t->size(), 1u);
    EXPECT_EQ((*t)[0].file, std::optional<std::string>("a.exr"));
    EXPECT_FALSE((*t)[0].frame);

    auto f = io::read_lens_table("file,f_number\na.exr,2\n", "parameter 'lens_table'", LensTableKey::Frame);
    ASSERT_FALSE(f);
    EXPECT_EQ(f.message(), "parameter 'lens_table': unknown column 'file' (known: frame, focus_distance, f_number, "
                           "focal_length_mm, sensor_width_mm, near, far)");
    auto k = io::read_lens_table("f_number\n2\n", "P", LensTableKey::Frame);
    ASSERT_FALSE(k);
    EXPECT_EQ(k.message(), "P: needs a 'frame' column");
    auto kf = io::read_lens_table("f_number\n2\n", "T");
    ASSERT_FALSE(kf);
    EXPECT_EQ(kf.message(), "T: needs a 'frame' or 'file' column");
}

TEST(lens_table, BadCellsNameTheSourceLineAndColumn) {
    auto nan = io::read_lens_table("frame,f_number\n1,2\n2,nan\n", "table 'lens.csv'");
    ASSERT_FALSE(nan);
    EXPECT_EQ(nan.message(), "table 'lens.csv' line 3 column 'f_number': not a number: 'nan'");
    // "inf" only in the far column; no overflow, no trailing text.
    for (const char* bad : {"frame,near\n1,inf\n", "frame,far\n1,infinity\n", "frame,far\n1,1e999\n", "frame,far\n1,3m\n",
                            "frame,far\nx,3\n"}) {
        auto r = io::read_lens_table(bad, "T");
        ASSERT_FALSE(r) << bad;
        EXPECT_NE(r.message().find("T line 2 column '"), std::string::npos) << r.message();
        EXPECT_NE(r.message().find("not a number"), std::string::npos) << r.message();
    }
    auto cells = io::read_lens_table("frame,f_number\n1\n", "T");
    ASSERT_FALSE(cells);
    EXPECT_EQ(cells.message(), "T line 2: 1 cells, the header has 2");
    auto unknown = io::read_lens_table("frame,focus\n1,2\n", "T");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.message().find("unknown column 'focus'"), std::string::npos) << unknown.message();
}

TEST(lens_table, ATableWithoutRowsIsNoErrorHere) {
    for (const char* text : {"", "\n  \n# nothing\n", "frame,focus_distance,f_number\n"}) {
        auto t = io::read_lens_table(text, "T");
        ASSERT_TRUE(t) << text << ": " << t.message();
        EXPECT_TRUE(t->empty()) << text;
    }
}

}  // namespace

TEST(lens_table, LensAtFrameInterpolatesFocusAsARingTurns) {
    // Keys at frames 10 and 20 (given out of order); frame 15 lies halfway:
    // focus 1 / ((1/2 + 1/8) / 2) = 3.2 (the ring's halfway, not 5 m), the
    // f-number and focal length linearly; a keyed frame is its row exactly;
    // before and after the keys the ends hold.
    auto rows = io::read_lens_table("frame,focus_distance,f_number,focal_length_mm\n20,8,4,50\n10,2,2,35\n", "t",
                                    LensTableKey::Frame);
    ASSERT_TRUE(rows) << rows.message();
    auto mid = io::lens_at_frame(*rows, 15, "t");
    ASSERT_TRUE(mid) << mid.message();
    EXPECT_DOUBLE_EQ(*mid->focus_distance, 3.2);
    EXPECT_DOUBLE_EQ(*mid->f_number, 3.0);
    EXPECT_DOUBLE_EQ(*mid->focal_length_mm, 42.5);
    EXPECT_FALSE(mid->sensor_width_mm);
    auto quarter = io::lens_at_frame(*rows, 12.5, "t");
    ASSERT_TRUE(quarter);
    EXPECT_DOUBLE_EQ(1.0 / *quarter->focus_distance, 0.75 * 0.5 + 0.25 * 0.125);
    for (auto [frame, focus] : {std::pair{10.0, 2.0}, {20.0, 8.0}, {3.0, 2.0}, {99.0, 8.0}}) {
        auto l = io::lens_at_frame(*rows, frame, "t");
        ASSERT_TRUE(l);
        EXPECT_EQ(*l->focus_distance, focus) << frame;
    }
    // Errors name the table and the lines.
    auto twice = io::read_lens_table("frame,f_number\n1,2\n1,4\n", "t", LensTableKey::Frame);
    ASSERT_TRUE(twice);
    auto e = io::lens_at_frame(*twice, 1, "t");
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("lines 2 and 3"), std::string::npos) << e.message();
    auto stack = io::read_lens_table("frame,near,far\n1,2,inf\n", "t", LensTableKey::Frame);
    ASSERT_TRUE(stack);
    EXPECT_FALSE(io::lens_at_frame(*stack, 1, "t"));
    auto zero = io::read_lens_table("frame,f_number\n1,0\n", "t", LensTableKey::Frame);
    ASSERT_TRUE(zero);
    auto z = io::lens_at_frame(*zero, 1, "t");
    ASSERT_FALSE(z);
    EXPECT_NE(z.message().find("line 2 column 'f_number'"), std::string::npos) << z.message();
    EXPECT_FALSE(io::lens_at_frame({}, 1, "t"));
}
