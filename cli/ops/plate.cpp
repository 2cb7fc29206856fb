// Live-action plates and the files they come in: --depth FILE (a depth map
// as its own file), --part and --view (which parts of a multipart or stereo
// file), --depth-cleanup (what the plate preparation repairs), --focus-at
// (focus from a pixel) and --probe (what the pipeline sees at a pixel).
#include <iostream>
#include <optional>
#include <sstream>

#include "camera_field.h"
#include "cli.h"
#include "gdof/blur_map.h"
#include "gdof/io/image_io.h"
#include "gdof/plate.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

const std::string P = "Live-action plates";

// The one flat part a plate operation works on: the top image must be flat.
Image& flat_plate(StackEntry& top, const std::string& flag) {
    for (std::size_t i = 0; i < top.images.size(); ++i)
        if (!top.images.is_deep(i)) return top.images.flat(i);
    runtime_error(flag + ": " + image_name(top) + " has no flat part");
}

void do_depth(Frame& f, const std::string& path) {
    StackEntry& top = f.top("--depth");
    io::ReadOptions ro;
    ro.colorspace = "raw";  // depth values are data: never colour-converted
    ro.colour = f.session->colour.get();
    auto r = io::read_image(path, ro);
    if (!r) runtime_error("--depth: " + r.message());
    const ImageSet& d = r.value();
    if (d.empty() || d.is_deep(0)) runtime_error("--depth: '" + path + "' holds no flat image");
    const Image& depth = d.flat(0);
    // --depth-channel names the channel in the depth file when it has one of
    // that name; else Z, else its first channel. It becomes the plate's
    // depth channel under the same name (default Z).
    if (depth.nchannels() == 0) runtime_error("--depth: '" + path + "' has no channels");
    const std::string name = f.source.depth_channel.empty() ? std::string("Z") : f.source.depth_channel;
    int c = depth.channel_index(name);
    if (c < 0) c = 0;
    Image& plate = flat_plate(top, "--depth");
    check(attach_depth(plate, depth, c, name, image_name(top), "'" + path + "'"), "--depth");
    top.attached_depth = name;
    top.attached_from = path;
}

void do_view(Frame& f, const Step& s) {
    StackEntry& top = f.top(s.flag);
    auto r = select_view(top.images, s.args[0]);
    if (!r) runtime_error(s.flag + ": " + image_name(top) + ": " + r.message());
    top.images = std::move(r).value();
}

void do_part(Frame& f, const Step& s) {
    StackEntry& top = f.top(s.flag);
    auto r = select_parts(top.images, s.args[0]);
    if (!r) runtime_error(s.flag + ": " + image_name(top) + ": " + r.message());
    top.images = std::move(r).value();
}

std::pair<int, int> pixel(const Step& s) {
    const std::size_t comma = s.args[0].find(',');
    if (comma == std::string::npos) usage_error(s.flag + ": expected X,Y (pixel coordinates), got '" + s.args[0] + "'");
    return {parse_int(s.flag, s.args[0].substr(0, comma)), parse_int(s.flag, s.args[0].substr(comma + 1))};
}

// Prints what it can: depth needs no camera (but to decode a range or a
// disparity from a baseline), a world position needs one, a blur a lens or a
// --blurfield. A probe is how a focus distance is chosen, so it must not ask
// for one first; what is missing is said on the line.
void do_probe(Frame& f, const Step& s) {
    StackEntry& top = f.top(s.flag);
    const std::string where = image_name(top);
    const auto [x, y] = pixel(s);
    std::size_t part = 0;
    while (part < top.images.size() && top.images.is_deep(part)) ++part;
    if (part == top.images.size()) runtime_error("--probe: " + where + " has no flat part");
    const Image& img = top.images.flat(part);
    std::optional<Camera> camera;
    std::string missing;
    if (f.focus_at) {
        camera = image_camera(f, top.images, part, "--probe", where);
    } else if (auto c = resolve_camera(top.images.metadata(part), img.display_window(), f.lens)) {
        camera = std::move(c).value();
    } else {
        missing = "no world position or blur: " + message_naming_flag(c.status());
    }
    std::optional<BlurField> field;
    if (camera) {
        auto lens = camera->thin_lens();
        if (f.blur || lens) field = field_for(f, *camera, "--probe", where);
        else missing = "no blur: " + lens.message() + " (--f-number and --focus-distance or --focus-at, or --blurfield)";
    }
    auto z = find_depth_channel(img, f.source.depth_channel);
    if (!z || *z < 0) runtime_error("--probe: " + where + " has no depth channel (give --depth FILE or --depth-channel)");
    auto p = probe_plate(img, *z, f.source.depth_decode, f.defocus.cleanup, camera ? &*camera : nullptr,
                         field ? &*field : nullptr, x, y, f.session->exec);
    if (!p) runtime_error("--probe: " + where + ": " + message_naming_flag(p.status()));
    std::ostringstream o;
    o << "pixel " << x << "," << y << ": depth " << p->depth;
    if (camera) o << ", world (" << p->position.x << ", " << p->position.y << ", " << p->position.z << ")";
    if (field) o << ", blur " << p->blur_px << " px";
    if (p->mixed) {  // what the defocus blurs apart there
        o << ", a split silhouette pixel: " << p->fg_share << " foreground at depth " << p->fg_depth;
        if (field) o << " (blur " << p->fg_blur_px << " px)";
        o << ", the rest at depth " << p->bg_depth;
        if (field) o << " (blur " << p->bg_blur_px << " px)";
    }
    if (!missing.empty()) o << " (" << missing << ")";
    o << "\n";
    std::cout << o.str();
    std::cout.flush();
}

