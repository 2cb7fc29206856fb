// gdof.Error: a library Status as a Python exception with the library's
// message as its text (what the CLI prints after "gdof: error: <flag>: ").
#include <nanobind/stl/string.h>

#include "gdof_python.h"

namespace gdof::python {

namespace {

PyObject* g_error = nullptr;

std::string code_name(StatusCode code) {
    switch (code) {
        case StatusCode::Ok: return "ok";
        case StatusCode::Failed: return "failed";
        case StatusCode::InvalidArgument: return "invalid_argument";
        case StatusCode::NotFound: return "not_found";
        case StatusCode::Io: return "io";
        case StatusCode::Cancelled: return "cancelled";
    }
    return "failed";
}

}  // namespace

void register_errors(nb::module_& m) {
    g_error = PyErr_NewExceptionWithDoc(
        "gdof.Error",
        "A gdof library error. str(e) is the library's message, naming the culprit (file, channel, key, "
        "parameter); e.code is its kind ('failed', 'invalid_argument', 'not_found', 'io', 'cancelled') and "
        "e.subject the setting it is about ('focal_length_mm'), or ''.",
        PyExc_RuntimeError, nullptr);
    m.attr("Error") = nb::handle(g_error);
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const StatusError& e) {
            nb::object exc = nb::steal(PyObject_CallFunction(g_error, "s", e.status.message().c_str()));
            if (!exc.is_valid()) return;  // the call's own error is set
            exc.attr("code") = code_name(e.status.code());
            exc.attr("subject") = e.status.subject();
            PyErr_SetObject(g_error, exc.ptr());
        }
    });
}

}  // namespace gdof::python
