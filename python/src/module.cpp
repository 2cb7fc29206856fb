// The extension module gdof._gdof: each binding file registers its part.
#include "gdof_python.h"
#include "gdof/version.h"

NB_MODULE(_gdof, m) {
    using namespace gdof::python;
    m.doc() = "gdof: generalized depth of field (the C++ library's bindings; import gdof)";
    m.attr("__version__") = gdof::version();
    register_errors(m);
    register_images(m);
    register_image_io(m);
    register_camera(m);
    register_blur_field(m);
    register_psf_field(m);
    register_defocus(m);
    register_composite(m);
    register_render(m);
    register_lightfield(m);
    register_focus_sweep(m);
}
