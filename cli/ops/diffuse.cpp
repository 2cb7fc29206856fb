// --diffuse: method 3, generalized defocus by simulated heat diffusion of
// layers (gdof/defocus.h). The top image (deep, multipart / multilayer with
// P or Z, or flat RGBA + depth) becomes one flat part: R, G, B, A defocused,
// the other channels of a flat input carried over. Modifiers before it:
// --solver, --layers, --adi-steps (Frame::defocus), and the --eval-blur ones
// (positions, depth channel and encoding, lens overrides).
#include <filesystem>

#include "camera_field.h"
#include "cli.h"
#include "gdof/defocus.h"
#include "gdof/diffusion.h"
#include "gdof/io/psf_field_io.h"
#include "gdof/layers.h"
#include "gdof/psf_field.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

const char* op_flag(DefocusFilter filter) {
    return filter == DefocusFilter::Bokeh ? "--bokeh" : filter == DefocusFilter::Vibrate ? "--vibrate" : "--diffuse";
}

void report_defocus(Frame& f, const std::string& flag, const std::string& where, const DefocusStats& stats) {
    Session& s = *f.session;
    s.stats.add(" layers", stats.t_layers);
    s.stats.add(" blur map", stats.t_blur);
    s.stats.add(" extrapolate", stats.t_extrapolate);
    s.stats.add(" solve", stats.t_diffuse);
    s.stats.add(" composite", stats.t_composite);
    if (s.global.stats || s.global.verbose) {
        // The library's report without its title line, headed by what ran.
        std::string rep = stats.report();
        rep = rep.substr(rep.find('\n') + 1);
        if (!rep.empty() && rep.back() == '\n') rep.pop_back();
        const std::string how =
            f.defocus.filter == DefocusFilter::Bokeh ? "aperture " + format_aperture(f.defocus.aperture)
            : f.defocus.filter == DefocusFilter::Vibrate
                ? "psf field " + f.defocus.psf_field.describe() + ", aperture " + format_aperture(f.defocus.aperture)
                : "solver " + std::string(to_string(f.defocus.diffusion.solver));
        s.progress.message("gdof: " + flag + " " + where + (f.frame ? " frame " + std::to_string(*f.frame) : "") +
                           " (" + how + "):\n" + rep);
    }
}

// One view (or a file without views) through defocus().
ImageSet diffuse_view(Frame& f, const ImageSet& images, const std::string& where) {
    Session& s = *f.session;
    const std::string flag = op_flag(f.defocus.filter);
    const std::size_t ref = defocus_reference_part(images);
    const Camera camera = image_camera(f, images, ref, flag, where);
    const BlurField field = field_for(f, camera, flag, where);
    DefocusOptions options = f.defocus;
    options.source = f.source;

    DefocusStats stats;
    Result<ImageSet> result = ImageSet{};
    {
        StageTimer timer(s.stats, flag.substr(2));
        result = defocus(images, field, camera, options, &stats, s.exec);
    }
    check_interrupted();
    if (!result) runtime_error(flag + ": " + where + ": " + message_naming_flag(result.status()));
    report_defocus(f, flag, where, stats);
    return std::move(result).value();
}

// --diffuse and --bokeh: the same pipeline, a different filter per layer.
void do_defocus(Frame& f, DefocusFilter filter) {
    f.defocus.filter = filter;
    const std::string flag = op_flag(filter);
    StackEntry& top = f.top(flag);
    const std::string where = image_name(top);
    if (top.images.empty()) runtime_error(flag + ": " + where + " has no image parts");
    if (!top.colorspace.empty())
        runtime_error(flag + ": the colour channels of " + where + " are in '" + top.colorspace +
                      "' (after --colorconvert); defocus in the scene-linear working space, convert afterwards");
    // A stereo / multi-view file: every view, one output part each (--view
    // picks one).
    const std::vector<std::string> views = part_views(top.images);
    f.session->progress.begin(flag.substr(2));
    if (views.size() <= 1) {
        top.images = diffuse_view(f, top.images, where);
        return;
    }
    ImageSet out;
    for (std::size_t i = 0; i < views.size(); ++i) {
        const std::string& v = views[i];
        f.session->progress.part(int(i), int(views.size()));
        auto sub = select_view(top.images, v);
        if (!sub) runtime_error(flag + ": " + where + ": " + sub.message());
        ImageSet r = diffuse_view(f, *sub, where + " view '" + v + "'");
        for (Part& p : r.parts) {
            std::visit([&](auto& img) { img.view = v; }, p);
            out.parts.push_back(std::move(p));
        }
    }
    top.images = std::move(out);
}

// The values of --solver, --layers, --adi-steps; usage errors naming the flag.
DiffusionSolver solver(const Step& s) {
    auto r = parse_diffusion_solver(s.args[0].c_str());
    if (!r) usage_error(s.flag + ": " + r.message());
    return r.value();
}

LayerSplit layer_split(const Step& s) {
    auto r = parse_layer_split(s.args[0]);
    if (!r) usage_error(s.flag + ": " + r.message());
    return std::move(r).value();
}

int adi_steps(const Step& s) {
    const int k = parse_int(s.flag, s.args[0]);
    if (k < 0 || k > 1000) usage_error(s.flag + ": expected 0 (automatic) to 1000, got '" + s.args[0] + "'");
    return k;
}

