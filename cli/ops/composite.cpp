// --composite MANIFEST: method 2, each output pixel pulled from the focus /
// aperture stack reference whose [near, far] best matches the desired one
// (gdof/compositing.h). The desired near/far come from --surfaces (B-spline
// control grids), --near-map/--far-map (images), or, with neither, from the
// blur field (--blurfield, else the camera's thin lens) along the rays of the
// top image, which supplies Z or P and the camera and is replaced by the
// result. Options may come before or after --composite: it runs when a step
// comes that is not one of them (or at the end).
#include <chrono>
#include <filesystem>

#include "camera_field.h"
#include "cli.h"
#include "gdof/compositing.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/image_io.h"
#include "gdof/io/stack_reader.h"
#include "gdof/io/stack_sources.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

namespace fs = std::filesystem;

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

Image read_map(Frame& f, const std::string& flag, const std::string& path) {
    io::ReadOptions ro;
    ro.linearize = false;  // depths are data
    ro.colour = f.session->colour.get();
    auto r = io::read_flat(path, ro);
    if (!r) {
        std::error_code ec;
        if (!fs::exists(path, ec)) runtime_error(flag + ": file '" + path + "' not found");
        runtime_error(flag + " '" + path + "': " + r.message());
    }
    return std::move(r).value();
}

