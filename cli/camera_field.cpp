// The camera and the blur field of an image part (camera_field.h).
#include "camera_field.h"

#include <cmath>
#include <iostream>

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

Camera image_camera(const Frame& f, const ImageSet& set, std::size_t part, const std::string& flag,
                    const std::string& where) {
    const Roi display = set.is_deep(part) ? set.deep(part).display_window() : set.flat(part).display_window();
    Camera cam = part_camera(f, set.metadata(part), display, flag, where);
    if (!f.focus_at) return cam;
    // The part with the depth: this one, else the first flat one that has it.
    const Image* plate = nullptr;
    int zc = -1;
    for (std::size_t k = 0; k <= set.size() && !plate; ++k) {
        const std::size_t i = k == 0 ? part : k - 1;
        if (i >= set.size() || set.is_deep(i)) continue;
        auto z = find_depth_channel(set.flat(i), f.source.depth_channel);
        if (z && *z >= 0) plate = &set.flat(i), zc = *z;
    }
    if (!plate)
        runtime_error("--focus-at: " + where + " has no flat part with a depth channel '" +
                      (f.source.depth_channel.empty() ? std::string("Z") : f.source.depth_channel) + "'");
    return focus_camera(f, set.metadata(part), display, *plate, zc, cam, where);
}

Camera focus_camera(const Frame& f, const Metadata& md, const Roi& display, const Image& plate, int zc,
                    const Camera& camera, const std::string& where) {
    const auto [x, y] = *f.focus_at;
    auto picked = focus_distance_at(plate, zc, f.source.depth_decode, camera, x, y, f.defocus.cleanup, f.session->exec);
    if (!picked) runtime_error("--focus-at: " + where + ": " + message_naming_flag(picked.status()));
    const double* d = &picked->distance;
    // A guess, not a measurement: said.
    if (picked->filled)
        std::cerr << "gdof: --focus-at " << x << "," << y << ": " << where
                  << ": no measured depth within 2 px; focusing at the depth the hole fill gives there ("
                  << format_double("%g", *d) << ")\n";
    LensOverrides lens = f.lens;
    lens.focus_distance = *d;
    auto focused = resolve_camera(md, display, lens);
    if (!focused) runtime_error("--focus-at: " + where + ": " + message_naming_flag(focused.status()));
    // A depth inside the focal length is no scene a lens can focus on: most
    // often an integer depth file read as 0..1 (as OFX hosts deliver clips
    // too) and decoded as metres. Say so here, not as a bad focus distance.
    const LensInfo& li = focused->lens();
    const double focal = li.focal_length_mm / li.scene_unit_mm;
    if (std::isfinite(focal) && *d <= focal)
        runtime_error("--focus-at " + std::to_string(x) + "," + std::to_string(y) + ": " + where +
                      ": the depth there decodes to " + format_double("%g", *d) +
                      " scene units, within the focal length (" + format_double("%g", focal) +
                      "): check --depth-encoding and --depth-scale (8- and 16-bit files are read as 0..1, so "
                      "millimetres in a 16-bit file are --depth-encoding scaled --depth-scale 65.535)");
    return std::move(focused).value();
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