DepthCleanupOptions cleanup(const Step& s) {
    DepthCleanupOptions c;
    c.remove_speckles = c.mixed_pixels = c.smooth_noise = false;
    const std::string& v = s.args[0];
    if (v == "all") return {};
    if (v == "none") return c;
    std::size_t pos = 0;
    while (pos <= v.size()) {
        const std::size_t comma = std::min(v.find(',', pos), v.size());
        const std::string item = v.substr(pos, comma - pos);
        pos = comma + 1;
        if (item == "speckles") c.remove_speckles = true;
        else if (item == "mixed") c.mixed_pixels = true;
        else if (item == "noise") c.smooth_noise = true;
        else usage_error(s.flag + ": unknown step '" + item + "' (expected all, none, or a list of speckles, noise, mixed)");
    }
    return c;
}

}  // namespace

std::vector<Command> plate_commands() {
    std::vector<Command> t;
    t.push_back({.names = {"--depth"}, .args = "FILE", .kind = Kind::Action, .group = P,
                 .help = "attach FILE's depth (its --depth-channel or Z, else its first channel) to the top image as "
                         "its depth channel; the sizes must match",
                 .file_args = {0}, .stack = StackUse::NeedsImage,
                 .run = [](Frame& f, const Step& s) { do_depth(f, s.args[0]); }});
    t.push_back({.names = {"--part"}, .args = "NAME|INDEX[,...]", .kind = Kind::Action, .group = P,
                 .help = "keep only these parts of the top image (names or indices, in this order)",
                 .stack = StackUse::NeedsImage, .run = do_part});
    t.push_back({.names = {"--view"}, .args = "NAME", .kind = Kind::Action, .group = P,
                 .help = "keep only this view of a stereo / multi-view top image (--diffuse does every view "
                         "otherwise)",
                 .stack = StackUse::NeedsImage, .run = do_view});
    t.push_back({.names = {"--depth-cleanup"}, .args = "all|none|LIST", .kind = Kind::Modifier, .group = P,
                 .help = "what --diffuse repairs in a plate's depth besides filling holes: all (default), none, or "
                         "a list of speckles, noise, mixed (noise: a sensor's noisy depth, measured above 0.1%, is "
                         "smoothed within each surface; mixed: silhouette pixels between two surfaces take the nearer "
                         "one's depth, and filled holes at a silhouette are decided by their colour)",
                 .run = [](Frame& f, const Step& s) {
                     const DepthCleanupOptions c = cleanup(s);
                     f.defocus.cleanup.remove_speckles = c.remove_speckles;
                     f.defocus.cleanup.mixed_pixels = c.mixed_pixels;
                     f.defocus.cleanup.smooth_noise = c.smooth_noise;
                 },
                 .check = [](const Step& s) { cleanup(s); }});
    t.push_back({.names = {"--focus-at"}, .args = "X,Y", .kind = Kind::Modifier, .group = P,
                 .help = "focus at the depth of pixel X,Y (median of 5x5 valid depths; none valid: the depth the "
                         "hole fill gives there): the thin lens's focus distance, and a --blurfield refocused there",
                 .run = [](Frame& f, const Step& s) { f.focus_at = pixel(s); },
                 .check = [](const Step& s) { pixel(s); }});
    t.push_back({.names = {"--probe"}, .args = "X,Y", .kind = Kind::Action, .group = P,
                 .help = "print depth, world position and blur radius at pixel X,Y of the top image (the depth "
                         "needs no lens: without a focal length only the depth, without an f-number and focus "
                         "distance no blur)",
                 .stack = StackUse::NeedsImage, .is_work = true, .prints_result = true, .run = do_probe,
                 .check = [](const Step& s) { pixel(s); }});
    return t;
}

}  // namespace gdof::cli
