// --ch (channel selection / renaming / constants) and --mulc (scale), on every
// flat part of the top image. The work is gdof::select_channels / multiply_channels.
#include "cli.h"
#include "gdof/image_ops.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

void do_ch(Frame& f, const std::string& list) {
    StackEntry& top = f.top("--ch");
    std::vector<std::string> spec = take(split_list(list), "--ch");
    for (std::size_t i = 0; i < top.images.size(); ++i) {
        if (top.images.is_deep(i)) runtime_error("--ch: part " + std::to_string(i) + " of '" + top.source + "' is deep; --ch works on flat images");
        top.images.parts[i] = take(select_channels(top.images.flat(i), spec), "--ch " + list);
    }
}

void do_mulc(Frame& f, const std::string& list) {
    StackEntry& top = f.top("--mulc");
    std::vector<double> factors;
    for (const std::string& v : take(split_list(list), "--mulc")) factors.push_back(parse_double("--mulc", v));
    for (std::size_t i = 0; i < top.images.size(); ++i) {
        if (top.images.is_deep(i)) runtime_error("--mulc: part " + std::to_string(i) + " of '" + top.source + "' is deep; --mulc works on flat images");
        check(multiply_channels(top.images.flat(i), factors), "--mulc " + list);
    }
}

}  // namespace

std::vector<Command> channel_commands() {
    const std::string O = "Input and output";
    std::vector<Command> t;
    t.push_back({.names = {"--ch"}, .args = "LIST", .kind = Kind::Action, .group = O,
                 .help = "keep/rename channels: R,G,B or Y=blur or A=1.0 (as oiiotool)",
                 .run = [](Frame& f, const Step& s) { do_ch(f, s.args[0]); }});
    t.push_back({.names = {"--mulc"}, .args = "F[,F...]", .kind = Kind::Action, .group = O,
                 .help = "multiply float channels by one factor or one per channel",
                 .run = [](Frame& f, const Step& s) { do_mulc(f, s.args[0]); }});
    return t;
}

}  // namespace gdof::cli
