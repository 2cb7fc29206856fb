// Write -> read round trips of generated EXR images: every pixel, sample,
// window, name, channel type and attribute must come back exactly.
#include <gtest/gtest.h>

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>

#include <OpenEXR/ImfThreading.h>
#include <tbb/global_control.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>

#include "gdof/io/image_io.h"
#include "io_test_helpers.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {

Image make_multilayer(Roi data, Roi display) {
    Image img({{"R", PixelType::Half},
               {"G", PixelType::Half},
               {"B", PixelType::Half},
               {"A", PixelType::Half},
               {"Z", PixelType::Float},
               {"P.x", PixelType::Float},
               {"P.y", PixelType::Float},
               {"P.z", PixelType::Float},
               {"diffuse.R", PixelType::Half},
               {"id", PixelType::UInt}},
              data, display);
    for (int c = 0; c < img.nchannels(); ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i) {
            if (img.channel(c).type == PixelType::UInt) img.uplane(c)[i] = 16777216u + std::uint32_t(i) * 3u + 1u;
            else if (img.channel(c).type == PixelType::Half) img.plane(c)[i] = half_value(i, c);
            else img.plane(c)[i] = float(i) * 0.1234567f - 17.0f + float(c);  // not half-representable
        }
    return img;
}

void add_camera(Metadata& md) {
    Mat44 w2c;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) w2c.m[r][c] = double(float(0.25 * r - 0.5 * c + (r == c ? 1.0 : 0.0)));
    w2c.m[3][2] = -10.5;
    md.set_matrix("worldToCamera", w2c);
    Mat44 w2n = w2c;
    w2n.m[2][3] = -1.0;
    w2n.m[3][3] = 0.0;
    md.set_matrix("worldToNDC", w2n);
    md.set_float("focalLength", double(35.0f));
    md.set_float("aperture", double(2.8f));
    md.set_float("focus", double(4.25f));
    md.set_string("comments", "shot 42, camera A");
    md.set_int("gdof:frame", 1001);
    md.set({"cameraNearFar", "vector2", {0.125, 1000.0}, {}});
    md.set({"worldToCameraD", "matrixd", {1.1, 0, 0, 0, 0, 1.2, 0, 0, 0, 0, 1.3, 0, 0.1, 0.2, 0.3, 1}, {}});
    md.set({"exposure", "double", {0.123456789012345}, {}});
    md.set({"lensTags", "string[3]", {}, std::string("prime\0anamorphic\0", 17)});
    md.set({"weights", "float[3]", {0.5, 0.25, 0.125}, {}});
    md.set({"originOffset", "box2i", {-4, -3, 10, 12}, {}});
}

ImageSet roundtrip(const ImageSet& set, const std::string& path, const io::WriteOptions& wo = {}) {
    Status st = io::write_image(path, set, wo);
    EXPECT_TRUE(st) << st.message();
    auto r = io::read_image(path);
    EXPECT_TRUE(r) << r.message();
    return r ? std::move(r.value()) : ImageSet{};
}

}  // namespace

TEST(io_roundtrip, FlatMultilayerKeepsTypesValuesAndCamera) {
    ScratchDir dir;
    ImageSet set;
    Image img = make_multilayer({0, 0, 37, 23}, {0, 0, 37, 23});
    add_camera(img.metadata);
    set.parts.push_back(img);
    ImageSet back = roundtrip(set, dir.file("ml.exr"));
    ASSERT_EQ(back.size(), 1u);
    ASSERT_FALSE(back.is_deep(0));
    expect_same_flat(img, back.flat(0), "multilayer");
    expect_same_metadata(img.metadata, back.metadata(0), "multilayer");
    // Camera attributes keep their EXR types and values.
    const Metadata& md = back.metadata(0);
    ASSERT_TRUE(md.get_matrix("worldToCamera"));
    EXPECT_EQ(md.find("worldToCamera")->type, "matrix");
    EXPECT_EQ(md.find("focalLength")->type, "float");
    EXPECT_DOUBLE_EQ(*md.get_float("aperture"), double(2.8f));
    EXPECT_EQ(*md.get_string("comments"), "shot 42, camera A");
    EXPECT_EQ(md.find("gdof:frame")->type, "int");
    // id values above 2^24 are exact (not squeezed through float).
    const Image& b = back.flat(0);
    EXPECT_EQ(b.uplane(b.channel_index("id"))[5], 16777216u + 16u);
    // Channel names verbatim; R,G,B,A first.
    EXPECT_EQ(b.channel(0).name, "R");
    EXPECT_EQ(b.channel(3).name, "A");
    EXPECT_GE(b.channel_index("P.x"), 0);
    EXPECT_GE(b.channel_index("diffuse.R"), 0);
}

