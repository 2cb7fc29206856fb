// Frame ranges ("1-10x2,15") and file patterns ("shot.####.exr", "@",
// "%04d"): the first line is a range, the second a pattern, expanded for the
// range's first frames and matched against the scratch folder.
#include "fuzz_support.h"
#include "gdof/io/sequence.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto [range, pattern] = gdof::fuzz::split(gdof::fuzz::text(data, size), "\n");
    auto frames = gdof::io::parse_frame_range(range);
    if (!gdof::io::has_frame_pattern(pattern)) return 0;
    std::vector<int> some = {0, -1, 1234567, 2147483647};
    if (frames)
        for (std::size_t i = 0; i < frames.value().size() && i < 4; ++i) some.push_back(frames.value()[i]);
    for (int f : some) (void)gdof::io::expand_frame_pattern(pattern, f);
    (void)gdof::io::frames_on_disk(gdof::fuzz::scratch_dir() + "/" + pattern);
    return 0;
}
