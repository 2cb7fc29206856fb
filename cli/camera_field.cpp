// The camera and the blur field of an image part (camera_field.h).
#include "camera_field.h"

#include "blur_state.h"
#include "errors.h"

namespace gdof::cli {

std::string image_name(const StackEntry& e) { return e.source.empty() ? std::string("the top image") : "'" + e.source + "'"; }

Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where) {
    auto cam = resolve_camera(md, display, f.lens);
    if (!cam) runtime_error(flag + ": " + where + ": " + message_naming_flag(cam.status()));
    return std::move(cam).value();
}

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

}  // namespace gdof::cli
