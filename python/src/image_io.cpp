// Files: read_image / write_image (gdof::io, image_io.h), the options named
// as ReadOptions / WriteOptions' fields.
#include <nanobind/stl/string.h>

#include "gdof/io/image_io.h"
#include "gdof_python.h"

namespace gdof::python {

void register_image_io(nb::module_& m) {
    m.def("read_image",
          [](const std::string& path, bool linearize, const std::string& colorspace) {
              io::ReadOptions ro;
              ro.linearize = linearize;
              ro.colorspace = colorspace;
              Result<ImageSet> r = ImageSet{};
              {
                  nb::gil_scoped_release release;
                  r = io::read_image(path, ro);
              }
              return take(std::move(r));
          },
          nb::arg("path"), nb::arg("linearize") = true, nb::arg("colorspace") = "",
          "Reads every part of an image file (EXR flat, multipart, deep; PNG, JPEG, TIFF, ...) as a gdof.ImageSet; "
          "colour to scene-linear unless linearize=False.");
    m.def("write_image",
          [](const std::string& path, const nb::handle& images, const std::string& pixel_type,
             const std::string& compression, const std::string& colorspace) {
              ImageSet storage;
              const ImageSet& set = to_image_set(images, storage);
              io::WriteOptions wo;
              wo.pixel_type = pixel_type;
              wo.compression = compression;
              wo.colorspace = colorspace;
              Status st;
              {
                  nb::gil_scoped_release release;
                  st = io::write_image(path, set, wo);
              }
              check(st);
          },
          nb::arg("path"), nb::arg("images"), nb::arg("pixel_type") = "", nb::arg("compression") = "",
          nb::arg("colorspace") = "",
          "Writes a gdof.ImageSet, an Image, a DeepImage or a list of them (several: EXR multipart); "
          "atomically (a temporary file renamed: never a partial file).");
}

}  // namespace gdof::python
