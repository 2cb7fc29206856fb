// The lens CSV table (a stack's or the OFX Focal Stack's lens per frame or
// file), with either key column.
#include "fuzz_support.h"
#include "gdof/io/stack_sources.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text = gdof::fuzz::text(data, size);
    (void)gdof::io::read_lens_table(text, "lens.csv", gdof::io::LensTableKey::FrameOrFile);
    (void)gdof::io::read_lens_table(text, "lens.csv", gdof::io::LensTableKey::Frame);
    return 0;
}
