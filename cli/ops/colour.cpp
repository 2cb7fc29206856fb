// Colour: --colorconfig, --iscolorspace, --colorconvert, --ocolorspace, and
// checking colour space names against the config before any work is done.
#include "cli.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

void require_space(const io::ColourConfig& config, const std::string& flag, const std::string& name) {
    if (!config.resolve(name).empty()) return;
    std::string known;
    for (const std::string& n : config.colour_spaces()) known += (known.empty() ? "" : ", ") + n;
    if (known.size() > 200) known = known.substr(0, 200) + " ...";
    usage_error(flag + ": unknown colour space '" + name + "' in the " + config.description() + " (known: " + known + ")");
}

// Every argument of the step names a colour space.
void require_spaces(const Session& session, const Step& s) {
    for (const std::string& name : s.args) require_space(*session.colour, s.flag, name);
}

void do_colorconvert(Frame& f, const std::string& from, const std::string& to) {
    Session& s = *f.session;
    StackEntry& top = f.top("--colorconvert");
    StageTimer t(s.stats, "colour");
    const io::ColourConfig& config = *s.colour;
    const std::string b = config.resolve(to);
    for (std::size_t i = 0; i < top.images.size(); ++i) {
        check_interrupted();
        Status st = top.images.is_deep(i) ? config.convert(top.images.deep(i), from, to)
                                          : config.convert(top.images.flat(i), from, to);
        check(st, "--colorconvert " + from + " " + to);
        top.images.metadata(i).set_string("oiio:ColorSpace", b);
    }
    // Remember where the values are now, so -o does not convert them twice.
    if (b != config.resolve("raw")) top.colorspace = b == working_space(config) ? std::string() : b;
}

}  // namespace

std::string working_space(const io::ColourConfig& config) {
    for (const char* n : {"scene_linear", "linear", "default"}) {
        std::string r = config.resolve(n);
        if (!r.empty() && config.is_linear(r)) return r;
    }
    for (const std::string& n : config.colour_spaces())
        if (config.is_linear(n)) return n;
    return {};
}

std::vector<Command> colour_commands() {
    const std::string C = "Colour";
    std::vector<Command> t;
    t.push_back({.names = {"--colorconfig"}, .args = "FILE", .kind = Kind::Global, .group = C,
                 .help = "OpenColorIO config (default: $OCIO, else built-in linear/sRGB)",
                 .set = [](GlobalOptions& g, const Step& s) { g.colorconfig = s.args[0]; }});
    t.push_back({.names = {"--iscolorspace"}, .args = "NAME", .kind = Kind::Modifier, .group = C,
                 .help = "colour space of the next input, overriding its metadata (8-bit PNG/JPEG default: sRGB)",
                 .run = [](Frame& f, const Step& s) { f.next_input_colorspace = s.args[0]; },
                 .preflight = require_spaces});
    t.push_back({.names = {"--colorconvert"}, .args = "FROM TO", .kind = Kind::Action, .group = C,
                 .help = "convert the colour channels of the top image", .stack = StackUse::NeedsImage,
                 .run = [](Frame& f, const Step& s) { do_colorconvert(f, s.args[0], s.args[1]); },
                 .preflight = require_spaces});
    t.push_back({.names = {"--ocolorspace"}, .args = "NAME", .kind = Kind::Modifier, .group = C,
                 .help = "colour space of the following outputs (PNG/JPEG default: sRGB; EXR: linear)",
                 .run = [](Frame& f, const Step& s) { f.output.colorspace = s.args[0]; },
                 .preflight = require_spaces});
    return t;
}

}  // namespace gdof::cli
