// Method 2 (gdof/compositing.h): gdof.composite, the stack from its manifest
// (read tile by tile, io::StackReader) and the desired focus from surfaces,
// near/far maps, or the blur field along the rays of an image with Z or P,
// as the CLI's --composite.
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include "gdof/compositing.h"
#include "gdof/focus_surfaces.h"
#include "gdof/io/stack_reader.h"
#include "gdof/io/stack_sources.h"
#include "gdof/text_file.h"
#include "gdof_python.h"

namespace gdof::python {

void register_composite(nb::module_& m) {
    m.def("composite",
          [](const std::string& manifest, const nb::handle& surfaces, const Image* near_map, const Image* far_map,
             const Image* image, std::optional<BlurField> blurfield, std::optional<Camera> camera, int soft, bool aovs,
             const nb::object& progress, int threads) {
              const FocalStack stack = take(io::load_stack(manifest));
              check(io::check_stack_files(stack));
              auto reader = take(io::StackReader::create(stack));
              CompositeOptions options;
              options.soft_k = soft;
              options.aovs = aovs;
              FocusSource focus;
              if (!surfaces.is_none()) {
                  // A file, or the surfaces themselves (a dict or JSON text).
                  std::string text = nb::isinstance<nb::str>(surfaces) && !nb::cast<std::string>(surfaces).starts_with("{")
                                         ? take(read_text(nb::cast<std::string>(surfaces)))
                                         : json_text(surfaces);
                  focus = take(parse_focus_surfaces(text));
              } else if (near_map || far_map) {
                  if (!near_map || !far_map)
                      raise(Status::error("composite: near_map and far_map go together", StatusCode::InvalidArgument));
                  const int nc = find_focus_map_channel(*near_map, "near"), fc = find_focus_map_channel(*far_map, "far");
                  if (nc < 0 || fc < 0)
                      raise(Status::error(std::string(nc < 0 ? "near_map" : "far_map") + ": no float channel",
                                          StatusCode::InvalidArgument));
                  focus = FocusMaps{near_map, nc, far_map, fc};
              } else if (image) {
                  if (!camera) camera = take(resolve_camera(image->metadata, image->display_window()));
                  if (!blurfield) blurfield = take(BlurField::from_thin_lens(take(camera->thin_lens())));
                  BlurFocusOptions bs;
                  bs.coc_px = stack.coc_px;
                  focus = FocusFromBlurField{&*blurfield, &*camera, image, bs};
              } else {
                  raise(Status::error("composite: no desired focus: give surfaces, near_map and far_map, or an image "
                                      "with Z or P (and a blurfield)",
                                      StatusCode::InvalidArgument));
              }
              Result<Image> result = Image{};
              run_work(progress, threads, [&](const Exec& exec) {
                  result = composite(stack, focus, *reader, options, nullptr, exec);
                  return result.status();
              });
              Image out = std::move(result).value();
              out.metadata.set_string("gdof:stackManifest", manifest);
              return out;
          },
          nb::arg("manifest"), nb::kw_only(), nb::arg("surfaces") = nb::none(), nb::arg("near_map") = nb::none(),
          nb::arg("far_map") = nb::none(), nb::arg("image") = nb::none(), nb::arg("blurfield") = nb::none(),
          nb::arg("camera") = nb::none(), nb::arg("soft") = 1, nb::arg("aovs") = false,
          nb::arg("progress") = nb::none(), nb::arg("threads") = 0,
          "Method 2: each pixel from the stack reference (manifest.json) whose near/far best matches the desired "
          "focus: surfaces (a file, dict or JSON text), near_map and far_map (Images), or the blur field along "
          "the rays of `image` (Z or P; blurfield defaults to its camera's thin lens). soft=K blends the best K.");
}

}  // namespace gdof::python
