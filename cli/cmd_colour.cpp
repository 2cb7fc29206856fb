// --colorconvert, and checking colour space names before any work is done.
#include "cli.h"

namespace gdof::cli {

namespace {

void require_space(const io::ColourConfig& config, const std::string& flag, const std::string& name) {
    if (!config.resolve(name).empty()) return;
    std::string known;
    for (const std::string& n : config.colour_spaces()) known += (known.empty() ? "" : ", ") + n;
    if (known.size() > 200) known = known.substr(0, 200) + " ...";
    usage_error(flag + ": unknown colour space '" + name + "' in the " + config.description() + " (known: " + known + ")");
}

}  // namespace

void preflight_colour(const Session& session, const std::vector<Step>& steps) {
    for (const Step& s : steps) {
        if (s.is_input()) continue;
        const std::string& n = s.name();
        if (n == "--iscolorspace" || n == "--ocolorspace") require_space(*session.colour, s.flag, s.args[0]);
        if (n == "--colorconvert") {
            require_space(*session.colour, s.flag, s.args[0]);
            require_space(*session.colour, s.flag, s.args[1]);
        }
    }
}

void do_colorconvert(Frame& f, const std::string& from, const std::string& to) {
    Session& s = *f.session;
    StackEntry& top = f.top("--colorconvert");
    StageTimer t(s.stats, "colour");
    const io::ColourConfig& config = *s.colour;
    const std::string a = config.resolve(from), b = config.resolve(to);
    for (std::size_t i = 0; i < top.images.size(); ++i) {
        check_interrupted();
        Status st = top.images.is_deep(i) ? config.convert(top.images.deep(i), from, to)
                                          : config.convert(top.images.flat(i), from, to);
        check(st, "--colorconvert " + from + " " + to);
        top.images.metadata(i).set_string("oiio:ColorSpace", b);
    }
    // Remember where the values are now, so -o does not convert them twice.
    if (b != config.resolve("raw")) top.colorspace = b == working_space(config) ? std::string() : b;
    (void)a;
}

}  // namespace gdof::cli