TEST(io_roundtrip, NegativeOriginAndWindowOutsideDisplay) {
    ScratchDir dir;
    ImageSet set;
    // Data window with a negative origin, partly outside the display window.
    set.parts.push_back(make_multilayer({-13, -7, 29, 18}, {0, 0, 20, 10}));
    ImageSet back = roundtrip(set, dir.file("win.exr"));
    ASSERT_EQ(back.size(), 1u);
    expect_same_flat(set.flat(0), back.flat(0), "windows");
    // Entirely outside too.
    ImageSet set2;
    set2.parts.push_back(make_multilayer({100, 200, 110, 205}, {0, 0, 20, 10}));
    ImageSet back2 = roundtrip(set2, dir.file("win2.exr"));
    expect_same_flat(set2.flat(0), back2.flat(0), "outside");
}

TEST(io_roundtrip, EmptyDataWindow) {
    // OpenEXR cannot store an empty data window; it is written as a single
    // zero pixel with a marker attribute and comes back empty.
    ScratchDir dir;
    ImageSet set;
    Image img = make_multilayer({5, 6, 5, 6}, {0, 0, 64, 32});
    ASSERT_TRUE(img.data_window().empty());
    set.parts.push_back(img);
    set.parts.push_back(make_deep({3, 3, 3, 9}, {0, 0, 64, 32}, false));
    set.flat(0).name = "flat";
    set.deep(1).name = "deep";
    ImageSet back = roundtrip(set, dir.file("empty.exr"));
    ASSERT_EQ(back.size(), 2u);
    EXPECT_TRUE(back.flat(0).data_window().empty());
    EXPECT_EQ(back.flat(0).data_window().x0, 5);
    EXPECT_EQ(back.flat(0).display_window(), (Roi{0, 0, 64, 32}));
    EXPECT_EQ(back.flat(0).nchannels(), img.nchannels());
    EXPECT_TRUE(back.deep(1).data_window().empty());
    EXPECT_EQ(back.deep(1).total_samples(), 0u);
    EXPECT_FALSE(back.metadata(0).has("gdof:emptyDataWindow"));
}

TEST(io_roundtrip, MultipartWithNamesWindowsAndDeep) {
    ScratchDir dir;
    ImageSet set;
    Image beauty = make_multilayer({0, 0, 40, 30}, {0, 0, 40, 30});
    beauty.name = "beauty";
    beauty.view = "left";
    add_camera(beauty.metadata);
    Image mask = Image::with_channels({"mask.R", "mask.G"}, {-5, 3, 17, 12});
    mask.set_display_window({0, 0, 40, 30});
    for (int c = 0; c < 2; ++c)
        for (std::size_t i = 0; i < mask.npixels(); ++i) mask.plane(c)[i] = float(i) * 1e-3f * float(c + 1);
    mask.name = "masks";
    mask.storage.tile_width = 8;
    mask.storage.tile_height = 4;
    mask.storage.compression = "piz";
    DeepImage deep = make_deep({2, 1, 33, 27}, {0, 0, 40, 30}, false);
    deep.name = "deep.layers";
    deep.metadata.set_string("renderer", "gdof-test");
    set.parts = {beauty, mask, deep};
    ImageSet back = roundtrip(set, dir.file("multi.exr"));
    ASSERT_EQ(back.size(), 3u);
    expect_same_set(set, back, "multipart");
    EXPECT_EQ(back.part_name(0), "beauty");
    EXPECT_EQ(back.flat(0).view, "left");
    EXPECT_EQ(back.flat(1).storage.tile_width, 8);
    EXPECT_EQ(back.flat(1).storage.compression, "piz");
    EXPECT_EQ(back.flat(0).storage.compression, "zip");  // the default
    EXPECT_TRUE(back.is_deep(2));
    // OIIO sees the same three subimages with their names.
    auto in = OIIO::ImageInput::open(dir.file("multi.exr"));
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("name"), "beauty");
    ASSERT_TRUE(in->seek_subimage(2, 0));
    EXPECT_TRUE(in->spec().deep);
    EXPECT_EQ(in->spec().get_string_attribute("name"), "deep.layers");
    in->close();
}

