// --lightfield PATTERN --lf lf.json --stack stack.json -o stack/ref.####.exr:
// extracts a focus/aperture stack from a light field by shift-and-add
// (gdof/lightfield.h). The -o pattern's frame number is the reference index
// (from 1); manifest.json goes beside the images, written last
// (StackOutput, stack_output.cpp). --stack's row is render.cpp's (it also
// names the stack --render makes).
#include <chrono>

#include "cli.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "gdof/io/lightfield_io.h"
#include "gdof/lightfield.h"
#include "ops/ops.h"
#include "stack_output.h"

namespace gdof::cli {

void do_lightfield_output(Frame& f, const std::string& pattern) {
    Session& s = *f.session;
    const std::string source = f.lightfield.source;
    f.lightfield.source.clear();
    check_stack_pattern(pattern, "a light-field stack");

    io::LightFieldConfig config;
    if (!f.lightfield.config.empty()) config = take(io::read_lightfield_config(f.lightfield.config), "--lf");
    ExtractStackOptions spec = take(io::read_extract_stack_options(f.lightfield.stack_spec), "--stack");
    spec.scene_unit_mm = config.scene_unit_mm;

    const StackOutput out(f, pattern, spec.references.size());

    // Load the views.
    io::ReadOptions ro;
    ro.colour = s.colour.get();
    LightField lf;
    {
        StageTimer t(s.stats, "read views");
        s.progress.begin("lightfield");
        s.progress.part(0, 2);  // reading the views, then extracting the stack
        auto r = io::load_lightfield(source, config, ro, s.exec);
        check_interrupted();
        lf = take(std::move(r), "--lightfield");
    }
    const Image& central = lf.central();
    // Plan first: bad references fail before any file is written.
    FocalStack planned = take(plan_stack(lf, spec), "--stack '" + f.lightfield.stack_spec + "'");
    out.create_folder();
    if (s.progress.enabled() || s.global.verbose)
        s.progress.message("gdof: --lightfield '" + source + "': " + std::to_string(lf.rows) + " x " +
                           std::to_string(lf.cols) + " views " + std::to_string(central.width()) + "x" +
                           std::to_string(central.height()) + ", " + std::to_string(planned.references.size()) +
                           " references");

    double t_write = 0, view_pixels = 0;
    const std::size_t n = planned.references.size();
    auto label = [&](std::size_t i) {
        const StackReference& r = planned.references[i];
        return "reference " + std::to_string(i + 1) + "/" + std::to_string(n) + " (disparity " +
               format_double("%g", r.focus_disparity) + ", aperture " + format_double("%g", r.aperture_radius_views) +
               ")";
    };
    auto sink = [&](std::size_t i, Image&& image) -> Status {
        const auto t0 = std::chrono::steady_clock::now();
        Status st = out.write(i, std::move(image));
        t_write += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!st) return st;
        view_pixels += double(lf.aperture_views(planned.references[i].aperture_radius_views)) * double(central.npixels());
        if (s.progress.enabled() || s.global.verbose) s.progress.message("gdof: " + label(i) + " -> " + out.name(i));
        return {};
    };
    Result<ExtractedStack> result = ExtractedStack{};
    const auto t0 = std::chrono::steady_clock::now();
    {
        s.progress.part(1, 2);
        result = extract_stack(lf, spec, sink, s.exec);
    }
    const double t_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    check_interrupted();
    if (!result) runtime_error("--lightfield '" + source + "': " + result.message());
    s.stats.add("refocus", t_total - t_write);
    s.stats.add("write", t_write);

    {
        StageTimer t(s.stats, "write");
        out.write_manifest(std::move(result.value().stack));
    }
    if (s.global.stats) {
        const double refocus_s = t_total - t_write;
        s.progress.message("gdof: --lightfield: " + std::to_string(n) + " references, " + format_double("%.4g", view_pixels) +
                           " view x pixels in " + format_double("%.3f", refocus_s) + " s = " +
                           format_double("%.1f", refocus_s > 0 ? view_pixels / refocus_s / 1e6 : 0.0) +
                           " M view x pixels/s (" + std::to_string(central.nchannels()) + " channels)");
    }
}

std::vector<Command> lightfield_commands() {
    const std::string L = "Stacks from light fields (method 2)";
    std::vector<Command> t;
    // The views' pattern numbers rows and columns, not frames: no file_args.
    t.push_back({.names = {"--lightfield"}, .args = "PATTERN|FOLDER", .kind = Kind::Action, .group = L,
                 .help = "light-field views, e.g. 'views/2067_%02d_%02d.png' (row, column) or a Stanford-archive folder; "
                         "the next -o (with ####) writes one refocused image per --stack reference and manifest.json",
                 .stack = StackUse::PushesImage, .progress_stage = true,
                 .run = [](Frame& f, const Step& s) { f.lightfield.source = s.args[0]; }});
    t.push_back({.names = {"--lf"}, .args = "FILE", .kind = Kind::Modifier, .group = L,
                 .help = "light-field geometry JSON for --lightfield (disparity_at_infinity, ...)", .file_args = {0},
                 .run = [](Frame& f, const Step& s) { f.lightfield.config = s.args[0]; }});
    return t;
}

}  // namespace gdof::cli
