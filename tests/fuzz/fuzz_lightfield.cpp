// Light fields: the text as lf.json and, up to its first newline, as a view
// source (a pattern with two integer fields, or a folder) looked up in the
// scratch folder, which holds a few view-like empty files.
#include "fuzz_support.h"
#include "gdof/io/lightfield_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text = gdof::fuzz::text(data, size);
    auto config = gdof::io::parse_lightfield_config(text);
    if (config) (void)gdof::io::lightfield_geometry(config.value(), 64);
    static const bool views = [] {
        for (const char* name : {"v_00_00.png", "v_00_01.png", "v_01_00.png", "out_00_00_1.0_2.0.png"})
            gdof::fuzz::write_file(name, "");
        return true;
    }();
    (void)views;
    const std::string source = gdof::fuzz::split(text, "\n").first;
    (void)gdof::io::find_lightfield_views(gdof::fuzz::scratch_dir() + "/" + source);
    return 0;
}
