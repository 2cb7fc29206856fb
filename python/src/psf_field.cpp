// gdof.PsfField and gdof.VibrateOptions: method 4's displacement field
// (gdof/psf_field.h) from a dict, JSON text or a file (blend weights'
// image_map masks read from disk by gdof::io, relative to base_dir or the
// file's folder), and the sampling settings of the vibrate filter.
#include <nanobind/stl/string.h>

#include "gdof/io/psf_field_io.h"
#include "gdof/psf_field.h"
#include "gdof_python.h"

namespace gdof::python {

PsfField psf_field_of(const nb::handle& h) {
    if (nb::isinstance<PsfField>(h)) return nb::cast<PsfField>(h);
    if (nb::isinstance<nb::str>(h)) return take(io::read_psf_field(nb::cast<std::string>(h)));
    return take(io::parse_psf_field(json_text(h), ""));
}

void register_psf_field(nb::module_& m) {
    nb::class_<PsfField>(m, "PsfField",
                         "Method 4's PSF field (docs/psf_field.md): for a point and an aperture sample, a displacement. "
                         "PsfField() is the defocus field; PsfField.parse(dict or JSON text), PsfField.read(path)")
        .def(nb::init<>(), "the defocus field: B(x) times the aperture sample")
        .def_static("parse",
                    [](const nb::handle& spec, const std::string& base_dir) {
                        return take(io::parse_psf_field(json_text(spec), base_dir));
                    },
                    nb::arg("spec"), nb::arg("base_dir") = "",
                    "from a dict ({'psf_field': {...}}) or JSON text; image_map paths relative to base_dir")
        .def_static("read", [](const std::string& path) { return take(io::read_psf_field(path)); }, nb::arg("path"),
                    "from a JSON file")
        .def_prop_ro("samples", &PsfField::samples, "aperture samples the file asks for (0: automatic)")
        .def_prop_ro("moves_depth", &PsfField::moves_depth, "True when a part moves points along their rays")
        .def("describe", &PsfField::describe)
        .def("__repr__", [](const PsfField& f) { return "gdof.PsfField(" + f.describe() + ")"; });

    nb::class_<VibrateOptions>(m, "VibrateOptions", "The vibrate filter's sampling (psf_field.h)")
        .def(nb::init<>())
        .def_rw("samples", &VibrateOptions::samples, "aperture samples; 0: the field's, else automatic")
        .def_rw("seed", &VibrateOptions::seed, "of the samples' jitter")
        .def_rw("prefilter", &VibrateOptions::prefilter, "each sample's splat: sigma = prefilter * sample spacing");

    nb::class_<VibrateStats>(m, "VibrateStats", "What the vibrate filter did")
        .def(nb::init<>())
        .def_ro("samples", &VibrateStats::samples)
        .def_ro("spacing", &VibrateStats::spacing)
        .def_ro("max_displacement_px", &VibrateStats::max_displacement_px)
        .def_ro("splats", &VibrateStats::splats);
}

}  // namespace gdof::python