void run_composite(Frame& f) {
    Session& s = *f.session;
    PendingComposite o = f.composite;
    f.composite.manifest.clear();
    const std::string flag = "--composite";
    const std::string mpath = o.manifest;
    const auto t_start = std::chrono::steady_clock::now();

    // The stack: every listed file must exist before any work.
    auto parsed = io::load_stack(mpath);  // listed references, or a pattern with attributes / a table
    if (!parsed) runtime_error(flag + ": " + parsed.message());
    const FocalStack stack = std::move(parsed).value();
    check(io::check_stack_files(stack), flag + " '" + mpath + "'");

    io::StackReaderOptions ro;
    ro.colour = s.colour.get();
    auto reader_r = io::StackReader::create(stack, ro);
    if (!reader_r) runtime_error(flag + ": " + reader_r.message());
    io::StackReader& reader = *reader_r.value();

    // Desired near/far.
    if (!o.surfaces.empty() && (!o.near_map.empty() || !o.far_map.empty()))
        usage_error("--surfaces and --near-map/--far-map both given; use one source of desired focus");
    if (o.near_map.empty() != o.far_map.empty())
        usage_error(std::string(o.near_map.empty() ? "--far-map" : "--near-map") +
                    " given without " + (o.near_map.empty() ? "--near-map" : "--far-map"));
    const bool from_image = o.surfaces.empty() && o.near_map.empty();
    DesiredFocus desired;
    std::string source_what;
    {
        StageTimer t(s.stats, "composite: desired focus");
        if (!o.surfaces.empty()) {
            auto surf = parse_focus_surfaces(read_flag_file("--surfaces", "file", o.surfaces));
            if (!surf) runtime_error("--surfaces '" + o.surfaces + "': " + surf.message());
            int w = stack.width, h = stack.height;
            if (w <= 0 || h <= 0) {
                // The manifest does not say: the first reference tells (it is opened).
                auto info = reader.info(0);
                if (!info) runtime_error(flag + ": " + info.message());
                w = info->data_window.width();
                h = info->data_window.height();
            }
            desired = take(desired_from_surfaces(surf.value(), w, h, s.exec), "--surfaces '" + o.surfaces + "'");
            source_what = "surfaces '" + o.surfaces + "'";
        } else if (!o.near_map.empty()) {
            const Image near_img = read_map(f, "--near-map", o.near_map);
            const Image far_img = read_map(f, "--far-map", o.far_map);
            const int nc = find_focus_map_channel(near_img, "near"), fc = find_focus_map_channel(far_img, "far");
            if (nc < 0) runtime_error("--near-map '" + o.near_map + "': no float channel");
            if (fc < 0) runtime_error("--far-map '" + o.far_map + "': no float channel");
            auto d = desired_from_maps(near_img, nc, far_img, fc);
            if (!d) runtime_error("--near-map '" + o.near_map + "' / --far-map '" + o.far_map + "': " + d.message());
            desired = std::move(d).value();
            source_what = "maps '" + o.near_map + "', '" + o.far_map + "'";
        } else {
            if (f.stack.empty())
                usage_error("--composite: no desired focus: give --surfaces FILE, --near-map/--far-map, or an input "
                            "image with Z or P (and --blurfield) before --composite");
            StackEntry& top = f.top(flag);
            const std::string where = image_name(top);
            if (top.images.empty() || top.images.is_deep(0))
                runtime_error(flag + ": " + where + " must be a flat image with Z or P to derive near/far from the blur field");
            const Image& img = top.images.flat(0);
            const Camera camera = part_camera(f, img.metadata, img.display_window(), flag, where);
            const BlurField field = field_for(f, camera, flag, where);
            BlurFocusOptions bs;
            bs.coc_px = stack.coc_px;
            bs.source = f.source;
            s.progress.begin("composite: near/far from the blur field");
            auto d = desired_from_blur_field(field, camera, img, bs, s.exec);
            s.progress.end();
            check_interrupted();
            if (!d) runtime_error(flag + ": " + where + ": " + d.message());
            desired = std::move(d).value();
            source_what = "blur field along the rays of " + where;
        }
    }
    const int W = desired.window.width(), H = desired.window.height();
    if (stack.width > 0 && stack.height > 0 && (stack.width != W || stack.height != H))
        runtime_error(flag + ": the desired focus (" + source_what + ") is " + size_str(W, H) + " but the stack '" +
                      mpath + "' is " + size_str(stack.width, stack.height));

    // Which references are needed (no pixel read yet).
    std::vector<DepthInterval> limits;
    for (const StackReference& r : stack.references) limits.push_back({r.near, r.far});
    const StackIndex index = take(StackIndex::build(limits), flag + " '" + mpath + "'");
    const CompositeOptions cs = o.options;
    CompositeStats stats;
    StackSelection sel;
    {
        StageTimer t(s.stats, "composite: select");
        const auto t0 = std::chrono::steady_clock::now();
        sel = take(select_references(index, desired, cs, s.exec), flag);
        stats.select_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const std::vector<int> used = sel.used_references();
    if (used.empty()) runtime_error(flag + ": no pixel selected any reference (desired near/far are all NaN?)");

    // The output's windows and metadata: those of the first used reference.
    auto info = reader.info(used.front());
    if (!info) runtime_error(flag + ": " + info.message());
    if (info->data_window.width() != W || info->data_window.height() != H)
        runtime_error(flag + ": reference '" + stack.references[std::size_t(used.front())].path + "' is " +
                      size_str(info->data_window.width(), info->data_window.height()) + " but the desired focus (" +
                      source_what + ") is " + size_str(W, H));

    Image out;
    {
        StageTimer t(s.stats, "composite: pixels");
        s.progress.begin("composite");
        auto r = composite_stack(sel, reader, cs, info->data_window.x0, info->data_window.y0, &stats, s.exec);
        s.progress.end();
        check_interrupted();
        if (!r) runtime_error(flag + " '" + mpath + "': " + r.message());
        out = std::move(r).value();
    }
    out.set_display_window(info->display_window);
    out.metadata = info->metadata;
    // One lens focus no longer describes the result.
    for (const char* a : {"focusDistance", "focus", "fNumber", "aperture"}) out.metadata.erase(a);
    out.metadata.set_string("gdof:stackManifest", mpath);

    StackEntry e;
    e.images.parts.emplace_back(std::move(out));
    if (from_image && !f.stack.empty()) f.stack.back() = std::move(e);
    else f.stack.push_back(std::move(e));

    if (s.global.stats || s.global.verbose) {
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        std::string list;
        for (std::size_t i = 0; i < used.size() && i < 32; ++i) list += (i ? "," : "") + std::to_string(used[i]);
        if (used.size() > 32) list += ",...";
        char buf[512];
        const double mpx = double(W) * double(H) * 1e-6;
        std::snprintf(buf, sizeof buf,
                      "gdof: --composite '%s'%s: %dx%d from %s\n"
                      "  references used %d of %d [%s], unused %d, files opened %d\n"
                      "  %s, %ld tiles of %d px, %ld reference tiles read\n"
                      "  select %.3f s, pixels %.3f s (%.1f Mpixel/s), total %.3f s (%.1f Mpixel/s)",
                      mpath.c_str(), f.frame ? (" frame " + std::to_string(*f.frame)).c_str() : "", W, H,
                      source_what.c_str(), int(used.size()), int(stack.references.size()), list.c_str(),
                      int(stack.references.size() - used.size()), reader.files_opened(),
                      cs.soft_k > 1 ? ("soft K=" + std::to_string(cs.soft_k)).c_str() : "hard pick", stats.tiles,
                      cs.tile_size, stats.tile_reads, stats.select_seconds, stats.composite_seconds,
                      stats.composite_seconds > 0 ? mpx / stats.composite_seconds : 0.0, total,
                      total > 0 ? mpx / total : 0.0);
        s.progress.message(buf);
    }
}

int soft_k(const Step& s) {
    const int k = parse_int(s.flag, s.args[0]);
    if (k < 1 || k > 16) usage_error(s.flag + ": expected 1 (hard pick) to 16, got '" + s.args[0] + "'");
    return k;
}

// --aovs: the pending --render's (--aovs=LIST), else --composite's.
void set_aovs(Frame& f, const Step& s) {
    if (f.render.pending()) return set_render_aovs(f, s);
    if (!s.args.empty() && s.args[0] != "all")
        usage_error(s.flag + "=" + s.args[0] + ": --composite's AOVs are stack.index and stack.deviation: give --aovs alone");
    f.composite.options.aovs = true;
}

unsigned composite_option_waits(const Frame&, const Step&) { return kCompositeWaits; }

// A --composite option: waits with it (and runs a pending --render first).
Command option(std::vector<std::string> names, std::string args, std::string help,
               std::function<void(Frame&, const Step&)> run, std::vector<int> file_args = {0}) {
    return {.names = std::move(names), .args = std::move(args), .kind = Kind::Modifier,
            .group = "Compositing from focus/aperture stacks (method 2)", .help = std::move(help),
            .file_args = std::move(file_args), .run = std::move(run), .lets_wait = composite_option_waits};
}

}  // namespace

