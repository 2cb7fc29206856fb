// --blurfield FILE and --eval-blur: evaluate the blur field at each pixel's
// world position (P channels, or depth + camera) and add a float channel
// "blur" (circle-of-confusion radius in output pixels) to the top image.
#include <filesystem>

#include "blur_state.h"
#include "camera_field.h"
#include "cli.h"
#include "gdof/blur_map.h"
#include "gdof/io/blur_field_io.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

// Runs with the session's Exec (progress, SIGINT / SIGTERM) and reports a failure.
void run_with_progress(Frame& f, const std::string& where, const std::function<Status(const Exec&)>& work) {
    Session& s = *f.session;
    Status st = work(s.exec);
    check_interrupted();
    if (!st) runtime_error("--eval-blur: " + where + ": " + message_naming_flag(st));
}

std::string depth_channel_name(const Frame& f) {
    return f.source.depth_channel.empty() ? std::string("Z") : f.source.depth_channel;
}

// Deep part: a float sample channel "blur" from each sample's pixel centre and
// depth. Returns false (reason in skipped) if the part has no depth channel.
bool eval_blur_deep(Frame& f, DeepImage& deep, const std::string& where, std::vector<std::string>& skipped) {
    int zc = deep.z_channel();
    if (!f.source.depth_channel.empty()) {
        zc = deep.channel_index(f.source.depth_channel);
        if (zc < 0) runtime_error("--depth-channel: channel '" + f.source.depth_channel + "' not found in " + where);
    }
    if (zc < 0 || deep.channel(zc).type == PixelType::UInt) {
        skipped.push_back(where + " is deep and has no depth channel '" + depth_channel_name(f) + "'");
        return false;
    }
    const Camera camera = part_camera(f, deep.metadata, deep.display_window(), "--eval-blur", where);
    const BlurField field = field_for(f, camera, "--eval-blur", where);
    int bc = deep.channel_index("blur");
    if (bc >= 0 && deep.channel(bc).type == PixelType::UInt)
        runtime_error("--eval-blur: " + where + " has a uint channel 'blur'; cannot write the blur there");
    if (bc < 0) bc = deep.add_channel({"blur", PixelType::Float});
    else check(deep.set_channel_type(bc, PixelType::Float), "--eval-blur: " + where);
    run_with_progress(f, where, [&](const Exec& exec) {
        return evaluate_blur_deep(field, camera, deep, zc, std::span<float>(deep.samples(bc), deep.total_samples()), exec);
    });
    return true;
}

// Flat part: as above from its positions or depth. Returns false (reason in
// skipped) if it has neither; channels a flag names must exist.
bool eval_blur_flat(Frame& f, Image& img, const std::string& where, std::vector<std::string>& skipped) {
    const PositionSource& source = f.source;
    auto pos = find_position_channels(img, source.position_channels);
    if (!pos) runtime_error("--position-channels: " + pos.message() + " in " + where);
    // A --depth-channel the image lacks is an error even when positions are used.
    auto z = find_depth_channel(img, source.depth_channel);
    if (!z) runtime_error("--depth-channel: " + z.message() + " in " + where);
    if (!*pos) {
        if (*z < 0) {
            skipped.push_back(where + " has no position channels (P.x/P.y/P.z, P.X/Y/Z, P.R/G/B, P.red/green/blue, "
                              "Pworld.*) and no depth channel '" + depth_channel_name(f) + "'");
            return false;
        }
    }
    if (f.focus_at && *z < 0) runtime_error("--focus-at: " + where + " has no depth channel '" + depth_channel_name(f) + "'");
    const Camera camera = f.focus_at ? focus_camera(f, img.metadata, img.display_window(), img, *z, where)
                                     : part_camera(f, img.metadata, img.display_window(), "--eval-blur", where);
    const BlurField field = field_for(f, camera, "--eval-blur", where);
    // Output channel: replaces an existing float "blur".
    int bc = img.channel_index("blur");
    if (bc >= 0 && img.channel(bc).type == PixelType::UInt) {
        img.remove_channel(bc);
        bc = -1;
    }
    if (bc < 0) bc = img.add_channel({"blur", PixelType::Float});
    else check(img.set_channel_type(bc, PixelType::Float), "--eval-blur: " + where);
    run_with_progress(f, where, [&](const Exec& exec) {
        return evaluate_blur_map(field, camera, img, source, img.channel_view(bc), exec);
    });
    return true;
}

void do_blurfield(Frame& f, const std::string& path) {
    Session& s = *f.session;
    if (auto it = s.blur_cache.find(path); it != s.blur_cache.end()) {
        f.blur = it->second;
        return;
    }
    StageTimer t(s.stats, "blurfield");
    const std::string text = read_flag_file("--blurfield", "file", path);
    std::error_code ec;
    const std::string dir = std::filesystem::absolute(std::filesystem::path(path), ec).parent_path().string();
    auto r = io::parse_blur_field(text, dir);  // image_map masks read from disk, as data
    if (!r) runtime_error("--blurfield '" + path + "': " + r.message());
    auto st = std::make_shared<BlurState>();
    st->path = path;
    st->field = std::move(r).value();
    f.blur = st;
    s.blur_cache[path] = st;
    if (s.global.verbose) s.progress.message("gdof: blur field " + path + ": " + st->field.describe());
}

void do_eval_blur(Frame& f) {
    Session& s = *f.session;
    StackEntry& top = f.top("--eval-blur");
    const std::string where = image_name(top);
    StageTimer timer(s.stats, "eval-blur");

    int evaluated = 0;
    std::vector<std::string> skipped;
    s.progress.begin("eval-blur");
    for (std::size_t part = 0; part < top.images.size(); ++part) {
        const bool several = top.images.size() > 1;
        s.progress.part(int(part), int(top.images.size()));
        if (top.images.is_deep(part)) {
            const std::string pwhere = several ? where + " part " + std::to_string(part) : where;
            if (eval_blur_deep(f, top.images.deep(part), pwhere, skipped)) ++evaluated;
            continue;
        }
        Image& img = top.images.flat(part);
        const std::string pwhere =
            several ? where + " part " + std::to_string(part) + (img.name.empty() ? "" : " '" + img.name + "'") : where;
        if (eval_blur_flat(f, img, pwhere, skipped)) ++evaluated;
    }
    if (evaluated == 0) {
        std::string why = skipped.empty() ? std::string("no image parts") : skipped.front();
        for (std::size_t i = 1; i < skipped.size() && i < 4; ++i) why += "; " + skipped[i];
        runtime_error("--eval-blur: " + why);
    }
}

}  // namespace

std::vector<Command> blur_commands() {
    const std::string B = "Blur field";
    std::vector<Command> t;
    t.push_back({.names = {"--blurfield"}, .args = "FILE", .kind = Kind::Action, .group = B,
                 .help = "load a blur-field JSON (thin_lens, focal_planes, region, ...)", .file_args = {0},
                 .is_work = true, .run = [](Frame& f, const Step& s) { do_blurfield(f, s.args[0]); },
                 // A --render waits for it: the render uses the field.
                 .lets_wait = [](const Frame&, const Step&) -> unsigned { return kRenderWaits; }});
    t.push_back({.names = {"--eval-blur"}, .kind = Kind::Action, .group = B,
                 .help = "add a float channel 'blur' (CoC radius in output pixels) from P, or Z + camera",
                 .stack = StackUse::NeedsImage, .progress_stage = true,
                 .run = [](Frame& f, const Step&) { do_eval_blur(f); }});
    return t;
}

}  // namespace gdof::cli