int psf_samples(const Step& s) {
    const int k = parse_int(s.flag, s.args[0]);
    if (k < 0 || k > 65536) usage_error(s.flag + ": expected 0 (automatic) to 65536, got '" + s.args[0] + "'");
    return k;
}

// --psf-field FILE: the PSF field's JSON (docs/psf_field.md); its blend
// weights' image_maps are read relative to the file, as data.
void psf_field(Frame& f, const std::string& path) {
    const std::string text = read_flag_file("--psf-field", "file", path);
    std::error_code ec;
    const std::string dir = std::filesystem::absolute(std::filesystem::path(path), ec).parent_path().string();
    auto r = io::parse_psf_field(text, dir);
    if (!r) runtime_error("--psf-field '" + path + "': " + r.message());
    f.defocus.psf_field = std::move(r).value();
}

bool pyramid(const Step& s) {
    if (s.args[0] == "on") return true;
    if (s.args[0] == "off") return false;
    usage_error(s.flag + ": expected 'on' or 'off', got '" + s.args[0] + "'");
}

}  // namespace

std::vector<Command> diffuse_commands() {
    const std::string D = "Defocus by heat diffusion (method 3)";
    std::vector<Command> t;
    // The three actions run one pipeline with a different filter.
    auto action = [&](const char* name, DefocusFilter filter, const char* help) {
        Command c{.names = {name}, .kind = Kind::Action, .group = D, .help = help, .stack = StackUse::NeedsImage,
                  .progress_stage = true};
        c.run = [filter](Frame& f, const Step&) { do_defocus(f, filter); };
        t.push_back(std::move(c));
    };
    action("--diffuse", DefocusFilter::Diffusion,
           "defocus the top image: layers (deep, multipart, or RGBA + Z/P) blurred per the blur field "
           "(default: the camera's thin lens) and composited");
    action("--bokeh", DefocusFilter::Bokeh,
           "defocus the top image as --diffuse does (same layers, blur field, extrapolation, "
           "compositing), each layer spread over the --aperture shape (default disc): bokeh that "
           "respects visibility");
    action("--vibrate", DefocusFilter::Vibrate,
           "method 4, the generalized PSF field: the layers of --diffuse moved per aperture sample by "
           "the --psf-field displacement (default: defocus, B(x) times the --aperture sample), "
           "composited with visibility and averaged");
    t.push_back({.names = {"--psf-field"}, .args = "FILE", .kind = Kind::Modifier, .group = D,
                 .help = "the PSF field JSON for --vibrate: defocus, swirl, depth, image_map, sum, blend (docs/psf_field.md)",
                 .run = [](Frame& f, const Step& s) { psf_field(f, s.args[0]); }});
    t.push_back({.names = {"--psf-samples"}, .args = "N", .kind = Kind::Modifier, .group = D,
                 .help = "aperture samples for --vibrate (default 0: the field's \"samples\", else automatic from the "
                         "largest displacement)",
                 .run = [](Frame& f, const Step& s) { f.defocus.vibrate.samples = psf_samples(s); },
                 .check = [](const Step& s) { psf_samples(s); }});
    t.push_back({.names = {"--solver"}, .args = "NAME", .kind = Kind::Modifier, .group = D,
                 .help = "diffusion solver: auto (default: per layer, explicit up to about 15 px of blur, else adi), adi "
                         "(cost independent of the blur) or explicit (the paper's reference)",
                 .run = [](Frame& f, const Step& s) { f.defocus.diffusion.solver = solver(s); },
                 .check = [](const Step& s) { solver(s); }});
    t.push_back({.names = {"--layers"}, .args = "N|auto[:OPTS]|id[:CHANNEL]", .kind = Kind::Modifier, .group = D,
                 .help = "how --diffuse splits the input into layers: auto (depth clusters, also cut by blur where "
                         "a layer's blur would vary by more than max(2 px, largest/4); under --diffuse only at "
                         "silhouettes whose sides' blur differs by more than max(2 px, largest/4.5)); options after auto: MAX layers, blur=PX, gaps "
                         "(no blur cuts), e.g. auto:16:blur=3; N slices; or by a deep id channel",
                 .run = [](Frame& f, const Step& s) { f.defocus.split = layer_split(s); },
                 .check = [](const Step& s) { layer_split(s); }});
    t.push_back({.names = {"--adi-steps"}, .args = "K", .kind = Kind::Modifier, .group = D,
                 .help = "ADI sub-steps per layer (default 0: automatic, up to 64)",
                 .run = [](Frame& f, const Step& s) { f.defocus.diffusion.adi_steps = adi_steps(s); },
                 .check = [](const Step& s) { adi_steps(s); }});
    t.push_back({.names = {"--pyramid"}, .args = "on|off", .kind = Kind::Modifier, .group = D,
                 .help = "on (default): blurs above 6 px solved on coarser levels of a pyramid and blended per pixel, "
                         "many times faster; off: every layer at full resolution (the reference)",
                 .run = [](Frame& f, const Step& s) { f.defocus.diffusion.pyramid = pyramid(s); },
                 .check = [](const Step& s) { pyramid(s); }});
    return t;
}

}  // namespace gdof::cli
