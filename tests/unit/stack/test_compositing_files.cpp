// Method 2 from files: StackReader through the image cache. Unselected
// references are never opened; missing files and mismatched resolutions are
// clear errors; PNG references are linearised as read_image does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "gdof/compositing.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/image_io.h"
#include "gdof/io/stack_reader.h"
#include "test_support.h"

namespace gdof {
namespace {

Image make_ref(int i, int W, int H) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, {0, 0, W, H});
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            img.at(0, x, y) = float(i) + 0.01f * float(x);
            img.at(1, x, y) = 0.25f * float(i) + 0.001f * float(y);
            img.at(2, x, y) = float((x * 7 + y * 3 + i) % 11) / 11.0f;
            img.at(3, x, y) = 1.0f;
        }
    img.metadata.set_float("focalLength", 50.0);
    return img;
}

// Writes n references (ref_i.exr) and a manifest with explicit limits
// [i + 1, i + 1.5]; reference `odd` gets size odd_w x H when odd >= 0.
FocalStack write_stack(const test::ScratchDir& dir, int n, int W, int H, int odd = -1, int odd_w = 0) {
    std::string refs;
    for (int i = 0; i < n; ++i) {
        const std::string name = "ref_" + std::to_string(i) + ".exr";
        EXPECT_TRUE(io::write_flat(dir.file(name), make_ref(i, i == odd ? odd_w : W, H)));
        refs += std::string(i ? "," : "") + "{\"file\": \"" + name + "\", \"near\": " + std::to_string(i + 1) +
                ", \"far\": " + std::to_string(i + 1.5) + "}";
    }
    const std::string json = "{\"gdof_stack\": 1, \"width\": " + std::to_string(W) + ", \"height\": " +
                             std::to_string(H) + ", \"references\": [" + refs + "]}";
    std::ofstream(dir.file("manifest.json")) << json;
    auto s = parse_stack_manifest(json, dir.path().string());
    EXPECT_TRUE(s) << s.message();
    return s.value();
}

DesiredFocus two_regions(const FocalStack& s, int W, int H, int left, int right) {
    DesiredFocus d;
    d.window = {0, 0, W, H};
    d.near.resize(d.npixels());
    d.far.resize(d.npixels());
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const StackReference& r = s.references[std::size_t(x < W / 2 ? left : right)];
            d.near[d.offset(x, y)] = float(r.near);
            d.far[d.offset(x, y)] = float(r.far);
        }
    return d;
}

StackIndex index_of(const FocalStack& s) {
    std::vector<DepthInterval> l;
    for (const auto& r : s.references) l.push_back({r.near, r.far});
    return StackIndex::build(l).value();
}

TEST(compositing, files_only_selected_references_are_opened) {
    test::ScratchDir dir;
    const int W = 200, H = 90, N = 8;
    const FocalStack s = write_stack(dir, N, W, H);
    const DesiredFocus d = two_regions(s, W, H, 2, 5);
    auto sel = select_references(index_of(s), d);
    ASSERT_TRUE(sel) << sel.message();
    EXPECT_EQ(sel->used_references(), (std::vector<int>{2, 5}));

    auto reader = io::StackReader::create(s);
    ASSERT_TRUE(reader) << reader.message();
    EXPECT_EQ(reader.value()->files_opened(), 0);
    CompositeOptions cs;
    cs.tile_size = 32;  // several tiles, some straddling the boundary
    CompositeStats st;
    auto out = composite_stack(sel.value(), *reader.value(), cs, 0, 0, &st);
    ASSERT_TRUE(out) << out.message();
    EXPECT_EQ(reader.value()->files_opened(), 2);
    EXPECT_EQ(reader.value()->cache_files_opened(), 2) << "OIIO's own count";
    EXPECT_EQ(st.references_used, 2);
    EXPECT_EQ(st.tiles, 7L * 3L);

    auto r2 = io::read_flat(dir.file("ref_2.exr")).value();
    auto r5 = io::read_flat(dir.file("ref_5.exr")).value();
    for (int c = 0; c < 4; ++c)
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                ASSERT_EQ(out->at(c, x, y), (x < W / 2 ? r2 : r5).at(c, x, y)) << c << " " << x << " " << y;

    auto info = reader.value()->info(2);
    ASSERT_TRUE(info) << info.message();
    EXPECT_EQ(info->data_window, (Roi{0, 0, W, H}));
    EXPECT_EQ(info->metadata.get_float("focalLength").value_or(0), 50.0);
    EXPECT_EQ(reader.value()->files_opened(), 2);
}