void run_pending_composite(Frame& f) {
    if (!f.composite.manifest.empty()) run_composite(f);
}

std::vector<Command> composite_commands() {
    std::vector<Command> t;
    Command composite = option({"--composite"}, "MANIFEST",
                               "pull each pixel from the stack reference whose near/far best matches the desired one "
                               "(from --surfaces, --near-map/--far-map, or the top image's Z/P with --blurfield)",
                               [](Frame& f, const Step& s) {
                                   run_pending_composite(f);
                                   f.composite.manifest = s.args[0];
                               });
    composite.kind = Kind::Action;
    composite.stack = StackUse::PushesImage;
    t.push_back(std::move(composite));
    t.push_back(option({"--surfaces"}, "FILE", "desired near/far focus surfaces (B-spline control grids, JSON)",
                       [](Frame& f, const Step& s) { f.composite.surfaces = s.args[0]; }));
    t.push_back(option({"--near-map"}, "FILE", "desired near depth per pixel (channel 'near', else Z, Y, first)",
                       [](Frame& f, const Step& s) { f.composite.near_map = s.args[0]; }));
    t.push_back(option({"--far-map"}, "FILE", "desired far depth per pixel (channel 'far', else Z, Y, first)",
                       [](Frame& f, const Step& s) { f.composite.far_map = s.args[0]; }));
    Command soft = option({"--soft"}, "K", "blend the best K references by deviation (default 1: hard pick)",
                          [](Frame& f, const Step& s) { f.composite.options.soft_k = soft_k(s); }, {});
    soft.check = [](const Step& s) { soft_k(s); };
    t.push_back(std::move(soft));
    Command aovs = option({"--aovs"}, "",
                          "--composite also writes stack.index and stack.deviation; after --render, --aovs=LIST picks "
                          "the AOVs (albedo,Z,P,N,id | all | none; default all)",
                          set_aovs, {});
    aovs.optional_value = true;
    aovs.lets_wait = render_option_waits;  // a pending --render's option too
    t.push_back(std::move(aovs));
    return t;
}

}  // namespace gdof::cli
