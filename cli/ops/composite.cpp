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

    // The source of the desired near/far (composite() evaluates it).
    if (!o.surfaces.empty() && (!o.near_map.empty() || !o.far_map.empty()))
        usage_error("--surfaces and --near-map/--far-map both given; use one source of desired focus");
    if (o.near_map.empty() != o.far_map.empty())
        usage_error(std::string(o.near_map.empty() ? "--far-map" : "--near-map") +
                    " given without " + (o.near_map.empty() ? "--near-map" : "--far-map"));
    const bool from_image = o.surfaces.empty() && o.near_map.empty();
    FocusSource focus;
    std::string source_what, focus_context;  // for --stats; for errors about the desired focus
    Image near_img, far_img;
    Camera camera;
    BlurField field;
    if (!o.surfaces.empty()) {
        auto surf = parse_focus_surfaces(read_flag_file("--surfaces", "file", o.surfaces));
        if (!surf) runtime_error("--surfaces '" + o.surfaces + "': " + surf.message());
        focus = std::move(surf).value();
        source_what = "surfaces '" + o.surfaces + "'";
        focus_context = "--surfaces '" + o.surfaces + "'";
    } else if (!o.near_map.empty()) {
        near_img = read_map(f, "--near-map", o.near_map);
        far_img = read_map(f, "--far-map", o.far_map);
        const int nc = find_focus_map_channel(near_img, "near"), fc = find_focus_map_channel(far_img, "far");
        if (nc < 0) runtime_error("--near-map '" + o.near_map + "': no float channel");
        if (fc < 0) runtime_error("--far-map '" + o.far_map + "': no float channel");
        focus = FocusMaps{&near_img, nc, &far_img, fc};
        source_what = "maps '" + o.near_map + "', '" + o.far_map + "'";
        focus_context = "--near-map '" + o.near_map + "' / --far-map '" + o.far_map + "'";
    } else {
        if (f.stack.empty())
            usage_error("--composite: no desired focus: give --surfaces FILE, --near-map/--far-map, or an input "
                        "image with Z or P (and --blurfield) before --composite");
        StackEntry& top = f.top(flag);
        const std::string where = image_name(top);
        if (top.images.empty() || top.images.is_deep(0))
            runtime_error(flag + ": " + where + " must be a flat image with Z or P to derive near/far from the blur field");
        const Image& img = top.images.flat(0);
        camera = part_camera(f, img.metadata, img.display_window(), flag, where);
        field = field_for(f, camera, flag, where);
        BlurFocusOptions bs;
        bs.coc_px = stack.coc_px;
        bs.source = f.source;
        focus = FocusFromBlurField{&field, &camera, &img, bs};
        source_what = "blur field along the rays of " + where;
        focus_context = flag + ": " + where;
    }

    const CompositeOptions cs = o.options;
    CompositeStats stats;
    s.progress.begin("composite");
    auto r = composite(stack, focus, reader, cs, &stats, s.exec);
    check_interrupted();
    if (!r) {
        // The subject names the input at fault: the desired focus, or the stack (its near/far, its pixels).
        const Status st = r.status();
        check(st, st.subject() == "focus" ? focus_context : st.subject().empty() ? flag : flag + " '" + mpath + "'");
    }
    Image out = std::move(r).value();
    s.stats.add("composite: desired focus", stats.desired_seconds);
    s.stats.add("composite: select", stats.select_seconds);
    s.stats.add("composite: pixels", stats.composite_seconds);
    out.metadata.set_string("gdof:stackManifest", mpath);
    const int W = out.width(), H = out.height();
    const std::vector<int>& used = stats.used_references;

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
    composite.progress_stage = true;
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
