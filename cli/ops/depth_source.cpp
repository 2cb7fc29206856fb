// Where --eval-blur, --diffuse and --composite find depth: the position or
// depth channels and how depth values are encoded (Frame::source, a
// PositionSource).
#include "cli.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

Command source_option(std::vector<std::string> names, std::string args, std::string help,
                      std::function<void(Frame&, const Step&)> run) {
    return {.names = std::move(names), .args = std::move(args), .kind = Kind::Modifier, .group = "Blur field",
            .help = std::move(help), .run = std::move(run)};
}

double number(const Step& s) { return parse_double(s.flag, s.args[0]); }

}  // namespace

std::vector<Command> depth_source_commands() {
    std::vector<Command> t;
    t.push_back(source_option({"--position-channels"}, "NAME",
                              "position layer (Pworld) or three channels (px,py,pz) for --eval-blur",
                              [](Frame& f, const Step& s) { f.source.position_channels = s.args[0]; }));
    t.push_back(source_option({"--depth-channel"}, "NAME", "depth channel for --eval-blur (default Z)",
                              [](Frame& f, const Step& s) { f.source.depth_channel = s.args[0]; }));
    t.push_back(source_option(
        {"--depth-encoding"}, "NAME",
        "depth values are metric (default), inverse, scaled (e.g. uint16 counts), near_far_linear, near_far_inverse",
        [](Frame& f, const Step& s) {
            auto e = parse_depth_encoding(s.args[0]);
            if (!e) usage_error(s.flag + ": " + e.message());
            f.source.depth_decode.encoding = e.value();
        }));
    t.push_back(source_option({"--depth-scale"}, "S", "depth = value * S (metric, scaled) or S / value (inverse)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.scale = number(s); }));
    t.push_back(source_option({"--depth-near"}, "D", "near depth for near_far_* encodings (scene units)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.near = number(s); }));
    t.push_back(source_option({"--depth-far"}, "D", "far depth for near_far_* encodings (scene units)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.far = number(s); }));
    return t;
}

}  // namespace gdof::cli