TEST(io_roundtrip, SingleNamedPartKeepsName) {
    ScratchDir dir;
    ImageSet set;
    set.parts.push_back(make_multilayer({0, 0, 8, 8}, {0, 0, 8, 8}));
    set.flat(0).name = "rgba";
    ImageSet back = roundtrip(set, dir.file("named.exr"));
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back.flat(0).name, "rgba");
}

TEST(io_roundtrip, DeepScanlineAndTiled) {
    ScratchDir dir;
    for (bool tiled : {false, true}) {
        ImageSet set;
        set.parts.push_back(make_deep({-3, -2, 45, 31}, {0, 0, 40, 30}, tiled));
        set.deep(0).metadata.set_float("focalLength", double(50.0f));
        const std::string file = dir.file(tiled ? "deep_tiled.exr" : "deep_scan.exr");
        ImageSet back = roundtrip(set, file);
        ASSERT_EQ(back.size(), 1u);
        ASSERT_TRUE(back.is_deep(0));
        expect_same_deep(set.deep(0), back.deep(0), file);
        expect_same_metadata(set.deep(0).metadata, back.metadata(0), file);
        EXPECT_EQ(back.deep(0).storage.tile_width, tiled ? 16 : 0);
        EXPECT_EQ(back.deep(0).channel(back.deep(0).channel_index("Z")).type, PixelType::Float);
        std::uint32_t mx = 0;
        for (auto n : back.deep(0).sample_counts()) mx = std::max(mx, n);
        EXPECT_EQ(mx, 5u);
        // OIIO reads our deep file too, with the same sample total.
        auto in = OIIO::ImageInput::open(file);
        ASSERT_TRUE(in);
        OIIO::DeepData dd;
        ASSERT_TRUE(in->read_native_deep_image(0, 0, dd));
        std::size_t total = 0;
        for (int p = 0; p < int(dd.pixels()); ++p) total += dd.samples(p);
        EXPECT_EQ(total, set.deep(0).total_samples());
        in->close();
    }
}

TEST(io_roundtrip, PixelTypeOverrideAndCompression) {
    ScratchDir dir;
    ImageSet set;
    set.parts.push_back(make_multilayer({0, 0, 16, 16}, {0, 0, 16, 16}));
    io::WriteOptions wo;
    wo.pixel_type = "half";
    wo.compression = "dwaa:45";
    ImageSet back = roundtrip(set, dir.file("half.exr"), wo);
    ASSERT_EQ(back.size(), 1u);
    const Image& b = back.flat(0);
    EXPECT_EQ(b.channel(b.channel_index("Z")).type, PixelType::Half);
    EXPECT_EQ(b.channel(b.channel_index("id")).type, PixelType::UInt);  // uint stays uint
    EXPECT_EQ(b.storage.compression, "dwaa");
    EXPECT_EQ(b.uplane(b.channel_index("id"))[3], 16777216u + 10u);

    wo = {};
    wo.pixel_type = "float";
    wo.compression = "none";
    back = roundtrip(set, dir.file("float.exr"), wo);
    EXPECT_EQ(back.flat(0).channel(back.flat(0).channel_index("R")).type, PixelType::Float);
    EXPECT_EQ(back.flat(0).storage.compression, "none");

    wo = {};
    wo.compression = "bogus";
    Status st = io::write_image(dir.file("bogus.exr"), set, wo);
    EXPECT_FALSE(st);
    EXPECT_NE(st.message().find("bogus"), std::string::npos) << st.message();
}

