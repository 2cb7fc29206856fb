// Photographed focus sweeps (gdof/focus_sweep.h): gdof.align_sweep and
// gdof.depth_from_focus, the library calls behind the CLI's
// --depth-from-focus (which aligns, then measures).
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "gdof/focus_sweep.h"
#include "gdof_python.h"

namespace gdof::python {

void register_focus_sweep(nb::module_& m) {
    nb::class_<Similarity>(m, "Similarity",
                           "A frame-to-frame map: x' = a x - b y + tx, y' = b x + a y + ty (positions from the data "
                           "window's corner, pixel centres at +0.5)")
        .def(nb::init<>())
        .def_rw("a", &Similarity::a)
        .def_rw("b", &Similarity::b)
        .def_rw("tx", &Similarity::tx)
        .def_rw("ty", &Similarity::ty)
        .def_prop_ro("scale", &Similarity::scale)
        .def_prop_ro("rotation_degrees", &Similarity::rotation_degrees)
        .def("apply", [](const Similarity& s, double x, double y) {
            double xo, yo;
            s.apply(x, y, xo, yo);
            return nb::make_tuple(xo, yo);
        }, nb::arg("x"), nb::arg("y"))
        .def("__repr__", [](const Similarity& s) {
            char b[160];
            std::snprintf(b, sizeof b, "Similarity(a=%.6g, b=%.6g, tx=%.6g, ty=%.6g)", s.a, s.b, s.tx, s.ty);
            return std::string(b);
        });
    nb::class_<SweepAlignment>(m, "SweepAlignment", "What align_sweep() found (focus_sweep.h)")
        .def_ro("reference", &SweepAlignment::reference, "the frame the others are aligned to (from 0)")
        .def_ro("maps", &SweepAlignment::maps, "per frame: reference pixel -> that frame's pixel")
        .def_ro("residual_before", &SweepAlignment::residual_before)
        .def_ro("residual_after", &SweepAlignment::residual_after)
        .def_ro("common", &SweepAlignment::common, "the pixels every frame sees")
        .def("report", &SweepAlignment::report)
        .def("__repr__", &SweepAlignment::report);
    nb::class_<DepthFromFocusStats>(m, "DepthFromFocusStats")
        .def_ro("pixels", &DepthFromFocusStats::pixels)
        .def_ro("holes", &DepthFromFocusStats::holes)
        .def_ro("outliers", &DepthFromFocusStats::outliers)
        .def("report", &DepthFromFocusStats::report)
        .def("__repr__", &DepthFromFocusStats::report);

    m.def("align_sweep",
          [](std::vector<Image> frames, const nb::object& progress, int threads) {
              Result<SweepAlignment> r = SweepAlignment{};
              run_work(progress, threads, [&](const Exec& exec) {
                  r = gdof::align_sweep(frames, AlignOptions{}, exec);
                  return r.status();
              });
              return nb::make_tuple(std::move(frames), std::move(r).value());
          },
          nb::arg("frames"), nb::kw_only(), nb::arg("progress") = nb::none(), nb::arg("threads") = 0,
          "Aligns a focus sweep's frames (a list of gdof.Image, one size) to the middle one: a similarity per frame, "
          "chained from neighbour to neighbour. Returns (aligned frames, SweepAlignment).");
    m.def("depth_from_focus",
          [](std::vector<Image> frames, std::optional<std::vector<double>> focus_distances, bool align, int window_radius,
             double min_peak_ratio, const nb::object& progress, int threads) {
              DepthFromFocusOptions o;
              o.window_radius = window_radius;
              o.min_peak_ratio = min_peak_ratio;
              Result<DepthFromFocus> r = DepthFromFocus{};
              run_work(progress, threads, [&](const Exec& exec) {
                  if (align) {
                      auto a = gdof::align_sweep(frames, AlignOptions{}, exec);
                      if (!a) return a.status();
                  }
                  r = gdof::depth_from_focus(frames, focus_distances.value_or(std::vector<double>{}), o, exec);
                  return r.status();
              });
              DepthFromFocus out = std::move(r).value();
              return nb::make_tuple(std::move(out.plate), out.stats);
          },
          nb::arg("frames"), nb::arg("focus_distances") = nb::none(), nb::kw_only(), nb::arg("align") = true,
          nb::arg("window_radius") = DepthFromFocusOptions{}.window_radius,
          nb::arg("min_peak_ratio") = DepthFromFocusOptions{}.min_peak_ratio, nb::arg("progress") = nb::none(),
          nb::arg("threads") = 0,
          "Depth from focus (the CLI's --depth-from-focus): frames in sweep order, aligned first unless align=False, "
          "and their focus distances (else the frame index from 1 is the depth). Returns (plate, DepthFromFocusStats): "
          "the all-in-focus R, G, B, A with Z, focus.index and focus.confidence.");
}

}  // namespace gdof::python
