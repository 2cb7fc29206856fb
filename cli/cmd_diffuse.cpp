// --diffuse: method 3, generalized defocus by simulated heat diffusion of
// layers (gdof/defocus.h). The top image (deep, multipart / multilayer with
// P or Z, or flat RGBA + depth) becomes one flat part: R, G, B, A defocused,
// the other channels of a flat input carried over. Modifiers before it:
// --solver, --layers, --adi-steps, and the --eval-blur ones (positions,
// depth channel and encoding, lens overrides).
#include "cli.h"
#include "gdof/defocus.h"

namespace gdof::cli {

namespace {

// The part whose camera and display window the result takes (as defocus()
// does: the first deep part, else the first part).
std::size_t reference_part(const ImageSet& set) {
    for (std::size_t i = 0; i < set.size(); ++i)
        if (set.is_deep(i)) return i;
    return 0;
}

Roi part_display(const ImageSet& set, std::size_t i) {
    return set.is_deep(i) ? set.deep(i).display_window() : set.flat(i).display_window();
}

}  // namespace

void do_diffuse(Frame& f) {
    Session& s = *f.session;
    StackEntry& top = f.top("--diffuse");
    const std::string where = image_name(top);
    if (top.images.empty()) runtime_error("--diffuse: " + where + " has no image parts");
    if (!top.colorspace.empty())
        runtime_error("--diffuse: the colour channels of " + where + " are in '" + top.colorspace +
                      "' (after --colorconvert); diffuse in the scene-linear working space, convert afterwards");

    const std::size_t ref = reference_part(top.images);
    const Camera camera = part_camera(f, top.images.metadata(ref), part_display(top.images, ref), "--diffuse", where);
    const BlurField field = field_for(f, camera, "--diffuse", where);

    DefocusOptions settings;
    settings.diffusion.solver = f.solver;
    settings.diffusion.adi_steps = f.adi_steps;
    settings.split = f.layer_split;
    settings.source = PositionSource{f.position_channels, f.depth_channel, f.depth_decode};

    DefocusStats stats;
    Result<ImageSet> result = ImageSet{};
    {
        StageTimer timer(s.stats, "diffuse");
        s.progress.begin("diffuse");
        result = defocus(top.images, field, camera, settings, &stats, s.exec);
        s.progress.end();
    }
    check_interrupted();
    if (!result) runtime_error("--diffuse: " + where + ": " + message_naming_flag(result.status()));
    top.images = std::move(result).value();

    s.stats.add(" layers", stats.t_layers);
    s.stats.add(" blur map", stats.t_blur);
    s.stats.add(" extrapolate", stats.t_extrapolate);
    s.stats.add(" solve", stats.t_diffuse);
    s.stats.add(" composite", stats.t_composite);
    if (s.global.stats || s.global.verbose) {
        // The library's report, headed by what ran.
        std::string rep = stats.report();
        rep = rep.substr(rep.find('\n') + 1);
        if (!rep.empty() && rep.back() == '\n') rep.pop_back();
        s.progress.message("gdof: --diffuse " + where + (f.frame ? " frame " + std::to_string(*f.frame) : "") +
                           " (solver " + to_string(f.solver) + "):\n" + rep);
    }
}

}  // namespace gdof::cli
