// The command table and argv -> Program.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "cli.h"
#include "gdof/diffusion.h"
#include "gdof/io/sequence.h"
#include "gdof/layers.h"
#include "gdof/version.h"

namespace gdof::cli {

namespace {

// The last command added may also be given as --flag=VALUE (its optional argument).
void table_back_optional_value(std::vector<CommandDef>& t) { t.back().optional_value = true; }

std::vector<CommandDef> make_table() {
    std::vector<CommandDef> t;
    auto add = [&](std::vector<std::string> names, std::string args, Kind kind, std::string group, std::string help,
                   std::vector<int> file_args = {}) {
        CommandDef d;
        d.names = std::move(names);
        d.args = std::move(args);
        d.nargs = 0;
        if (!d.args.empty()) {
            d.nargs = 1;
            for (char c : d.args)
                if (c == ' ') ++d.nargs;
        }
        d.kind = kind;
        d.group = std::move(group);
        d.help = std::move(help);
        d.file_args = std::move(file_args);
        t.push_back(std::move(d));
    };
    const std::string G = "General", S = "Sequences", C = "Colour", O = "Input and output", B = "Blur field";
    add({"--help", "-h"}, "", Kind::Immediate, G, "print this help and exit");
    add({"--version"}, "", Kind::Immediate, G, "print the version and exit");
    add({"-v", "--verbose"}, "", Kind::Global, G, "verbose: --info lists every attribute; frame counters");
    add({"--threads"}, "N", Kind::Global, G, "worker threads (default 0: all cores)");
    add({"--progress"}, "", Kind::Global, G, "show progress on stderr even when it is not a terminal");
    add({"--no-progress"}, "", Kind::Global, G, "never show progress");
    add({"--stats"}, "", Kind::Global, G, "print the time spent per stage on stderr at the end");

    add({"--frames"}, "SPEC", Kind::Global, S,
        "run once per frame (1-10, 1-10x2, 1,3,7-9, 10-1); #### @ %04d in file names become the frame");
    add({"--skip-bad-frames"}, "", Kind::Global, S, "report a failing frame and go on with the next (exit 1 at the end)");

    add({"--colorconfig"}, "FILE", Kind::Global, C, "OpenColorIO config (default: $OCIO, else built-in linear/sRGB)");
    add({"--iscolorspace"}, "NAME", Kind::Modifier, C,
        "colour space of the next input, overriding its metadata (8-bit PNG/JPEG default: sRGB)");
    add({"--colorconvert"}, "FROM TO", Kind::Action, C, "convert the colour channels of the top image");
    add({"--ocolorspace"}, "NAME", Kind::Modifier, C,
        "colour space of the following outputs (PNG/JPEG default: sRGB; EXR: linear)");

    add({"-i"}, "FILE", Kind::Action, O, "read FILE (same as giving FILE alone)", {0});
    add({"-o"}, "FILE", Kind::Action, O, "write the top image to FILE (atomically)", {0});
    add({"-d"}, "TYPE", Kind::Modifier, O, "pixel type of the following outputs: half or float");
    add({"--compression"}, "NAME", Kind::Modifier, O, "compression of the following outputs (zip, piz, dwaa:45, none ...)");
    add({"--info"}, "", Kind::Action, O, "describe the top image, or (before any input) each input file");
    add({"--ch"}, "LIST", Kind::Action, O, "keep/rename channels: R,G,B or Y=blur or A=1.0 (as oiiotool)");
    add({"--mulc"}, "F[,F...]", Kind::Action, O, "multiply float channels by one factor or one per channel");

    const std::string R = "Render (method 1: ray tracing)";
    add({"--render"}, "SCENE", Kind::Action, R,
        "ray-trace a scene JSON (docs/scene.md): beauty + albedo, Z, P, N, id; lens from --blurfield or the scene camera",
        {0});
    add({"--spp"}, "N", Kind::Modifier, R, "--render: aperture samples per pixel, the cap (default 64)");
    add({"--min-spp"}, "N", Kind::Modifier, R, "--render: samples every pixel gets before adaptive stopping (default 4)");
    add({"--adaptive-threshold"}, "E", Kind::Modifier, R,
        "--render: stop a pixel when its luminance standard error <= E * mean (default 0.01; 0: always --spp)");
    add({"--light-samples"}, "N", Kind::Modifier, R, "--render: area-light samples per hit (default 2)");
    add({"--pinhole"}, "", Kind::Modifier, R, "--render: all in focus (pinhole camera), ignoring the lens");
    add({"--straight-thin-lens"}, "", Kind::Modifier, R,
        "--render: trace the scene's thin lens with straight rays (reference for the polyline camera)");
    add({"--deep"}, "", Kind::Modifier, R,
        "--render: write a deep image instead (one sample per surface seen in a pixel: the input method 3 wants)");
    add({"--stack"}, "FILE", Kind::Modifier, R,
        "stack JSON: after --render, the focus distances x f-numbers to render; with --lightfield, the "
        "(focus, aperture) references to extract; the next -o (with ####) writes one image per reference + manifest.json",
        {0});

    add({"--blurfield"}, "FILE", Kind::Action, B, "load a blur-field JSON (thin_lens, focal_planes, region, ...)", {0});
    add({"--eval-blur"}, "", Kind::Action, B,
        "add a float channel 'blur' (CoC radius in output pixels) from P, or Z + camera");
    add({"--position-channels"}, "NAME", Kind::Modifier, B,
        "position layer (Pworld) or three channels (px,py,pz) for --eval-blur");
    add({"--depth-channel"}, "NAME", Kind::Modifier, B, "depth channel for --eval-blur (default Z)");
    add({"--depth-encoding"}, "NAME", Kind::Modifier, B,
        "depth values are metric (default), inverse, scaled (e.g. uint16 counts), near_far_linear, near_far_inverse");
    add({"--depth-scale"}, "S", Kind::Modifier, B, "depth = value * S (metric, scaled) or S / value (inverse)");
    add({"--depth-near"}, "D", Kind::Modifier, B, "near depth for near_far_* encodings (scene units)");
    add({"--depth-far"}, "D", Kind::Modifier, B, "far depth for near_far_* encodings (scene units)");
    // Camera overrides for --eval-blur: same names as the camera JSON keys.
    add({"--focal-length-mm"}, "MM", Kind::Modifier, B, "camera focal length in mm (overrides metadata)");
    add({"--sensor-width-mm"}, "MM", Kind::Modifier, B, "camera sensor width in mm (overrides metadata)");
    add({"--f-number"}, "N", Kind::Modifier, B, "lens f-number (overrides metadata)");
    add({"--focus-distance"}, "D", Kind::Modifier, B, "lens focus distance in scene units (overrides metadata)");
    add({"--scene-unit-mm"}, "MM", Kind::Modifier, B, "millimetres per scene unit (default 1000: metres)");

    const std::string D = "Defocus by heat diffusion (method 3)";
    add({"--diffuse"}, "", Kind::Action, D,
        "defocus the top image: layers (deep, multipart, or RGBA + Z/P) blurred per the blur field "
        "(default: the camera's thin lens) and composited");
    add({"--solver"}, "NAME", Kind::Modifier, D, "diffusion solver: auto (default: per layer, explicit up to about 15 px of blur, else adi), adi (cost independent of the blur) or explicit (the paper's reference)");
    add({"--layers"}, "N|auto[:OPTS]|id[:CHANNEL]", Kind::Modifier, D,
        "how --diffuse splits the input into layers: auto (depth clusters; deep inputs also cut where the blur changes by more than max(2 px, largest/4)); options after auto: MAX layers, blur (cut flat+Z inputs too), blur=PX, gaps (no blur cuts), e.g. auto:16:blur=3; N slices; or by a deep id channel");
    add({"--adi-steps"}, "K", Kind::Modifier, D, "ADI sub-steps per layer (default 0: automatic, up to 64)");

    const std::string M = "Compositing from focus/aperture stacks (method 2)";
    add({"--composite"}, "MANIFEST", Kind::Action, M,
        "pull each pixel from the stack reference whose near/far best matches the desired one "
        "(from --surfaces, --near-map/--far-map, or the top image's Z/P with --blurfield)", {0});
    add({"--surfaces"}, "FILE", Kind::Modifier, M, "desired near/far focus surfaces (B-spline control grids, JSON)", {0});
    add({"--near-map"}, "FILE", Kind::Modifier, M, "desired near depth per pixel (channel 'near', else Z, Y, first)", {0});
    add({"--far-map"}, "FILE", Kind::Modifier, M, "desired far depth per pixel (channel 'far', else Z, Y, first)", {0});
    add({"--soft"}, "K", Kind::Modifier, M, "blend the best K references by deviation (default 1: hard pick)");
    add({"--aovs"}, "", Kind::Modifier, M,
        "--composite also writes stack.index and stack.deviation; after --render, --aovs=LIST picks the AOVs "
        "(albedo,Z,P,N,id | all | none; default all)");
    table_back_optional_value(t);

    const std::string L = "Stacks from light fields (method 2)";
    add({"--lightfield"}, "PATTERN|FOLDER", Kind::Action, L,
        "light-field views, e.g. 'views/2067_%02d_%02d.png' (row, column) or a Stanford-archive folder; "
        "the next -o (with ####) writes one refocused image per --stack reference and manifest.json");
    add({"--lf"}, "FILE", Kind::Modifier, L, "light-field geometry JSON for --lightfield (disparity_at_infinity, ...)", {0});
    // --stack (above, Render) also names the references a --lightfield extracts.
    return t;
}

bool looks_like_flag(const std::string& a) {
    if (a.size() < 2 || a[0] != '-') return false;
    // A negative number is not a flag (frame ranges, values).
    char* end = nullptr;
    errno = 0;
    std::strtod(a.c_str(), &end);
    return !(end && *end == '\0');
}

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

int parse_int(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE || n < -1000000 || n > 1000000)
        usage_error(flag + ": expected an integer, got '" + v + "'");
    return int(n);
}

// Checks the order of the steps before any work is done: operations need an
// image on the stack, --iscolorspace needs a following input.
void validate_structure(const Program& p) {
    int depth = 0;
    bool pending_iscs = false;
    std::string pending_diffuse;  // a --diffuse modifier not yet followed by --diffuse
    bool any_action = false;
    bool composite = false;
    std::string composite_option;  // a --composite option (valid only with --composite)
    bool after_render = false;     // a --render not yet followed by -o: --aovs is its option
    for (const Step& s : p.steps) {
        if (s.is_input()) {
            ++depth;
            pending_iscs = false;
            any_action = true;
            continue;
        }
        const std::string& n = s.name();
        if (n == "-o" || n == "--colorconvert" || n == "--eval-blur" || n == "--diffuse") {
            if (depth == 0)
                usage_error(s.flag + ": no image on the stack (give an input file before " + s.flag + ")");
            any_action = true;
        }
        if (n == "--info" || n == "--blurfield") any_action = true;
        if (n == "--render") ++depth, any_action = true, after_render = true;  // pushes the rendered image
        if (n == "-o") after_render = false;
        if (n == "--composite") ++depth, any_action = true, composite = true;  // pushes (or replaces) an image
        if (n == "--lightfield") ++depth, any_action = true;  // its stack is written by the next -o
        if (n == "--surfaces" || n == "--near-map" || n == "--far-map" || n == "--soft" ||
            (n == "--aovs" && !after_render))
            composite_option = s.flag;
        if (n == "--deep" && !after_render) usage_error(s.flag + ": a --render option: give it after --render");
        if (n == "--iscolorspace") pending_iscs = true;
        if (n == "--solver" || n == "--layers" || n == "--adi-steps") pending_diffuse = s.flag;
        if (n == "--diffuse") pending_diffuse.clear();
    }
    if (!composite_option.empty() && !composite)
        usage_error(composite_option + ": only used with --composite (none given)");
    if (pending_iscs) usage_error("--iscolorspace: no input file follows it");
    if (!pending_diffuse.empty())
        usage_error(pending_diffuse + ": no --diffuse follows it (modifiers apply to the commands after them)");
    if (!any_action) usage_error("nothing to do: give an input file or a command");
}

}  // namespace

