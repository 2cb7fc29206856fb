// Input and output: input files (and -i), -o, -d, --compression, --info.
// -o writes the top image, or the stack a --lightfield or --render --stack
// before it makes.
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "gdof/io/image_io.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

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

// The image library's messages name the file (image_io.h).
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
            runtime_error(r.message());
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
    io::WriteOptions wo = f.output;

    const ImageSet* images = &top.images;
    ImageSet converted;
    if (!top.colorspace.empty()) {
        // The colour channels are no longer scene-linear (--colorconvert): the
        // writer converts from the working space, so convert here instead and
        // tell the writer to leave the values alone.
        std::string target = f.output.colorspace;
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
        runtime_error(st.message());
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

// -o: a rendered stack, a light-field stack, or the top image.
void run_output(Frame& f, const Step& s) {
    if (s.stack_output && !f.render.stack_spec.empty()) do_render_stack_output(f, s.args[0]);
    else if (s.stack_output) do_lightfield_output(f, s.args[0]);
    else do_output(f, s.args[0]);
}

}  // namespace

std::vector<Command> io_commands() {
    const std::string O = "Input and output";
    std::vector<Command> t;
    t.push_back({.names = {"-i"}, .args = "FILE", .kind = Kind::Action, .group = O,
                 .help = "read FILE (same as giving FILE alone)", .file_args = {0},
                 .run = [](Frame& f, const Step& s) { do_input(f, s.args[0]); }});
    t.push_back({.names = {"-o"}, .args = "FILE", .kind = Kind::Action, .group = O,
                 .help = "write the top image to FILE (atomically)", .file_args = {0}, .stack = StackUse::NeedsImage,
                 .run = run_output,
                 // A rendered stack is the pending --render's own output.
                 .lets_wait = [](const Frame& f, const Step& s) -> unsigned {
                     return s.stack_output && !f.render.stack_spec.empty() ? kRenderWaits | kCompositeWaits
                                                                           : kNothingWaits;
                 }});
    t.push_back({.names = {"-d"}, .args = "TYPE", .kind = Kind::Modifier, .group = O,
                 .help = "pixel type of the following outputs: half or float",
                 .run = [](Frame& f, const Step& s) { f.output.pixel_type = s.args[0]; },
                 .check = [](const Step& s) {
                     if (s.args[0] != "half" && s.args[0] != "float")
                         usage_error("-d: unknown pixel type '" + s.args[0] + "' (expected half or float)");
                 }});
    t.push_back({.names = {"--compression"}, .args = "NAME", .kind = Kind::Modifier, .group = O,
                 .help = "compression of the following outputs (zip, piz, dwaa:45, none ...)",
                 .allows_empty_value = true,
                 .run = [](Frame& f, const Step& s) { f.output.compression = s.args[0]; }});
    t.push_back({.names = {"--info"}, .kind = Kind::Action, .group = O,
                 .help = "describe the top image, or (before any input) each input file", .is_work = true,
                 .prints_result = true,
                 .run = [](Frame& f, const Step&) { do_info(f); }});
    return t;
}

}  // namespace gdof::cli
