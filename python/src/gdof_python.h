// The gdof Python module (_gdof, wrapped by python/gdof/__init__.py): what
// its binding files share. Thin: values in, one library call, values out.
#pragma once

#include <functional>
#include <string>

#include <nanobind/nanobind.h>

#include "gdof/exec.h"
#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/psf_field.h"
#include "gdof/status.h"

namespace gdof::python {

namespace nb = nanobind;

// A failed Status as the Python exception gdof.Error: the library's message
// unchanged, its code ("invalid_argument", ...) and subject as attributes
// (errors.cpp).
struct StatusError {
    Status status;
};
[[noreturn]] inline void raise(const Status& s) { throw StatusError{s}; }
inline void check(const Status& s) {
    if (!s) raise(s);
}
template <class T>
T take(Result<T>&& r) {
    if (!r) raise(r.status());
    return std::move(r).value();
}

// Runs library work with the GIL released (work.cpp). `progress` (None or a
// callable taking a fraction 0..1) is called with the GIL held, at most
// every 0.1 s. Ctrl-C (a pending KeyboardInterrupt, checked on the calling
// thread) and an exception from `progress` cancel the work and are raised
// once it has stopped; otherwise a failed Status is raised as gdof.Error.
void run_work(const nb::object& progress, int threads, const std::function<Status(const Exec&)>& work);

// Windows: a gdof.Roi or a 4-sequence (x0, y0, x1, y1), half-open.
Roi to_roi(const nb::handle& h);
// Parts for the library: a gdof.ImageSet as it is (no copy), or an Image,
// a DeepImage or a sequence of them (copied into `storage`).
const ImageSet& to_image_set(const nb::handle& h, ImageSet& storage);
// Text of a JSON argument: a str as it is, anything else (dict, list)
// through json.dumps.
std::string json_text(const nb::handle& h);

// A PSF field for defocus(psf_field=...) and DefocusOptions.psf_field: a
// gdof.PsfField as it is, a str as the path of its file (the CLI's
// --psf-field FILE), anything else (a dict) as its JSON (psf_field.cpp).
PsfField psf_field_of(const nb::handle& h);

void register_errors(nb::module_& m);
void register_images(nb::module_& m);
void register_image_io(nb::module_& m);
void register_camera(nb::module_& m);
void register_blur_field(nb::module_& m);
void register_psf_field(nb::module_& m);
void register_defocus(nb::module_& m);
void register_composite(nb::module_& m);
void register_render(nb::module_& m);
void register_lightfield(nb::module_& m);
void register_focus_sweep(nb::module_& m);

}  // namespace gdof::python