std::string message_naming_flag(const Status& s) {
    if (s.subject().empty()) return s.message();
    std::string flag = "--" + s.subject();
    std::replace(flag.begin(), flag.end(), '_', '-');
    return find_command(flag) ? s.message() + " (" + flag + ")" : s.message();
}

double parse_double(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || errno == ERANGE) usage_error(flag + ": expected a number, got '" + v + "'");
    return d;
}

const std::vector<CommandDef>& command_table() {
    static const std::vector<CommandDef> table = make_table();
    return table;
}

const CommandDef* find_command(const std::string& name) {
    for (const CommandDef& d : command_table())
        for (const std::string& n : d.names)
            if (n == name) return &d;
    return nullptr;
}

const std::string& Step::name() const {
    static const std::string input = "input";
    return def ? def->names.front() : input;
}

std::optional<Program> parse_args(const std::vector<std::string>& argv, int& exit_code) {
    Program p;
    for (std::size_t i = 0; i < argv.size(); ++i) {
        const std::string& a = argv[i];
        if (!looks_like_flag(a)) {
            if (a.empty()) usage_error("empty file name argument");
            if (a == "-") usage_error("'-' (standard input) is not supported; give a file name");
            Step s;
            s.flag = a;
            s.args = {a};
            p.steps.push_back(std::move(s));
            continue;
        }
        // --flag=value is accepted for one-argument flags.
        std::string flag = a, inline_value;
        bool has_inline = false;
        if (auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
            flag = a.substr(0, eq);
            inline_value = a.substr(eq + 1);
            has_inline = true;
        }
        const CommandDef* def = find_command(flag);
        if (!def) usage_error("unknown flag '" + flag + "' (see gdof --help)");
        Step s;
        s.def = def;
        s.flag = flag;
        if (has_inline) {
            if (def->nargs != 1 && !def->optional_value) usage_error(flag + " does not take '=VALUE'");
            s.args.push_back(inline_value);
        } else {
            for (int k = 0; k < def->nargs; ++k) {
                if (i + 1 >= argv.size())
                    usage_error(flag + ": missing argument " + std::to_string(k + 1) + " (" + flag + " " + def->args + ")");
                const std::string& v = argv[++i];
                // A flag where a value was expected is almost always a mistake,
                // except a negative number (handled by looks_like_flag).
                if (looks_like_flag(v) && find_command(v))
                    usage_error(flag + ": missing argument (" + flag + " " + def->args + "), got flag '" + v + "'");
                s.args.push_back(v);
            }
        }
        const std::string& n = def->names.front();
        if (def->kind == Kind::Immediate) {
            if (n == "--help") std::cout << usage_text();
            if (n == "--version") std::cout << "gdof " << gdof::version() << "\n";
            std::cout.flush();
            exit_code = kOk;
            return std::nullopt;
        }
        if (def->kind == Kind::Global) {
            GlobalOptions& g = p.global;
            if (n == "-v") g.verbose = true;
            else if (n == "--threads") {
                g.threads = parse_int(flag, s.args[0]);
                if (g.threads < 0) usage_error("--threads: expected 0 (all cores) or more, got '" + s.args[0] + "'");
            } else if (n == "--progress") g.progress = true, g.no_progress = false;
            else if (n == "--no-progress") g.no_progress = true, g.progress = false;
            else if (n == "--stats") g.stats = true;
            else if (n == "--frames") {
                auto r = io::parse_frame_range(s.args[0]);
                if (!r) usage_error("--frames '" + s.args[0] + "': " + r.message());
                g.frames = s.args[0];
            } else if (n == "--skip-bad-frames") g.skip_bad_frames = true;
            else if (n == "--colorconfig") g.colorconfig = s.args[0];
            continue;
        }
        // Validate values that can be checked without any file.
        if (n == "-d") {
            if (s.args[0] != "half" && s.args[0] != "float")
                usage_error("-d: unknown pixel type '" + s.args[0] + "' (expected half or float)");
        } else if (n == "--focal-length-mm" || n == "--sensor-width-mm" || n == "--f-number" ||
                   n == "--focus-distance" || n == "--scene-unit-mm") {
            double v = parse_double(flag, s.args[0]);
            if (!(v > 0) || !std::isfinite(v)) usage_error(flag + ": expected a positive number, got '" + s.args[0] + "'");
        } else if (n == "--solver") {
            auto r = parse_diffusion_solver(s.args[0].c_str());
            if (!r) usage_error(flag + ": " + r.message());
        } else if (n == "--layers") {
            auto r = parse_layer_split(s.args[0]);
            if (!r) usage_error(flag + ": " + r.message());
        } else if (n == "--soft") {
            const int k = parse_int(flag, s.args[0]);
            if (k < 1 || k > 16) usage_error(flag + ": expected 1 (hard pick) to 16, got '" + s.args[0] + "'");
        } else if (n == "--adi-steps") {
            const int k = parse_int(flag, s.args[0]);
            if (k < 0 || k > 1000) usage_error(flag + ": expected 0 (automatic) to 1000, got '" + s.args[0] + "'");
        } else if (n == "-i") {
            s.def = nullptr;  // an input like any bare file name
        }
        for (const std::string& v : s.args)
            if (v.empty() && n != "--compression") usage_error(flag + ": empty argument");
        p.steps.push_back(std::move(s));
    }
    mark_stack_outputs(p);
    validate_structure(p);
    return p;
}

}  // namespace gdof::cli
