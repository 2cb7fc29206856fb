// Light fields (gdof/lightfield.h, gdof/io/lightfield_io.h):
// gdof.extract_stack, a focus/aperture stack refocused from the views by
// shift-and-add, for method 2.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "gdof/io/lightfield_io.h"
#include "gdof/lightfield.h"
#include "gdof_python.h"

namespace gdof::python {

namespace {

// A JSON argument: a file path (str), or the document itself (a dict).
bool is_path(const nb::handle& h) { return nb::isinstance<nb::str>(h); }

}  // namespace

void register_lightfield(nb::module_& m) {
    m.def("extract_stack",
          [](const std::string& views, const nb::handle& stack, const nb::handle& lf, const nb::object& progress,
             int threads) {
              io::LightFieldConfig config;
              if (!lf.is_none())
                  config = is_path(lf) ? take(io::read_lightfield_config(nb::cast<std::string>(lf)))
                                       : take(io::parse_lightfield_config(json_text(lf)));
              ExtractStackOptions spec = is_path(stack) ? take(io::read_extract_stack_options(nb::cast<std::string>(stack)))
                                                        : take(io::parse_extract_stack_options(json_text(stack)));
              spec.scene_unit_mm = config.scene_unit_mm;
              LightField field;
              Result<ExtractedStack> result = ExtractedStack{};
              run_work(progress, threads, [&](const Exec& exec) {
                  auto loaded = io::load_lightfield(views, config, {}, exec);
                  if (!loaded) return loaded.status();
                  field = std::move(loaded).value();
                  result = extract_stack(field, spec, {}, exec);
                  return result.status();
              });
              ExtractedStack out = std::move(result).value();
              return nb::make_tuple(std::move(out.images), format_stack_manifest(out.stack));
          },
          nb::arg("views"), nb::arg("stack"), nb::arg("lf") = nb::none(), nb::kw_only(), nb::arg("progress") = nb::none(),
          nb::arg("threads") = 0,
          "A focus/aperture stack from light-field views ('views/%02d_%02d.png' or a Stanford-archive folder): "
          "stack and lf are the CLI's --stack and --lf JSON (paths, or dicts). Returns (images, manifest JSON "
          "text; its file names are empty: write the images and set them).");
}

}  // namespace gdof::python
