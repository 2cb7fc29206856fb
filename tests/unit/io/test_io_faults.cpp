// The library's write path (io::write_image) under injected faults
// (docs/reliability.md, "Fault injection"): a full disk, a file-size limit,
// an unwritable or vanished folder, a cancelled write, and the temporary
// files of killed writers. The target keeps its old content or stays
// absent, no temporary file of this write remains, and the message names
// the file and the cause.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "fault_support.h"
#include "gdof/io/image_io.h"
#include "io_test_helpers.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;
namespace fs = std::filesystem;

namespace {

// A float RGBA image that does not compress (4 MB at 512 x 512).
ImageSet noise(int w, int h) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, {0, 0, w, h});
    for (int c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < img.npixels(); ++i)
            img.plane(c)[i] = float((i * 7919 + std::size_t(c) * 104729) % 65521) / 65521.f;
    img.storage.compression = "none";
    ImageSet set;
    set.parts.emplace_back(std::move(img));
    return set;
}

void write_all(const std::string& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Runs `body` with RLIMIT_FSIZE set to `bytes` and SIGXFSZ ignored (what a
// caller must do to get EFBIG instead of being killed), then restores both.
template <class F>
void with_file_size_limit(rlim_t bytes, F body) {
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim = old;
    lim.rlim_cur = bytes;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &lim), 0);
    body();
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
}

}  // namespace

TEST(io_faults, FullDiskKeepsTheOldFileAndSaysNoSpace) {
    ScratchDir dir;
    SmallTmpfs disk(dir.file("disk"), 1 << 20);
    if (!disk.mounted()) GTEST_SKIP() << disk.why() << "; FileSizeLimit covers the same write path";
    const std::string out = dir.file("disk/out.exr");
    write_all(out, "old frame");
    Status st = io::write_image(out, noise(512, 512));
    ASSERT_FALSE(st);
    EXPECT_TRUE(has(st.message(), "'" + out + "'")) << st.message();
    EXPECT_TRUE(has(st.message(), "No space left on device")) << st.message();
    EXPECT_EQ(file_bytes(out), "old frame");
    EXPECT_TRUE(temp_files(dir.file("disk")).empty());

    // PNG and TIFF through OpenImageIO, likewise.
    Image big = Image::with_channels({"R", "G", "B"}, {0, 0, 1024, 1024});
    std::uint32_t x = 1;  // an LCG's bytes: 3 MB that neither format can compress
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < big.npixels(); ++i) {
            x = x * 1103515245u + 12345u;
            big.plane(c)[i] = float((x >> 16) & 255u) / 255.f;
        }
    for (const char* name : {"out.png", "out.tif"}) {
        const std::string path = dir.file(std::string("disk/") + name);
        st = io::write_flat(path, big);
        ASSERT_FALSE(st) << name;
        EXPECT_TRUE(has(st.message(), name)) << st.message();
        EXPECT_FALSE(fs::exists(path));
        EXPECT_TRUE(temp_files(dir.file("disk")).empty());
    }
}

TEST(io_faults, FileSizeLimitGivesEfbigNotACorruptFile) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    write_all(out, "old frame");
    Status st;
    with_file_size_limit(1 << 20, [&] { st = io::write_image(out, noise(512, 512)); });
    ASSERT_FALSE(st);
    EXPECT_TRUE(has(st.message(), "'" + out + "'")) << st.message();
    EXPECT_TRUE(has(st.message(), "File too large")) << st.message();
    EXPECT_EQ(file_bytes(out), "old frame");
    EXPECT_TRUE(temp_files(dir.path().string()).empty());
    // Under the limit the same write succeeds.
    with_file_size_limit(8 << 20, [&] { st = io::write_image(out, noise(512, 512)); });
    EXPECT_TRUE(st) << st.message();
    auto back = io::read_image(out);
    ASSERT_TRUE(back) << back.message();
    EXPECT_EQ(back->flat(0).width(), 512);
}

