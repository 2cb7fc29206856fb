// The order rules between steps, checked after parsing and before any work
// (usage errors): operations need an image on the stack, modifiers need the
// command they modify, and which -o writes a stack.
#include "command.h"
#include "errors.h"

namespace gdof::cli {

// The first -o after each --lightfield writes its stack, and so does the -o
// after a --render given --stack (between the two). --lf and a --stack not
// after a --render need a --lightfield to apply to.
void mark_stack_outputs(Program& p) {
    std::string pending, lf_flag, stack_flag;
    bool any_lightfield = false;
    bool render_pending = false, render_stack = false;
    for (Step& s : p.steps) {
        const std::string& n = s.name();
        if (n == "--lf") lf_flag = s.flag;
        if (n == "--stack" && render_pending) render_stack = true;
        else if (n == "--stack") stack_flag = s.flag;
        if (n == "--render") render_pending = true, render_stack = false;
        if (n == "--lightfield") {
            if (!pending.empty()) usage_error("--lightfield '" + pending + "': no -o writes its stack before the next --lightfield");
            pending = s.args[0];
            any_lightfield = true;
        }
        if (n == "-o" && !pending.empty()) {
            if (stack_flag.empty())
                usage_error("--lightfield '" + pending + "': give --stack stack.json (the references to extract) before -o");
            s.stack_output = true;
            pending.clear();
        } else if (n == "-o" && render_stack) {
            s.stack_output = true;
        }
        if (n == "-o") render_pending = render_stack = false;
    }
    if (!pending.empty())
        usage_error("--lightfield '" + pending + "': no -o follows it (e.g. -o stack/ref.####.exr)");
    if (render_stack) usage_error("--render --stack: no -o follows it (e.g. -o stack/ref.####.exr)");
    if (!any_lightfield && !lf_flag.empty()) usage_error(lf_flag + ": only used with --lightfield (none given)");
    if (!any_lightfield && !stack_flag.empty())
        usage_error(stack_flag + ": only used with --lightfield or after --render (neither given)");
}

// The stack depth (from each row's StackUse), the modifiers' commands, and
// that there is something to do and a result: an -o, or a command that
// prints (a command line that writes nothing is a usage error).
void validate_structure(const Program& p) {
    int depth = 0;
    bool pending_iscs = false;
    std::string pending_diffuse;  // a --diffuse modifier not yet followed by --diffuse
    std::string pending_layers;   // --layers not yet followed by --diffuse, --bokeh or --vibrate
    std::string pending_vibrate;  // --psf-field / --psf-samples not yet followed by --vibrate
    std::string pending_sweep;    // --aligned-stack / --dff-* not yet followed by --depth-from-focus
    bool any_work = false;
    bool any_result = false;  // an -o, or a command that prints its result
    bool composite = false;
    std::string composite_option;  // a --composite option (valid only with --composite)
    bool after_render = false;     // a --render not yet followed by -o: --aovs is its option
    for (const Step& s : p.steps) {
        if (s.is_input()) {
            ++depth;
            pending_iscs = false;
            any_work = true;
            continue;
        }
        const Command& c = *s.def;
        if (s.name() == "-o" || c.prints_result) any_result = true;
        if (c.stack == StackUse::NeedsImage && depth == 0)
            usage_error(s.flag + ": no image on the stack (give an input file before " + s.flag + ")");
        if (c.stack == StackUse::PushesImage) ++depth;
        if (c.stack != StackUse::None || c.is_work) any_work = true;
        const std::string& n = s.name();
        if (n == "--render") after_render = true;
        if (n == "-o") after_render = false;
        if (n == "--composite") composite = true;
        if (n == "--surfaces" || n == "--near-map" || n == "--far-map" || n == "--soft" ||
            (n == "--aovs" && !after_render))
            composite_option = s.flag;
        if (n == "--deep" && !after_render) usage_error(s.flag + ": a --render option: give it after --render");
        if (n == "--iscolorspace") pending_iscs = true;
        if (n == "--solver" || n == "--adi-steps" || n == "--pyramid") pending_diffuse = s.flag;
        if (n == "--layers") pending_layers = s.flag;
        if (n == "--diffuse") pending_diffuse.clear();
        if (n == "--diffuse" || n == "--bokeh" || n == "--vibrate") pending_layers.clear();
        if (n == "--psf-field" || n == "--psf-samples") pending_vibrate = s.flag;
        if (n == "--vibrate") pending_vibrate.clear();
        if (n == "--aligned-stack" || n == "--focus-distances" || n == "--dff-window-radius" || n == "--dff-min-peak-ratio")
            pending_sweep = s.flag;
        if (n == "--depth-from-focus") pending_sweep.clear();
    }
    if (!composite_option.empty() && !composite)
        usage_error(composite_option + ": only used with --composite (none given)");
    if (pending_iscs) usage_error("--iscolorspace: no input file follows it");
    if (!pending_diffuse.empty())
        usage_error(pending_diffuse + ": no --diffuse follows it (modifiers apply to the commands after them)");
    if (!pending_layers.empty())
        usage_error(pending_layers + ": no --diffuse or --bokeh follows it (modifiers apply to the commands after them)");
    if (!pending_vibrate.empty())
        usage_error(pending_vibrate + ": no --vibrate follows it (modifiers apply to the commands after them)");
    if (!pending_sweep.empty())
        usage_error(pending_sweep + ": no --depth-from-focus follows it (modifiers apply to the commands after them)");
    if (!any_work) usage_error("nothing to do: give an input file or a command");
    if (!any_result) usage_error("no output: give -o FILE (or --info / --probe, which print their result)");
}

}  // namespace gdof::cli
