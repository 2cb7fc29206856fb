// Method 1 (gdof/raytrace.h): gdof.render, a scene file through the ray
// tracer, the settings named as RenderOptions' fields (the CLI's flags).
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include "gdof/raytrace.h"
#include "gdof/scene.h"
#include "gdof_python.h"

namespace gdof::python {

void register_render(nb::module_& m) {
    m.def("render",
          [](const std::string& scene_path, std::optional<BlurField> blurfield, int spp, int min_spp,
             double adaptive_threshold, bool pinhole, bool straight_thin_lens, int light_samples, std::uint64_t seed,
             const std::string& aovs, const nb::handle& aperture, bool deep, const nb::object& progress,
             int threads) -> nb::object {
              const Scene scene = take(load_scene(scene_path));
              RenderOptions o;
              o.spp = spp;
              o.min_spp = min_spp;
              o.adaptive_threshold = adaptive_threshold;
              o.pinhole = pinhole;
              o.straight_thin_lens = straight_thin_lens;
              o.light_samples = light_samples;
              o.seed = seed;
              o.aovs = take(parse_render_aovs(aovs));
              o.aperture = aperture.is_none() ? scene.aperture
                                              : nb::isinstance<Aperture>(aperture)
                                                    ? nb::cast<Aperture>(aperture)
                                                    : take(parse_aperture(nb::cast<std::string>(aperture)));
              if (blurfield && !pinhole) o.blur_field = &*blurfield;  // as the CLI: a pinhole has no lens
              std::shared_ptr<const RayTracer> tracer = take(RayTracer::build(scene));
              if (deep) {
                  Result<DeepImage> r = DeepImage{};
                  run_work(progress, threads, [&](const Exec& exec) {
                      r = render_deep(*tracer, o, nullptr, exec);
                      return r.status();
                  });
                  return nb::cast(std::move(r).value());
              }
              Result<Image> r = Image{};
              run_work(progress, threads, [&](const Exec& exec) {
                  r = render(*tracer, o, nullptr, exec);
                  return r.status();
              });
              return nb::cast(std::move(r).value());
          },
          nb::arg("scene"), nb::arg("blurfield") = nb::none(), nb::kw_only(), nb::arg("spp") = 64,
          nb::arg("min_spp") = 16, nb::arg("adaptive_threshold") = 0.01, nb::arg("pinhole") = false,
          nb::arg("straight_thin_lens") = false, nb::arg("light_samples") = 2, nb::arg("seed") = 0,
          nb::arg("aovs") = "all", nb::arg("aperture") = nb::none(), nb::arg("deep") = false,
          nb::arg("progress") = nb::none(), nb::arg("threads") = 0,
          "Method 1: renders a scene JSON (docs/scene.md) with its camera, or the blurfield's nonlinear rays; "
          "an Image (beauty + AOVs), or a DeepImage with deep=True.");
}

}  // namespace gdof::python
