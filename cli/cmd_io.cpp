// Inputs, -o and --info.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli.h"
#include "gdof/io/image_io.h"

namespace gdof::cli {

namespace {

// Library messages usually name the file already; add it when they do not.
std::string with_file(const std::string& verb, const std::string& path, const std::string& message) {
    if (message.find(path) != std::string::npos) return message;
    return verb + " '" + path + "': " + message;
}

std::string lower_ext(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

bool is_display_format(const std::string& path) {
    const std::string e = lower_ext(path);
    return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".jpe" || e == ".gif" || e == ".bmp" ||
           e == ".webp" || e == ".ppm" || e == ".pgm" || e == ".pnm";
}

}  // namespace

std::string read_text(const std::string& flag, const std::string& what, const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) runtime_error(flag + ": " + what + " '" + path + "' not found");
    std::ifstream in(path, std::ios::binary);
    if (!in) runtime_error(flag + ": cannot open " + what + " '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string working_space(const io::ColourConfig& config) {
    for (const char* n : {"scene_linear", "linear", "default"}) {
        std::string r = config.resolve(n);
        if (!r.empty() && config.is_linear(r)) return r;
    }
    for (const std::string& n : config.colour_spaces())
        if (config.is_linear(n)) return n;
    return {};
}

void do_input(Frame& f, const std::string& path) {
    Session& s = *f.session;
    io::ReadOptions ro;
    ro.colorspace = f.next_input_colorspace;
    ro.colour = s.colour.get();
    f.next_input_colorspace.clear();
    StackEntry e;
    {
        StageTimer t(s.stats, "read");
        auto r = io::read_image(path, ro);
        if (!r) {
            std::error_code ec;
            if (!std::filesystem::exists(path, ec)) runtime_error("input file '" + path + "' not found");
            check_interrupted();
            runtime_error(with_file("reading", path, r.message()));
        }
        e.images = std::move(r).value();
    }
    e.source = path;
    if (e.images.empty()) runtime_error("reading '" + path + "': the file holds no image");
    if (f.info_on_read) {
        std::cout << io::describe(e.images, path, s.global.verbose);
        std::cout.flush();
    }
    f.stack.push_back(std::move(e));
}

void do_output(Frame& f, const std::string& path) {
    Session& s = *f.session;
    StackEntry& top = f.top("-o");
    io::WriteOptions wo;
    wo.pixel_type = f.output_pixel_type;
    wo.compression = f.output_compression;
    wo.colorspace = f.output_colorspace;
    wo.colour = s.colour.get();

    const ImageSet* images = &top.images;
    ImageSet converted;
    if (!top.colorspace.empty()) {
        // The colour channels are no longer scene-linear (--colorconvert): the
        // writer converts from the working space, so convert here instead and
        // tell the writer to leave the values alone.
        std::string target = f.output_colorspace;
        if (target.empty()) target = is_display_format(path) ? std::string("sRGB") : top.colorspace;
        const std::string lin = working_space(*s.colour);
        if (lin.empty()) runtime_error("-o '" + path + "': the colour config has no scene-linear space");
        if (s.colour->resolve(target) != top.colorspace) {
            StageTimer t(s.stats, "colour");
            converted = top.images;
            for (std::size_t i = 0; i < converted.size(); ++i) {
                Status st = converted.is_deep(i) ? s.colour->convert(converted.deep(i), top.colorspace, target)
                                                 : s.colour->convert(converted.flat(i), top.colorspace, target);
                check(st, "-o '" + path + "'");
            }
            images = &converted;
        }
        wo.colorspace = lin;
    }
    check_interrupted();
    StageTimer t(s.stats, "write");
    Status st = io::write_image(path, *images, wo);
    if (!st) {
        check_interrupted();
        runtime_error(with_file("writing", path, st.message()));
    }
    if (s.global.verbose) s.progress.message("gdof: wrote " + path);
}

void do_info(Frame& f) {
    if (f.stack.empty()) {
        f.info_on_read = true;  // gdof --info a.exr b.exr
        return;
    }
    const StackEntry& top = f.stack.back();
    std::cout << io::describe(top.images, top.source.empty() ? std::string("(result)") : top.source,
                              f.session->global.verbose);
    std::cout.flush();
}

}  // namespace gdof::cli
