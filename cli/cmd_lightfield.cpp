// --lightfield PATTERN --lf lf.json --stack stack.json -o stack/ref.####.exr:
// extracts a focus/aperture stack from a light field by shift-and-add
// (gdof/lightfield.h). The -o pattern's frame number is the reference index
// (from 1); manifest.json goes beside the images, written last (temporary
// file + rename), so a failed run never leaves a manifest pointing at
// missing or half-written images.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "gdof/io/lightfield_io.h"
#include "gdof/io/sequence.h"
#include "gdof/lightfield.h"

namespace gdof::cli {

namespace {

namespace fs = std::filesystem;

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

void write_text_atomically(const std::string& path, const std::string& text) {
    const fs::path target(path);
    const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".gdof-tmp-" + std::to_string(::getpid()));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            runtime_error("writing '" + path + "': cannot write '" + tmp.string() + "'");
        }
    }
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) {
        std::error_code ec2;
        fs::remove(tmp, ec2);
        runtime_error("writing '" + path + "': " + ec.message());
    }
}

}  // namespace

void do_lightfield_output(Frame& f, const std::string& pattern) {
    Session& s = *f.session;
    const std::string source = f.lightfield;
    f.lightfield.clear();
    if (!io::has_frame_pattern(pattern))
        usage_error("-o '" + pattern + "': a light-field stack is one file per reference: give a frame pattern, "
                    "e.g. stack/ref.####.exr");

    io::LightFieldConfig config;
    if (!f.lightfield_config.empty()) config = take(io::read_lightfield_config(f.lightfield_config), "--lf");
    StackSpec spec = take(io::read_stack_spec(f.stack_spec), "--stack");
    spec.scene_unit_mm = config.scene_unit_mm;

    // Output names (reference i -> frame i + 1), all in one folder with the manifest.
    std::vector<std::string> names;
    for (std::size_t i = 0; i < spec.references.size(); ++i)
        names.push_back(take(io::expand_frame_pattern(pattern, int(i) + 1), "-o '" + pattern + "'"));
    const fs::path dir = fs::path(names.front()).parent_path();
    for (const std::string& n : names)
        if (fs::path(n).parent_path() != dir)
            usage_error("-o '" + pattern + "': the stack's files must share one folder (the frame pattern is in a folder name)");
    const std::string manifest_path = (dir / "manifest.json").string();

    // Load the views.
    io::ReadOptions ro;
    ro.colour = s.colour.get();
    LightField lf;
    {
        StageTimer t(s.stats, "read views");
        s.progress.begin("lightfield: reading views");
        auto r = io::load_lightfield(source, config, ro, s.exec);
        s.progress.end();
        check_interrupted();
        lf = take(std::move(r), "--lightfield");
    }
    const Image& central = lf.central();
    // Plan first: bad references fail before any file is written.
    FocalStack planned = take(plan_stack(lf, spec), "--stack '" + f.stack_spec + "'");
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec)) {
        fs::create_directories(dir, ec);
        if (ec) runtime_error("-o '" + pattern + "': cannot create folder '" + dir.string() + "': " + ec.message());
    }
    if (s.progress.enabled() || s.global.verbose)
        s.progress.message("gdof: --lightfield '" + source + "': " + std::to_string(lf.rows) + " x " +
                           std::to_string(lf.cols) + " views " + std::to_string(central.width()) + "x" +
                           std::to_string(central.height()) + ", " + std::to_string(planned.references.size()) +
                           " references");

    io::WriteOptions wo;
    wo.pixel_type = f.output_pixel_type;
    wo.compression = f.output_compression;
    wo.colorspace = f.output_colorspace;
    wo.colour = s.colour.get();

    double t_write = 0, view_pixels = 0;
    const std::size_t n = planned.references.size();
    auto label = [&](std::size_t i) {
        const StackReference& r = planned.references[i];
        return "reference " + std::to_string(i + 1) + "/" + std::to_string(n) + " (disparity " +
               fmt("%g", r.focus_disparity) + ", aperture " + fmt("%g", r.aperture_radius_views) + ")";
    };
    auto sink = [&](std::size_t i, Image&& image) -> Status {
        s.progress.end();
        const auto t0 = std::chrono::steady_clock::now();
        ImageSet set;
        set.parts.emplace_back(std::move(image));
        Status st = io::write_image(names[i], set, wo);
        t_write += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!st) return st.message().find(names[i]) != std::string::npos ? st : st.prefix("writing '" + names[i] + "'");
        view_pixels += double(lf.aperture_views(planned.references[i].aperture_radius_views)) * double(central.npixels());
        if (s.progress.enabled() || s.global.verbose) s.progress.message("gdof: " + label(i) + " -> " + names[i]);
        if (i + 1 < n) s.progress.begin("lightfield " + label(i + 1));
        return {};
    };
    Result<ExtractedStack> result = ExtractedStack{};
    const auto t0 = std::chrono::steady_clock::now();
    {
        s.progress.begin("lightfield " + label(0));
        result = extract_stack(lf, spec, s.exec, sink);
        s.progress.end();
    }
    const double t_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    check_interrupted();
    if (!result) runtime_error("--lightfield '" + source + "': " + result.message());
    s.stats.add("refocus", t_total - t_write);
    s.stats.add("write", t_write);

    FocalStack stack = std::move(result.value().stack);
    for (std::size_t i = 0; i < n; ++i) stack.references[i].file = fs::path(names[i]).filename().string();
    {
        StageTimer t(s.stats, "write");
        write_text_atomically(manifest_path, format_stack_manifest(stack));
    }
    if (s.global.verbose) s.progress.message("gdof: wrote " + manifest_path);
    if (s.global.stats) {
        const double refocus_s = t_total - t_write;
        s.progress.message("gdof: --lightfield: " + std::to_string(n) + " references, " + fmt("%.4g", view_pixels) +
                           " view x pixels in " + fmt("%.3f", refocus_s) + " s = " +
                           fmt("%.1f", refocus_s > 0 ? view_pixels / refocus_s / 1e6 : 0.0) +
                           " M view x pixels/s (" + std::to_string(central.nchannels()) + " channels)");
    }
}

}  // namespace gdof::cli
