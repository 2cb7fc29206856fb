// gdof.BlurField: B(x), the CoC radius in output pixels at world points
// (gdof/blur_field.h), from JSON text, a dict or a file (image_map masks
// read from disk by gdof::io, relative to base_dir or the file's folder).
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>

#include "gdof/blur_field.h"
#include "gdof/io/blur_field_io.h"
#include "gdof_python.h"

namespace gdof::python {

std::string json_text(const nb::handle& h) {
    if (nb::isinstance<nb::str>(h)) return nb::cast<std::string>(h);
    return nb::cast<std::string>(nb::module_::import_("json").attr("dumps")(h));
}

void register_blur_field(nb::module_& m) {
    nb::class_<BlurField>(m, "BlurField",
                          "The blur field B(x) (docs/blur_field.md): BlurField.parse(dict or JSON text), "
                          "BlurField.read(path), BlurField.from_thin_lens(lens)")
        .def(nb::init<>(), "a field that is 0 everywhere")
        .def_static("parse",
                    [](const nb::handle& spec, const std::string& base_dir) {
                        return take(io::parse_blur_field(json_text(spec), base_dir));
                    },
                    nb::arg("spec"), nb::arg("base_dir") = "",
                    "from a dict ({'blurfield': {...}}) or JSON text; image_map paths relative to base_dir")
        .def_static("read", [](const std::string& path) { return take(io::read_blur_field(path)); }, nb::arg("path"),
                    "from a JSON file")
        .def_static("from_thin_lens", [](const ThinLens& lens) { return take(BlurField::from_thin_lens(lens)); },
                    nb::arg("lens"))
        .def("evaluate",
             [](const BlurField& f, const Camera& camera, const nb::handle& points) {
                 nb::object a = nb::module_::import_("numpy").attr("ascontiguousarray")(points, "float64").attr("reshape")(-1, 3);
                 auto p = nb::cast<nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>(a);
                 const std::size_t n = p.shape(0);
                 std::vector<Vec3> world(n);
                 for (std::size_t i = 0; i < n; ++i) world[i] = {p(i, 0), p(i, 1), p(i, 2)};
                 nb::object out = nb::module_::import_("numpy").attr("empty")(n, "float32");
                 auto o = nb::cast<nb::ndarray<float, nb::ndim<1>, nb::c_contig, nb::device::cpu>>(out);
                 check(f.evaluate(camera, std::span<const Vec3>(world), std::span<float>(o.data(), n)));
                 return out;
             },
             nb::arg("camera"), nb::arg("points"), "B at (N, 3) world points: (N,) float32 radii in output pixels")
        .def("evaluate_pixel", &BlurField::evaluate_pixel, nb::arg("camera"), nb::arg("x"), nb::arg("y"), nb::arg("depth"),
             "B at continuous pixel (x, y) (centres at +0.5) and depth")
        .def("refocused", [](const BlurField& f, double d) { return take(f.refocused(d)); }, nb::arg("focus_distance"))
        .def_prop_ro("max_radius", &BlurField::max_radius)
        .def_prop_ro("depth_only", &BlurField::depth_only)
        .def("describe", &BlurField::describe)
        .def("__repr__", [](const BlurField& f) { return "gdof.BlurField(" + f.describe() + ")"; });
}

}  // namespace gdof::python