TEST(io_faults, UnwritableFolder) {
    ScratchDir dir;
    fs::create_directories(dir.file("ro"));
    fs::permissions(dir.file("ro"), fs::perms::owner_read | fs::perms::owner_exec | fs::perms::others_read |
                                        fs::perms::others_exec);
    const std::string out = dir.file("ro/out.exr");
    // Root writes through permission bits: act as nobody meanwhile.
    const bool root = ::geteuid() == 0;
    if (root) {
        ASSERT_EQ(::seteuid(kNobody), 0);
    }
    const Status checked = io::check_output_path(out);
    const Status st = io::write_image(out, noise(8, 8));
    if (root) {
        ASSERT_EQ(::seteuid(0), 0);
    }
    for (const Status& s : {checked, st}) {
        ASSERT_FALSE(s);
        EXPECT_TRUE(has(s.message(), "'" + out + "'")) << s.message();
        EXPECT_TRUE(has(s.message(), "Permission denied")) << s.message();
    }
    EXPECT_TRUE(fs::is_empty(dir.file("ro")));
}

TEST(io_faults, VanishedFolder) {
    ScratchDir dir;
    fs::create_directories(dir.file("shot"));
    const std::string out = dir.file("shot/out.exr");
    EXPECT_TRUE(io::check_output_path(out)) << io::check_output_path(out).message();
    fs::remove_all(dir.file("shot"));  // between the check and the write
    const Status st = io::write_image(out, noise(8, 8));
    ASSERT_FALSE(st);
    EXPECT_TRUE(has(st.message(), "'" + out + "'")) << st.message();
    EXPECT_TRUE(has(st.message(), "does not exist")) << st.message();
    EXPECT_FALSE(fs::exists(dir.file("shot")));
}

TEST(io_faults, CancelledWriteDropsTheFinishedTemporaryFile) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    write_all(out, "old frame");
    io::WriteOptions wo;
    int polls = 0;
    wo.cancelled = [&] { return ++polls > 0; };
    const Status st = io::write_image(out, noise(64, 64), wo);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.code(), StatusCode::Cancelled) << st.message();
    EXPECT_EQ(polls, 1);
    EXPECT_EQ(file_bytes(out), "old frame");
    EXPECT_TRUE(temp_files(dir.path().string()).empty());
}

TEST(io_faults, TemporaryFilesOfDeadWritersAreRemovedByTheNextWrite) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    // A process that has ended: its pid names a dead writer.
    const pid_t dead = ::fork();
    if (dead == 0) ::_exit(0);
    ASSERT_GT(dead, 0);
    ::waitpid(dead, nullptr, 0);
    // The temporary names follow io's pattern: .<name>.gdof-tmp-<host>-<pid>-<n>.<ext>
    char host[256] = {};
    ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
    std::string h(host);
    for (char& c : h)
        if (c == '-' || c == '/') c = '_';
    const std::string stale = ".out.exr.gdof-tmp-" + h + "-" + std::to_string(dead) + "-0.exr";
    const std::string live = ".out.exr.gdof-tmp-" + h + "-" + std::to_string(::getpid()) + "-99.exr";
    const std::string other_host = ".out.exr.gdof-tmp-elsewhere-" + std::to_string(dead) + "-0.exr";
    const std::string other_file = ".other.exr.gdof-tmp-" + h + "-" + std::to_string(dead) + "-0.exr";
    for (const std::string& n : {stale, live, other_host, other_file}) write_all(dir.file(n), "partial");
    ASSERT_TRUE(io::write_image(out, noise(8, 8)));
    EXPECT_FALSE(fs::exists(dir.file(stale)));
    EXPECT_TRUE(fs::exists(dir.file(live)));        // a running writer's
    EXPECT_TRUE(fs::exists(dir.file(other_host)));  // another machine's (shared storage)
    EXPECT_TRUE(fs::exists(dir.file(other_file)));  // another target's
}
