// Cameras and lenses (gdof/camera.h): gdof.ThinLens, gdof.LensInfo,
// gdof.Camera and resolve_camera, the camera of an image with the lens
// overrides named as the CLI's flags (focal_length_mm, f_number, ...).
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "gdof/camera.h"
#include "gdof/io/stack_sources.h"
#include "gdof/text_file.h"
#include "gdof_python.h"

namespace gdof::python {

namespace {

nb::object matrix(const Mat44& m) {
    nb::list rows;
    for (int r = 0; r < 4; ++r) {
        nb::list row;
        for (int c = 0; c < 4; ++c) row.append(m.m[std::size_t(r)][std::size_t(c)]);
        rows.append(row);
    }
    return nb::module_::import_("numpy").attr("array")(rows);
}

nb::object vec(const Vec3& v) { return nb::make_tuple(v.x, v.y, v.z); }

// (N, 3) points -> contiguous float64 array.
nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu> points_of(const nb::handle& points) {
    nb::object a = nb::module_::import_("numpy").attr("ascontiguousarray")(points, "float64").attr("reshape")(-1, 3);
    return nb::cast<nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>(a);
}

}  // namespace

void register_camera(nb::module_& m) {
    nb::class_<ThinLens>(m, "ThinLens", "A thin lens: CoC radii in output pixels")
        .def("__init__",
             [](ThinLens* t, double focal_length_mm, double f_number, double focus_distance, double sensor_width_mm,
                double image_width_px, double scene_unit_mm) {
                 new (t) ThinLens{focal_length_mm, f_number, focus_distance, sensor_width_mm, image_width_px, scene_unit_mm};
             },
             nb::arg("focal_length_mm") = 50.0, nb::arg("f_number") = 2.8, nb::arg("focus_distance") = 2.0,
             nb::arg("sensor_width_mm") = 36.0, nb::arg("image_width_px") = 1920.0, nb::arg("scene_unit_mm") = 1000.0)
        .def_rw("focal_length_mm", &ThinLens::focal_length_mm)
        .def_rw("f_number", &ThinLens::f_number)
        .def_rw("focus_distance", &ThinLens::focus_distance)
        .def_rw("sensor_width_mm", &ThinLens::sensor_width_mm)
        .def_rw("image_width_px", &ThinLens::image_width_px)
        .def_rw("scene_unit_mm", &ThinLens::scene_unit_mm)
        .def("validate", [](const ThinLens& t) { check(t.validate()); })
        .def("coc_radius_px", &ThinLens::coc_radius_px, nb::arg("depth"))
        .def("hyperfocal_distance", &ThinLens::hyperfocal_distance, nb::arg("coc_radius_px"))
        .def("dof_limits", [](const ThinLens& t, double coc) {
            auto l = t.dof_limits(coc);
            return nb::make_tuple(l.near, l.far);
        }, nb::arg("coc_radius_px"), "(near, far) where the CoC radius is coc_radius_px");

    nb::class_<LensInfo>(m, "LensInfo", "The lens data a camera carries (NaN = unknown)")
        .def(nb::init<>())
        .def_rw("focal_length_mm", &LensInfo::focal_length_mm)
        .def_rw("sensor_width_mm", &LensInfo::sensor_width_mm)
        .def_rw("f_number", &LensInfo::f_number)
        .def_rw("focus_distance", &LensInfo::focus_distance)
        .def_rw("scene_unit_mm", &LensInfo::scene_unit_mm)
        .def_prop_ro("complete", &LensInfo::complete);

    nb::class_<Camera>(m, "Camera", "Projection, view and lens of an image (docs/camera.md)")
        .def_static("from_metadata",
                    [](const Metadata& md, const nb::handle& display_window) {
                        return take(Camera::from_metadata(md, to_roi(display_window)));
                    },
                    nb::arg("metadata"), nb::arg("display_window"), "from EXR attributes (worldToCamera, worldToNDC, lens)")
        .def_static("look_at",
                    [](const nb::handle& position, const nb::handle& look_at, const nb::handle& up,
                       double focal_length_mm, double sensor_width_mm, const nb::handle& display_window,
                       double f_number, double focus_distance, double scene_unit_mm) {
                        auto v = [](const nb::handle& h) {
                            auto t = nb::cast<std::vector<double>>(h);
                            if (t.size() != 3) raise(Status::error("a point is (x, y, z)", StatusCode::InvalidArgument));
                            return Vec3{t[0], t[1], t[2]};
                        };
                        CameraDesc d;
                        d.position = v(position);
                        d.look_at = v(look_at);
                        d.up = v(up);
                        d.focal_length_mm = focal_length_mm;
                        d.sensor_width_mm = sensor_width_mm;
                        d.display_window = to_roi(display_window);
                        d.f_number = f_number;
                        d.focus_distance = focus_distance;
                        d.scene_unit_mm = scene_unit_mm;
                        return take(Camera::create(d));
                    },
                    nb::arg("position"), nb::arg("look_at"), nb::arg("up") = nb::make_tuple(0, 1, 0),
                    nb::arg("focal_length_mm") = 50.0, nb::arg("sensor_width_mm") = 36.0,
                    nb::arg("display_window") = nb::make_tuple(0, 0, 1920, 1080),
                    nb::arg("f_number") = std::numeric_limits<double>::quiet_NaN(),
                    nb::arg("focus_distance") = std::numeric_limits<double>::quiet_NaN(),
                    nb::arg("scene_unit_mm") = 1000.0,
                    "a perspective camera (right-handed world, as the scene JSON's camera)")
        .def("to_metadata", &Camera::to_metadata, nb::arg("metadata"), "writes worldToCamera, worldToNDC and the lens")
        .def("project",
             [](const Camera& c, const nb::handle& points) {
                 auto p = points_of(points);
                 const std::size_t n = p.shape(0);
                 nb::object out = nb::module_::import_("numpy").attr("empty")(nb::make_tuple(n, 3), "float64");
                 auto o = nb::cast<nb::ndarray<double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>(out);
                 for (std::size_t i = 0; i < n; ++i) {
                     const PixelDepth pd = c.project({p(i, 0), p(i, 1), p(i, 2)});
                     o(i, 0) = pd.x, o(i, 1) = pd.y, o(i, 2) = pd.depth;
                 }
                 return out;
             },
             nb::arg("points"), "(N, 3) world points -> (N, 3) pixel x, y (centres at +0.5) and depth")
        .def("unproject", [](const Camera& c, double x, double y, double depth) { return vec(c.unproject(x, y, depth)); },
             nb::arg("x"), nb::arg("y"), nb::arg("depth"))
        .def_prop_ro("world_to_camera", [](const Camera& c) { return matrix(c.world_to_camera()); })
        .def_prop_ro("world_to_ndc", [](const Camera& c) { return matrix(c.world_to_ndc()); })
        .def_prop_ro("display_window", &Camera::display_window)
        .def_prop_ro("position", [](const Camera& c) { return vec(c.position()); })
        .def_prop_ro("forward", [](const Camera& c) { return vec(c.forward()); })
        .def_prop_ro("focal_length_px", &Camera::focal_length_px)
        .def_prop_ro("hfov_deg", &Camera::hfov_deg)
        .def_prop_rw("lens", &Camera::lens, &Camera::set_lens)
        .def("thin_lens", [](const Camera& c) { return take(c.thin_lens()); },
             "the thin lens of the camera's lens data (an error naming what is missing)");

    m.def("resolve_camera",
          [](const Metadata& md, const nb::handle& display_window, std::optional<double> focal_length_mm,
             std::optional<double> sensor_width_mm, std::optional<double> f_number, std::optional<double> focus_distance,
             std::optional<double> scene_unit_mm) {
              LensOverrides o{focal_length_mm, sensor_width_mm, f_number, focus_distance, scene_unit_mm};
              return take(resolve_camera(md, to_roi(display_window), o));
          },
          nb::arg("metadata"), nb::arg("display_window"), nb::kw_only(), nb::arg("focal_length_mm") = nb::none(),
          nb::arg("sensor_width_mm") = nb::none(), nb::arg("f_number") = nb::none(),
          nb::arg("focus_distance") = nb::none(), nb::arg("scene_unit_mm") = nb::none(),
          "The camera of an image's metadata with lens overrides (the CLI's --focal-length-mm ...); without "
          "camera attributes, a camera at the origin looking down +z when a focal length is given.");

    m.def("lens_at_frame",
          [](const std::string& path, double frame) {
              const std::string source = "lens table '" + path + "'";
              const std::string text = take(read_text(path));
              const auto rows = take(io::read_lens_table(text, source, io::LensTableKey::Frame));
              const LensOverrides l = take(io::lens_at_frame(rows, frame, source));
              nb::dict d;
              if (l.focal_length_mm) d["focal_length_mm"] = *l.focal_length_mm;
              if (l.sensor_width_mm) d["sensor_width_mm"] = *l.sensor_width_mm;
              if (l.f_number) d["f_number"] = *l.f_number;
              if (l.focus_distance) d["focus_distance"] = *l.focus_distance;
              return d;
          },
          nb::arg("path"), nb::arg("frame"),
          "--lens-table FILE for one frame: the lens keywords (focus_distance, f_number, focal_length_mm, "
          "sensor_width_mm) the table gives that frame, as a dict for defocus(..., **lens): the frame's row, else "
          "interpolated between rows (focus in 1/distance), else the nearest end's.");
}

}  // namespace gdof::python
