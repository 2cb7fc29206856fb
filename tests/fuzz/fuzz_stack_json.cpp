// Stack JSON: the same text as a focus/aperture stack manifest (listed or
// pattern form, through io::load_stack, which also reads a lens table named
// in it), as the direct manifest parser, and as the --render --stack and
// --lightfield --stack option files. Each parser rejects the others' keys,
// so coverage of all four grows from one corpus.
#include "fuzz_support.h"
#include "gdof/focal_stack.h"
#include "gdof/io/lightfield_io.h"
#include "gdof/io/stack_sources.h"
#include "gdof/render_stack.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string json = gdof::fuzz::text(data, size);
    auto listed = gdof::parse_stack_manifest(json, gdof::fuzz::scratch_dir());
    if (listed) (void)gdof::format_stack_manifest(listed.value());
    (void)gdof::io::load_stack(gdof::fuzz::write_file("manifest.json", json));
    (void)gdof::parse_render_stack_options(json);
    (void)gdof::io::parse_extract_stack_options(json);
    return 0;
}
