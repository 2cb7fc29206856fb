// Runs one frame's steps on the image stack.
#include "cli.h"
#include "gdof/io/sequence.h"

namespace gdof::cli {

void check(const Status& s, const std::string& context) {
    if (s) return;
    if (interrupted()) throw CliError(kInterrupted, "interrupted");
    runtime_error(context.empty() ? s.message() : context + ": " + s.message());
}

StackEntry& Frame::top(const std::string& flag) {
    if (stack.empty()) usage_error(flag + ": no image on the stack (give an input file before " + flag + ")");
    return stack.back();
}

namespace {

std::string substitute(const std::string& arg, std::optional<int> frame) {
    if (!frame || !io::has_frame_pattern(arg)) return arg;
    auto r = io::expand_frame_pattern(arg, *frame);
    if (!r) runtime_error("'" + arg + "': " + r.message());
    return r.value();
}

std::string key_of(const std::string& flag) {
    std::string k = flag.substr(flag.find_first_not_of('-'));
    for (char& c : k)
        if (c == '-') c = '_';
    return k;
}

}  // namespace

void run_steps(Session& session, const std::vector<Step>& steps, std::optional<int> frame) {
    Frame f;
    f.session = &session;
    f.frame = frame;
    for (const Step& step : steps) {
        check_interrupted();
        if (render_step(f, &step)) continue;        // --render and its options (cmd_render.cpp)
        if (composite_step(f, &step)) continue;  // --composite and its options (cmd_composite.cpp)
        std::vector<std::string> args = step.args;
        if (step.is_input()) {
            do_input(f, substitute(args[0], frame));
            continue;
        }
        for (int k : step.def->file_args) args[std::size_t(k)] = substitute(args[std::size_t(k)], frame);
        const std::string& n = step.name();
        if (n == "-o" && step.stack_output) do_lightfield_output(f, step.args[0]);  // not a frame sequence
        else if (n == "-o") do_output(f, args[0]);
        else if (n == "--info") do_info(f);
        else if (n == "--ch") do_ch(f, args[0]);
        else if (n == "--mulc") do_mulc(f, args[0]);
        else if (n == "--colorconvert") do_colorconvert(f, args[0], args[1]);
        else if (n == "--iscolorspace") f.next_input_colorspace = args[0];
        else if (n == "--ocolorspace") f.output_colorspace = args[0];
        else if (n == "-d") f.output_pixel_type = args[0];
        else if (n == "--compression") f.output_compression = args[0];
        else if (n == "--blurfield") do_blurfield(f, args[0]);
        else if (n == "--lightfield") f.lightfield = args[0];
        else if (n == "--lf") f.lightfield_config = args[0];
        else if (n == "--stack") f.stack_spec = args[0];
        else if (n == "--eval-blur") do_eval_blur(f);
        else if (n == "--diffuse") do_diffuse(f);
        else if (n == "--solver") f.solver = take(parse_diffusion_solver(args[0].c_str()), step.flag);
        else if (n == "--layers") f.layer_split = take(parse_layer_split(args[0]), step.flag);
        else if (n == "--adi-steps") f.adi_steps = int(parse_double(step.flag, args[0]));
        else if (n == "--position-channels") f.position_channels = args[0];
        else if (n == "--depth-channel") f.depth_channel = args[0];
        else if (n == "--depth-encoding") {
            auto e = parse_depth_encoding(args[0]);
            if (!e) usage_error(step.flag + ": " + e.message());
            f.depth_decode.encoding = e.value();
        } else if (n == "--depth-scale") f.depth_decode.scale = parse_double(step.flag, args[0]);
        else if (n == "--depth-near") f.depth_decode.near = parse_double(step.flag, args[0]);
        else if (n == "--depth-far") f.depth_decode.far = parse_double(step.flag, args[0]);
        else if (n == "--focal-length-mm" || n == "--sensor-width-mm" || n == "--f-number" ||
                 n == "--focus-distance" || n == "--scene-unit-mm")
            f.camera_overrides[key_of(n)] = parse_double(step.flag, args[0]);
        else
            runtime_error("internal: no handler for " + n);
    }
    render_step(f, nullptr);     // a --render still waiting for its options runs now
    composite_step(f, nullptr);  // a --composite still waiting for its options runs now
}

}  // namespace gdof::cli
