// The camera and the blur field of an image part (camera_field.h).
#include "camera_field.h"

#include <cmath>
#include <iostream>
#include <string>

#include "blur_state.h"
#include "errors.h"
#include "gdof/blur_map.h"
#include "gdof/plate.h"
#include "values.h"

namespace gdof::cli {

std::string image_name(const StackEntry& e) { return e.source.empty() ? std::string("the top image") : "'" + e.source + "'"; }

Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where) {
    auto cam = resolve_camera(md, display, f.lens);
    if (!cam) runtime_error(flag + ": " + where + ": " + message_naming_flag(cam.status()));
    return std::move(cam).value();
}

namespace {

// A focused camera, or the error naming --focus-at; the note when the focus
// came from a hole's fill (a guess, not a measurement).
Camera focused_or_fail(const Frame& f, Result<FocusedCamera> r, const std::string& where) {
    if (!r) runtime_error("--focus-at: " + where + ": " + message_naming_flag(r.status()));
    if (r->focus.filled) {
        const auto [x, y] = *f.focus_at;
        std::string note = "gdof: --focus-at " + std::to_string(x) + "," + std::to_string(y) + ": " + where +
                           ": no measured depth within 2 px; focusing at the depth the hole fill gives there (" +
                           format_double("%g", r->focus.distance) + ")\n";
        if (f.focus_notes.insert(note).second) std::cerr << note;
    }
    return std::move(r->camera);
}

}  // namespace

Camera image_camera(const Frame& f, const ImageSet& set, std::size_t part, const std::string& flag,
                    const std::string& where) {
    if (!f.focus_at) {
        const Roi display = set.is_deep(part) ? set.deep(part).display_window() : set.flat(part).display_window();
        return part_camera(f, set.metadata(part), display, flag, where);
    }
    const auto [x, y] = *f.focus_at;
    return focused_or_fail(f, focus_camera_at(set, part, f.lens, f.source, f.defocus.cleanup, x, y, f.session->exec),
                           where);
}

Camera focus_camera(const Frame& f, const Metadata& md, const Roi& display, const Image& plate, int zc,
                    const std::string& where) {
    const auto [x, y] = *f.focus_at;
    return focused_or_fail(f,
                           focus_camera_at(md, display, f.lens, plate, zc, f.source.depth_decode, f.defocus.cleanup,
                                           x, y, f.session->exec),
                           where);
}

BlurField field_for(const Frame& f, const Camera& camera, const std::string& flag, const std::string& where) {
    if (f.blur && f.focus_at) {
        auto r = f.blur->field.refocused(camera.lens().focus_distance);
        if (!r) runtime_error(flag + ": --focus-at: " + message_naming_flag(r.status()));
        return std::move(r).value();
    }
    if (f.blur) return f.blur->field;
    auto lens = camera.thin_lens();
    if (!lens)
        runtime_error(flag + ": no --blurfield given and " + where + " has no complete lens for a thin lens: " +
                      lens.message() + " (or give --focal-length-mm, --f-number, --focus-distance, --sensor-width-mm)");
    auto tl = BlurField::from_thin_lens(lens.value());
    if (!tl) runtime_error(flag + ": " + tl.message());
    return std::move(tl).value();
}

}  // namespace gdof::cli