TEST(compositing, files_missing_reference_is_named) {
    test::ScratchDir dir;
    FocalStack s = write_stack(dir, 3, 40, 20);
    std::filesystem::remove(dir.file("ref_1.exr"));
    Status st = io::check_stack_files(s);
    ASSERT_FALSE(st);
    EXPECT_NE(st.message().find("ref_1.exr"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("references[1]"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("not found"), std::string::npos) << st.message();
    // The reader reports it when the file is needed, not before.
    auto reader = io::StackReader::create(s);
    ASSERT_TRUE(reader);
    std::vector<float> buf(16 * 4);
    EXPECT_TRUE(reader.value()->read_tile(0, {0, 0, 4, 4}, buf.data()));
    Status e = reader.value()->read_tile(1, {0, 0, 4, 4}, buf.data());
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("ref_1.exr"), std::string::npos) << e.message();
}

TEST(compositing, files_mismatched_resolution_names_file_and_sizes) {
    test::ScratchDir dir;
    const FocalStack s = write_stack(dir, 3, 40, 20, /*odd=*/2, /*odd_w=*/48);
    auto reader = io::StackReader::create(s);
    ASSERT_TRUE(reader);
    const DesiredFocus d = two_regions(s, 40, 20, 0, 2);
    auto sel = select_references(index_of(s), d);
    ASSERT_TRUE(sel);
    auto out = composite_stack(sel.value(), *reader.value());
    ASSERT_FALSE(out);
    const std::string& m = out.message();
    EXPECT_NE(m.find("ref_2.exr"), std::string::npos) << m;
    EXPECT_NE(m.find("48x20"), std::string::npos) << m;
    EXPECT_NE(m.find("40x20"), std::string::npos) << m;
}

TEST(compositing, files_png_references_are_linearised_like_read_image) {
    test::ScratchDir dir;
    const int W = 16, H = 8;
    // An sRGB 8-bit PNG with straight alpha.
    Image img = Image::with_channels({"R", "G", "B", "A"}, {0, 0, W, H});
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            img.at(0, x, y) = float(x) / W;
            img.at(1, x, y) = float(y) / H;
            img.at(2, x, y) = 0.5f;
            img.at(3, x, y) = x % 2 ? 1.0f : 0.5f;
        }
    ASSERT_TRUE(io::write_flat(dir.file("p.png"), img));
    FocalStack s;
    s.base_dir = dir.path().string();
    StackReference r;
    r.file = "p.png";
    r.path = dir.file("p.png");
    r.near = 1, r.far = 2;
    s.references.push_back(r);
    auto reader = io::StackReader::create(s);
    ASSERT_TRUE(reader);
    std::vector<float> buf(std::size_t(W * H * 4));
    ASSERT_TRUE(reader.value()->read_tile(0, {0, 0, W, H}, buf.data()));
    const Image want = io::read_flat(dir.file("p.png")).value();
    const RgbaIndices c = find_rgba(want);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t o = (std::size_t(y) * W + std::size_t(x)) * 4;
            EXPECT_NEAR(buf[o + 0], want.at(c.r, x, y), 1e-6) << x << "," << y;
            EXPECT_NEAR(buf[o + 1], want.at(c.g, x, y), 1e-6);
            EXPECT_NEAR(buf[o + 2], want.at(c.b, x, y), 1e-6);
            EXPECT_NEAR(buf[o + 3], want.at(c.a, x, y), 1e-6);
        }
}

}  // namespace
}  // namespace gdof

namespace gdof {
namespace {

// A cache much smaller than the references: tiles are evicted and re-read
// while several threads read; the result must still be exact.
TEST(compositing, files_small_cache_evicts_and_stays_exact) {
    test::ScratchDir dir;
    const int W = 1024, H = 512, N = 8;  // 8 MB of float RGBA per reference, 64 MB in all
    const FocalStack s = write_stack(dir, N, W, H);
    DesiredFocus d;
    d.window = {0, 0, W, H};
    d.near.resize(d.npixels());
    d.far.resize(d.npixels());
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int r = (x / 16 + y / 16) % N;  // every tile needs several references
            d.near[d.offset(x, y)] = float(s.references[std::size_t(r)].near + 0.1);
            d.far[d.offset(x, y)] = float(s.references[std::size_t(r)].far + 0.05);
        }
    CompositeOptions cs;
    cs.soft_k = 3;
    auto sel = select_references(index_of(s), d, cs);
    ASSERT_TRUE(sel);
    io::StackReaderOptions ro;
    ro.cache_memory_mb = 1;  // clamped to the minimum, 16 MB
    ro.cache_tile = 16;
    Image a, b;
    for (int pass = 0; pass < 2; ++pass) {
        auto reader = io::StackReader::create(s, ro);
        ASSERT_TRUE(reader);
        Exec ex;
        ex.nthreads = pass == 0 ? 1 : 0;
        auto out = composite_stack(sel.value(), *reader.value(), cs, 0, 0, nullptr, ex);
        ASSERT_TRUE(out) << out.message();
        (pass == 0 ? a : b) = std::move(out).value();
    }
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < a.npixels(); ++i) ASSERT_EQ(a.plane(c)[i], b.plane(c)[i]) << c << " " << i;
}

}  // namespace
}  // namespace gdof
