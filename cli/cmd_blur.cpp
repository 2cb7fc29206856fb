// --blurfield FILE and --eval-blur: evaluate the blur field at each pixel's
// world position (P channels, or depth + camera) and add a float channel
// "blur" (circle-of-confusion radius in output pixels) to the top image.
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "cli.h"
#include "gdof/blur_field.h"
#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/io/image_io.h"

namespace gdof::cli {

struct BlurState {
    std::string path;
    BlurField field;
};

std::string image_name(const StackEntry& e) { return e.source.empty() ? std::string("the top image") : "'" + e.source + "'"; }

LensOverrides lens_overrides(const Frame& f) {
    LensOverrides ov;
    auto get = [&](const char* k) -> std::optional<double> {
        auto it = f.camera_overrides.find(k);
        if (it == f.camera_overrides.end()) return std::nullopt;
        return it->second;
    };
    ov.focal_length_mm = get("focal_length_mm");
    ov.sensor_width_mm = get("sensor_width_mm");
    ov.f_number = get("f_number");
    ov.focus_distance = get("focus_distance");
    ov.scene_unit_mm = get("scene_unit_mm");
    return ov;
}

Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where) {
    auto cam = resolve_camera(md, display, lens_overrides(f));
    if (!cam) runtime_error(flag + ": " + where + ": " + message_naming_flag(cam.status()));
    return std::move(cam).value();
}

// The field: --blurfield, else a thin lens from the camera's lens data.
BlurField field_for(const Frame& f, const Camera& camera, const std::string& flag, const std::string& where) {
    if (f.blur) return f.blur->field;
    auto lens = camera.thin_lens();
    if (!lens)
        runtime_error(flag + ": no --blurfield given and " + where + " has no complete lens for a thin lens: " +
                      lens.message() + " (or give --focal-length-mm, --f-number, --focus-distance, --sensor-width-mm)");
    auto tl = BlurField::from_thin_lens(lens.value());
    if (!tl) runtime_error(flag + ": " + tl.message());
    return std::move(tl).value();
}

namespace {

// Reports the library's row progress on the CLI's bar, and stops on Ctrl-C.
void run_with_progress(Frame& f, const std::string& where, const std::function<Status(const Exec&)>& work) {
    Session& s = *f.session;
    s.progress.begin("eval-blur");
    Status st = work(s.exec);
    s.progress.end();
    check_interrupted();
    check(st, "--eval-blur: " + where);
}

// Deep part: a float sample channel "blur" from each sample's pixel centre and
// depth. Returns false (reason in skipped) if the part has no depth channel.
bool eval_blur_deep(Frame& f, DeepImage& deep, const std::string& where, std::vector<std::string>& skipped) {
    int zc = deep.z_channel();
    if (!f.depth_channel.empty()) {
        zc = deep.channel_index(f.depth_channel);
        if (zc < 0) runtime_error("--depth-channel: channel '" + f.depth_channel + "' not found in " + where);
    }
    if (zc < 0 || deep.channel(zc).type == PixelType::UInt) {
        skipped.push_back(where + " is deep and has no depth channel '" +
                          (f.depth_channel.empty() ? std::string("Z") : f.depth_channel) + "'");
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

}  // namespace

void do_blurfield(Frame& f, const std::string& path) {
    Session& s = *f.session;
    if (auto it = s.blur_cache.find(path); it != s.blur_cache.end()) {
        f.blur = it->second;
        return;
    }
    StageTimer t(s.stats, "blurfield");
    const std::string text = read_text("--blurfield", "file", path);
    std::error_code ec;
    BlurField::Context ctx;
    ctx.base_dir = std::filesystem::absolute(std::filesystem::path(path), ec).parent_path().string();
    // Painted masks are data: read without colour conversion.
    ctx.load_image = [](const std::string& p) -> Result<std::shared_ptr<const Image>> {
        io::ReadOptions ro;
        ro.linearize = false;
        auto r = io::read_flat(p, ro);
        if (!r) return r.status();
        return std::shared_ptr<const Image>(std::make_shared<Image>(std::move(r).value()));
    };
    auto r = BlurField::parse(text, ctx);
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
    for (std::size_t part = 0; part < top.images.size(); ++part) {
        if (top.images.is_deep(part)) {
            const std::string pwhere = top.images.size() > 1 ? where + " part " + std::to_string(part) : where;
            if (eval_blur_deep(f, top.images.deep(part), pwhere, skipped)) ++evaluated;
            continue;
        }
        Image& img = top.images.flat(part);
        const std::string pwhere =
            top.images.size() > 1 ? where + " part " + std::to_string(part) + (img.name.empty() ? "" : " '" + img.name + "'") : where;
        PositionSource source{f.position_channels, f.depth_channel, f.depth_decode};
        // Flag-named channels that are missing are errors; an image with
        // neither P nor Z is skipped (other parts may have them).
        auto pos = find_position_channels(img, source.position_channels);
        if (!pos) runtime_error("--position-channels: " + pos.message() + " in " + pwhere);
        if (!*pos) {
            auto z = find_depth_channel(img, source.depth_channel);
            if (!z) runtime_error("--depth-channel: " + z.message() + " in " + pwhere);
            if (*z < 0) {
                skipped.push_back(pwhere + " has no position channels (P.x/P.y/P.z, P.X/Y/Z, P.R/G/B, P.red/green/blue, "
                                  "Pworld.*) and no depth channel '" +
                                  (f.depth_channel.empty() ? std::string("Z") : f.depth_channel) + "'");
                continue;
            }
        }
        const Camera camera = part_camera(f, img.metadata, img.display_window(), "--eval-blur", pwhere);
        const BlurField field = field_for(f, camera, "--eval-blur", pwhere);
        // Output channel: replaces an existing float "blur".
        int bc = img.channel_index("blur");
        if (bc >= 0 && img.channel(bc).type == PixelType::UInt) {
            img.remove_channel(bc);
            bc = -1;
        }
        if (bc < 0) bc = img.add_channel({"blur", PixelType::Float});
        else check(img.set_channel_type(bc, PixelType::Float), "--eval-blur: " + pwhere);
        run_with_progress(f, pwhere, [&](const Exec& exec) {
            return evaluate_blur_map(field, camera, img, source, img.channel_view(bc), exec);
        });
        ++evaluated;
    }
    if (evaluated == 0) {
        std::string why = skipped.empty() ? std::string("no image parts") : skipped.front();
        for (std::size_t i = 1; i < skipped.size() && i < 4; ++i) why += "; " + skipped[i];
        runtime_error("--eval-blur: " + why);
    }
}

}  // namespace gdof::cli
