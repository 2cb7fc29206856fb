// Where --eval-blur, --diffuse and --composite find depth: the position or
// depth channels and how depth values are encoded (Frame::source, a
// PositionSource).
#include <limits>

#include "camera_field.h"
#include "cli.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

Command source_option(std::vector<std::string> names, std::string args, std::string help,
                      std::function<void(Frame&, const Step&)> run, std::function<void(const Step&)> check = {}) {
    return {.names = std::move(names), .args = std::move(args), .kind = Kind::Modifier, .group = "Blur field",
            .help = std::move(help), .run = std::move(run), .check = std::move(check)};
}

double number(const Step& s) { return parse_double(s.flag, s.args[0]); }

double invalid(const Step& s) {
    if (s.args[0] == "hole") return std::numeric_limits<double>::quiet_NaN();
    if (s.args[0] == "sky") return std::numeric_limits<double>::infinity();
    usage_error(s.flag + ": expected hole or sky, got '" + s.args[0] + "'");
}

}  // namespace

std::vector<Command> depth_source_commands() {
    std::vector<Command> t;
    t.push_back(source_option({"--position-channels"}, "NAME",
                              "position layer (Pworld) or three channels (px,py,pz) for --diffuse and --eval-blur",
                              [](Frame& f, const Step& s) { f.source.position_channels = s.args[0]; }));
    t.push_back(source_option(
        {"--depth-channel"}, "NAME",
        "depth channel for --diffuse, --eval-blur, --focus-at and --probe (default Z); before --depth, the channel it "
        "reads from its file",
        [](Frame& f, const Step& s) {
            // After --depth the depth file's channel is chosen and attached
            // under another name: a later NAME would find no depth, with no
            // word on why (modifiers act on later steps only).
            if (!f.stack.empty()) {
                const StackEntry& top = f.stack.back();
                bool has = false;
                for (std::size_t i = 0; i < top.images.size(); ++i)
                    has = has || (!top.images.is_deep(i) && top.images.flat(i).channel_index(s.args[0]) >= 0);
                if (!top.attached_depth.empty() && top.attached_depth != s.args[0] && !has)
                    usage_error(s.flag + " " + s.args[0] + ": comes after --depth, which attached '" +
                                top.attached_from + "' to " + image_name(top) + " as channel '" + top.attached_depth +
                                "'; give " + s.flag + " before --depth (there it picks the depth file's channel "
                                "and names the image's depth channel)");
            }
            f.source.depth_channel = s.args[0];
        }));
    t.push_back(source_option(
        {"--depth-encoding"}, "NAME",
        "depth values are metric (default), inverse, scaled (e.g. uint16 counts), near_far_linear, near_far_inverse, "
        "disparity (depth = focal length in px x --baseline / value)",
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
    t.push_back(source_option({"--depth-invalid"}, "hole|sky",
                              "what invalid depth (0, NaN, --depth-invalid-value, beyond --depth-max) is: a hole, "
                              "filled from around it (default), or sky (infinitely far)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.invalid = invalid(s); },
                              [](const Step& s) { invalid(s); }));
    t.push_back(source_option({"--depth-invalid-value"}, "V", "a stored value that means no measurement (e.g. 65535)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.invalid_value = number(s); }));
    t.push_back(source_option({"--depth-max"}, "D", "decoded depths beyond D are invalid (a sensor's range)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.max_depth = number(s); }));
    t.push_back(source_option({"--baseline"}, "B",
                              "stereo baseline (scene units) for --depth-encoding disparity; the focal length in px "
                              "comes from the camera (or --depth-scale gives focal px x baseline)",
                              [](Frame& f, const Step& s) { f.source.depth_decode.baseline = number(s); }));
    t.push_back(source_option({"--depth-range"}, "",
                              "depth values are distances along each pixel's ray, not along the viewing axis",
                              [](Frame& f, const Step&) { f.source.depth_decode.range = true; }));
    return t;
}

}  // namespace gdof::cli