TEST(io_roundtrip, ReadExrWithColorspaceOption) {
    // An EXR is linear unless the caller names its space.
    ScratchDir dir;
    Image img = Image::with_channels({"R", "G", "B"}, {0, 0, 2, 1});
    for (int c = 0; c < 3; ++c) img.plane(c)[0] = img.plane(c)[1] = 0.5f;
    ASSERT_TRUE(io::write_flat(dir.file("c.exr"), img));
    auto lin = io::read_flat(dir.file("c.exr"));
    ASSERT_TRUE(lin) << lin.message();
    EXPECT_EQ(lin->plane(0)[0], 0.5f);
    io::ReadOptions ro;
    ro.colorspace = "sRGB";
    auto conv = io::read_flat(dir.file("c.exr"), ro);
    ASSERT_TRUE(conv) << conv.message();
    EXPECT_NEAR(conv->plane(0)[0], 0.2140411f, 1e-5);
    EXPECT_EQ(*conv->metadata.get_string("oiio:ColorSpace"), "linear");
}

TEST(io_roundtrip, DescribeMentionsPartsChannelsAndCamera) {
    ImageSet set;
    Image beauty = make_multilayer({0, 0, 10, 10}, {0, 0, 10, 10});
    beauty.name = "beauty";
    add_camera(beauty.metadata);
    DeepImage deep = make_deep({0, 0, 6, 5}, {0, 0, 10, 10}, true);
    deep.name = "deep";
    set.parts = {beauty, deep};
    std::uint32_t mx = 0;
    for (auto n : deep.sample_counts()) mx = std::max(mx, n);
    const std::string max_text = "max " + std::to_string(mx);
    std::string d = io::describe(set, "shot.exr", false);
    EXPECT_NE(d.find(max_text), std::string::npos) << d;
    for (const char* s : {"shot.exr", "2 parts", "beauty", "deep", "flat", "P: x (float) y (float) z (float)",
                          "id (uint)", "worldToCamera", "focalLength", "aperture", "[0,10)x[0,10)", "tiled 16x8",
                          "Z range", "ZBack range"})
        EXPECT_NE(d.find(s), std::string::npos) << "missing '" << s << "' in:\n" << d;
    EXPECT_EQ(d.find("lensTags"), std::string::npos);
    std::string v = io::describe(set, "shot.exr", true);
    EXPECT_NE(v.find("lensTags (string[3]): [\"prime\", \"anamorphic\", \"\"]"), std::string::npos) << v;
    EXPECT_NE(v.find("comments (string): \"shot 42, camera A\""), std::string::npos) << v;
}

// OpenEXR compresses and decompresses on a worker pool that is empty unless
// the application sizes it; the reader and writer size it to the process's
// thread budget (the CLI's --threads is a TBB global_control) while a file is
// in flight. The bytes written do not depend on the budget, and no worker is
// left when no file is: a process that forks after reading (Python's
// multiprocessing) must be able to read in the child, where an idle sized
// pool would deadlock the first read (fork copies no threads).
TEST(io_roundtrip, ExrWorkersFollowTheThreadBudgetAndLeaveNoThreads) {
    ScratchDir dir;
    ImageSet set;
    Image img = make_multilayer({0, 0, 301, 157}, {0, 0, 301, 157});  // ten 16-row zip blocks
    set.parts.push_back(img);
    io::WriteOptions wo;
    wo.compression = "zip";
    std::string written[2];
    for (int budget : {1, 2}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(budget));
        const std::string path = dir.file("budget" + std::to_string(budget) + ".exr");
        ImageSet back = roundtrip(set, path, wo);
        EXPECT_EQ(Imf::globalThreadCount(), 0) << "budget " << budget << ": workers left after the last file";
        ASSERT_EQ(back.size(), 1u);
        expect_same_flat(img, back.flat(0), "budget " + std::to_string(budget));
        written[budget - 1] = file_bytes(path);
    }
    EXPECT_FALSE(written[0].empty());
    EXPECT_EQ(written[0], written[1]) << "the file's bytes depend on the number of threads";

    // Read in a forked child after the parent has read (the alarm turns a
    // deadlock into a failure).
    const std::string path = dir.file("budget2.exr");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        alarm(60);
        auto r = io::read_image(path);
        _exit(r && r->size() == 1 && r->flat(0).npixels() == img.npixels() ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "the forked child's read " << (WIFSIGNALED(status) ? "hung or crashed" : "failed");
}
