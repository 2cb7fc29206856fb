// An image's camera from its attributes plus user overrides.
#include "gdof/camera.h"

namespace gdof {

Result<Camera> resolve_camera(const Metadata& metadata, const Roi& display_window, const LensOverrides& ov) {
    Metadata md = metadata;
    if (ov.focal_length_mm) md.set_float("focalLength", *ov.focal_length_mm);
    if (ov.sensor_width_mm) md.set_float("sensorWidth", *ov.sensor_width_mm);
    if (ov.f_number) {
        md.set_float("fNumber", *ov.f_number);
        md.erase("aperture");
    }
    if (ov.focus_distance) {
        md.set_float("focusDistance", *ov.focus_distance);
        md.erase("focus");
    }
    CameraReadOptions opts;
    if (ov.scene_unit_mm) opts.scene_unit_mm = *ov.scene_unit_mm;
    if (md.has("worldToCamera") || md.has("worldToNDC")) return Camera::from_metadata(md, display_window, opts);
    if (!ov.focal_length_mm)
        return Status::error("no camera: no worldToCamera / worldToNDC attributes (give a focal length for a "
                             "camera at the origin looking down +z)",
                             StatusCode::NotFound, "focal_length_mm");
    CameraDesc d;
    d.handedness = Handedness::Left;  // world = camera space: +x right, +y up, +z forward
    d.focal_length_mm = *ov.focal_length_mm;
    if (ov.sensor_width_mm) d.sensor_width_mm = *ov.sensor_width_mm;
    if (ov.f_number) d.f_number = *ov.f_number;
    if (ov.focus_distance) d.focus_distance = *ov.focus_distance;
    if (ov.scene_unit_mm) d.scene_unit_mm = *ov.scene_unit_mm;
    d.display_window = display_window;
    return Camera::create(d);
}

}  // namespace gdof
