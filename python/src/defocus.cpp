// Method 3 (gdof/defocus.h): gdof.defocus and its settings, DefocusOptions
// and the structs it holds, field for field. defocus() also takes the CLI's
// flags as keywords, named without dashes (solver=, layers=, adi_steps=,
// pyramid=, aperture=, psf_field=, psf_samples=, depth_channel=,
// focal_length_mm=, ...); filter="vibrate" is method 4 (--vibrate).
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdio>
#include <functional>
#include <limits>
#include <map>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/defocus.h"
#include "gdof/plate.h"
#include "gdof_python.h"

namespace gdof::python {

namespace {

DiffusionSolver solver_of(const std::string& s) { return take(parse_diffusion_solver(s.c_str())); }
DepthEncoding encoding_of(const std::string& s) { return take(parse_depth_encoding(s)); }
DefocusFilter filter_of(const std::string& s) {
    if (s == "diffusion") return DefocusFilter::Diffusion;
    if (s == "bokeh") return DefocusFilter::Bokeh;
    if (s == "vibrate") return DefocusFilter::Vibrate;
    raise(Status::error("filter: expected diffusion, bokeh or vibrate, got '" + s + "'", StatusCode::InvalidArgument, "filter"));
}
Aperture aperture_of(const nb::handle& h) {
    if (nb::isinstance<Aperture>(h)) return nb::cast<Aperture>(h);
    return take(parse_aperture(nb::cast<std::string>(h)));
}
LayerSplit split_of(const nb::handle& h) {
    if (nb::isinstance<LayerSplit>(h)) return nb::cast<LayerSplit>(h);
    if (nb::isinstance<nb::int_>(h)) return take(parse_layer_split(std::to_string(nb::cast<int>(h))));
    return take(parse_layer_split(nb::cast<std::string>(h)));
}
double invalid_of(const nb::handle& h) {
    if (nb::isinstance<nb::str>(h)) {
        const std::string s = nb::cast<std::string>(h);
        if (s == "hole") return std::numeric_limits<double>::quiet_NaN();
        if (s == "sky") return std::numeric_limits<double>::infinity();
        raise(Status::error("depth_invalid: expected hole or sky, got '" + s + "'", StatusCode::InvalidArgument));
    }
    return nb::cast<double>(h);
}

// A pixel given as (x, y), as --focus-at X,Y and --probe X,Y take it.
std::pair<int, int> pixel_of(const nb::handle& h, const char* what) {
    auto seq = nb::cast<std::vector<int>>(h);
    if (seq.size() != 2)
        raise(Status::error(std::string(what) + ": expected (x, y), got " + std::to_string(seq.size()) + " values",
                            StatusCode::InvalidArgument, what));
    return {seq[0], seq[1]};
}

// defocus()'s keywords: the CLI's flags without dashes, each setting one
// field of DefocusOptions (or of the lens overrides of the camera, or the
// pixel to focus at).
struct Settings {
    DefocusOptions options;
    LensOverrides lens;
    std::optional<std::pair<int, int>> focus_at;
};
using Setter = std::function<void(Settings&, const nb::handle&)>;
const std::map<std::string, Setter>& keywords() {
    static const std::map<std::string, Setter> k = {
        {"filter", [](Settings& s, const nb::handle& v) { s.options.filter = filter_of(nb::cast<std::string>(v)); }},
        {"aperture", [](Settings& s, const nb::handle& v) { s.options.aperture = aperture_of(v); }},
        {"psf_field", [](Settings& s, const nb::handle& v) { s.options.psf_field = psf_field_of(v); }},
        {"psf_samples", [](Settings& s, const nb::handle& v) { s.options.vibrate.samples = nb::cast<int>(v); }},
        {"solver", [](Settings& s, const nb::handle& v) { s.options.diffusion.solver = solver_of(nb::cast<std::string>(v)); }},
        {"adi_steps", [](Settings& s, const nb::handle& v) { s.options.diffusion.adi_steps = nb::cast<int>(v); }},
        {"explicit_safety", [](Settings& s, const nb::handle& v) { s.options.diffusion.explicit_safety = nb::cast<double>(v); }},
        {"max_radius", [](Settings& s, const nb::handle& v) { s.options.diffusion.max_radius = nb::cast<double>(v); }},
        {"pyramid", [](Settings& s, const nb::handle& v) { s.options.diffusion.pyramid = nb::cast<bool>(v); }},
        {"layers", [](Settings& s, const nb::handle& v) { s.options.split = split_of(v); }},
        {"position_channels", [](Settings& s, const nb::handle& v) { s.options.source.position_channels = nb::cast<std::string>(v); }},
        {"depth_channel", [](Settings& s, const nb::handle& v) { s.options.source.depth_channel = nb::cast<std::string>(v); }},
        {"depth_encoding", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.encoding = encoding_of(nb::cast<std::string>(v)); }},
        {"depth_scale", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.scale = nb::cast<double>(v); }},
        {"depth_near", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.near = nb::cast<double>(v); }},
        {"depth_far", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.far = nb::cast<double>(v); }},
        {"depth_invalid", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.invalid = invalid_of(v); }},
        {"depth_invalid_value", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.invalid_value = nb::cast<double>(v); }},
        {"depth_max", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.max_depth = nb::cast<double>(v); }},
        {"baseline", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.baseline = nb::cast<double>(v); }},
        {"depth_range", [](Settings& s, const nb::handle& v) { s.options.source.depth_decode.range = nb::cast<bool>(v); }},
        {"remove_speckles", [](Settings& s, const nb::handle& v) { s.options.cleanup.remove_speckles = nb::cast<bool>(v); }},
        {"mixed_pixels", [](Settings& s, const nb::handle& v) { s.options.cleanup.mixed_pixels = nb::cast<bool>(v); }},
        {"smooth_noise", [](Settings& s, const nb::handle& v) { s.options.cleanup.smooth_noise = nb::cast<bool>(v); }},
        {"roi", [](Settings& s, const nb::handle& v) { s.options.roi = to_roi(v); }},
        {"focal_length_mm", [](Settings& s, const nb::handle& v) { s.lens.focal_length_mm = nb::cast<double>(v); }},
        {"sensor_width_mm", [](Settings& s, const nb::handle& v) { s.lens.sensor_width_mm = nb::cast<double>(v); }},
        {"f_number", [](Settings& s, const nb::handle& v) { s.lens.f_number = nb::cast<double>(v); }},
        {"focus_distance", [](Settings& s, const nb::handle& v) { s.lens.focus_distance = nb::cast<double>(v); }},
        {"scene_unit_mm", [](Settings& s, const nb::handle& v) { s.lens.scene_unit_mm = nb::cast<double>(v); }},
        {"focus_at", [](Settings& s, const nb::handle& v) { s.focus_at = pixel_of(v, "focus_at"); }},
    };
    return k;
}

void apply_keywords(Settings& s, const nb::kwargs& kwargs, const char* function = "defocus") {
    for (auto [key, value] : kwargs) {
        const std::string name = nb::cast<std::string>(key);
        auto it = keywords().find(name);
        if (it == keywords().end()) {
            std::string known;
            for (const auto& [n, setter] : keywords()) known += (known.empty() ? "" : ", ") + n;
            throw nb::type_error((std::string(function) + "(): unknown keyword '" + name + "' (known: " + known + ")").c_str());
        }
        if (!value.is_none()) it->second(s, value);
    }
}

// The camera of part `part` as the CLI resolves it: `given`, else the part's
// metadata with the lens keywords; focused at `focus_at` when given (as
// --focus-at: then the camera comes from the input, not `given`). Without
// `required`, a camera that cannot be resolved is none (a probe needs none).
std::optional<Camera> camera_of(const ImageSet& set, std::size_t part, const Settings& s, std::optional<Camera> given,
                                bool required) {
    if (s.focus_at) {
        if (given)
            raise(Status::error("focus_at: the focused camera is resolved from the input and the lens keywords; give "
                                "those instead of camera=",
                                StatusCode::InvalidArgument, "focus_at"));
        const auto [x, y] = *s.focus_at;
        return take(focus_camera_at(set, part, s.lens, s.options.source, s.options.cleanup, x, y)).camera;
    }
    if (given) return given;
    const Roi display = set.is_deep(part) ? set.deep(part).display_window() : set.flat(part).display_window();
    auto c = resolve_camera(set.metadata(part), display, s.lens);
    if (!c && !required) return std::nullopt;
    return take(std::move(c));
}

// The blur field as the CLI takes it: `given` (refocused at the camera's
// focus distance after focus_at), else the camera's thin lens. Without
// `required`, none when the lens is incomplete.
std::optional<BlurField> field_of(const Camera& camera, const Settings& s, std::optional<BlurField> given,
                                  bool required) {
    if (given && s.focus_at) return take(given->refocused(camera.lens().focus_distance));
    if (given) return given;
    auto lens = camera.thin_lens();
    if (!lens && !required) return std::nullopt;
    return take(BlurField::from_thin_lens(take(std::move(lens))));
}

}  // namespace

void register_defocus(nb::module_& m) {
    nb::class_<DiffusionOptions>(m, "DiffusionOptions")
        .def(nb::init<>())
        .def_prop_rw("solver", [](const DiffusionOptions& o) { return std::string(to_string(o.solver)); },
                     [](DiffusionOptions& o, const std::string& s) { o.solver = solver_of(s); }, "auto, explicit or adi")
        .def_rw("adi_steps", &DiffusionOptions::adi_steps)
        .def_rw("explicit_safety", &DiffusionOptions::explicit_safety)
        .def_rw("max_radius", &DiffusionOptions::max_radius)
        .def_rw("pyramid", &DiffusionOptions::pyramid);

    nb::class_<LayerSplit>(m, "LayerSplit", "How defocus splits its input into layers; LayerSplit.parse('auto:16:blur=3')")
        .def(nb::init<>())
        .def_static("parse", [](const std::string& t) { return take(parse_layer_split(t)); }, nb::arg("text"))
        .def_prop_ro("mode", [](const LayerSplit& l) {
            return std::string(l.mode == LayerSplit::Mode::Auto ? "auto" : l.mode == LayerSplit::Mode::Count ? "count" : "id");
        })
        .def_rw("count", &LayerSplit::count)
        .def_rw("max_layers", &LayerSplit::max_layers)
        .def_rw("blur_step", &LayerSplit::blur_step)
        .def_rw("id_channel", &LayerSplit::id_channel);

    nb::class_<DepthDecode>(m, "DepthDecode", "How stored depth values become metric depth (camera.h)")
        .def(nb::init<>())
        .def_prop_rw("encoding", [](const DepthDecode& d) { return std::string(to_string(d.encoding)); },
                     [](DepthDecode& d, const std::string& s) { d.encoding = encoding_of(s); })
        .def_rw("scale", &DepthDecode::scale)
        .def_rw("near", &DepthDecode::near)
        .def_rw("far", &DepthDecode::far)
        .def_rw("flip", &DepthDecode::flip)
        .def_rw("range", &DepthDecode::range)
        .def_rw("invalid", &DepthDecode::invalid)
        .def_rw("invalid_value", &DepthDecode::invalid_value)
        .def_rw("max_depth", &DepthDecode::max_depth)
        .def_rw("baseline", &DepthDecode::baseline);

    nb::class_<PositionSource>(m, "PositionSource", "Where a pixel's world position or depth comes from")
        .def(nb::init<>())
        .def_rw("position_channels", &PositionSource::position_channels)
        .def_rw("depth_channel", &PositionSource::depth_channel)
        .def_rw("depth_decode", &PositionSource::depth_decode, nb::rv_policy::reference_internal);

    nb::class_<DepthCleanupOptions>(m, "DepthCleanupOptions", "Plate depth repair (plate.h)")
        .def(nb::init<>())
        .def_rw("remove_speckles", &DepthCleanupOptions::remove_speckles)
        .def_rw("mixed_pixels", &DepthCleanupOptions::mixed_pixels)
        .def_rw("smooth_noise", &DepthCleanupOptions::smooth_noise)
        .def_rw("continuity", &DepthCleanupOptions::continuity)
        .def_rw("speckle_px", &DepthCleanupOptions::speckle_px)
        .def_rw("mixed_step", &DepthCleanupOptions::mixed_step);

    nb::class_<Aperture>(m, "Aperture",
                         "The iris (aperture.h): Aperture.parse('polygon:6:15,roundness=0.2'); an image kernel "
                         "is given as `image` (a gdof.Image)")
        .def(nb::init<>())
        .def_static("parse", [](const std::string& s) { return take(parse_aperture(s)); }, nb::arg("spec"))
        .def_prop_ro("kind", [](const Aperture& a) { return std::string(to_string(a.kind)); })
        .def_rw("blades", &Aperture::blades)
        .def_rw("rotation_deg", &Aperture::rotation_deg)
        .def_rw("roundness", &Aperture::roundness)
        .def_rw("squeeze", &Aperture::squeeze)
        .def_rw("cats_eye", &Aperture::cats_eye)
        .def_prop_rw("image", [](const Aperture& a) { return a.image; },
                     [](Aperture& a, const Image& img) {
                         a.kind = Aperture::Kind::Image;
                         a.image = img;
                     })
        .def("validate", [](const Aperture& a) { check(validate(a)); })
        .def("__str__", [](const Aperture& a) { return format_aperture(a); });

    nb::class_<DefocusOptions>(m, "DefocusOptions", "Every setting of defocus() (defocus.h), as the C++ struct")
        .def(nb::init<>())
        .def_prop_rw("filter", [](const DefocusOptions& o) { return std::string(to_string(o.filter)); },
                     [](DefocusOptions& o, const std::string& s) { o.filter = filter_of(s); }, "diffusion, bokeh or vibrate")
        .def_prop_rw("aperture", [](const DefocusOptions& o) { return o.aperture; },
                     [](DefocusOptions& o, const nb::handle& a) { o.aperture = aperture_of(a); })
        .def_prop_rw("psf_field", [](const DefocusOptions& o) { return o.psf_field; },
                     [](DefocusOptions& o, const nb::handle& f) { o.psf_field = psf_field_of(f); },
                     "vibrate: a PsfField, the path of its file or its dict")
        .def_rw("vibrate", &DefocusOptions::vibrate, nb::rv_policy::reference_internal)
        .def_rw("diffusion", &DefocusOptions::diffusion, nb::rv_policy::reference_internal)
        .def_prop_rw("split", [](const DefocusOptions& o) { return o.split; },
                     [](DefocusOptions& o, const nb::handle& s) { o.split = split_of(s); }, "a LayerSplit or its text")
        .def_rw("source", &DefocusOptions::source, nb::rv_policy::reference_internal)
        .def_rw("cleanup", &DefocusOptions::cleanup, nb::rv_policy::reference_internal)
        .def_prop_rw("roi", [](const DefocusOptions& o) { return o.roi; },
                     [](DefocusOptions& o, const nb::handle& r) { o.roi = to_roi(r); });

    nb::class_<DefocusStats>(m, "DefocusStats", "What defocus() did (pass one as stats= to fill it)")
        .def(nb::init<>())
        .def_ro("layers", &DefocusStats::layers)
        .def_ro("layers_empty", &DefocusStats::layers_empty)
        .def_ro("layers_sharp", &DefocusStats::layers_sharp)
        .def_ro("layers_explicit", &DefocusStats::layers_explicit)
        .def_ro("layers_adi", &DefocusStats::layers_adi)
        .def_ro("layers_bokeh", &DefocusStats::layers_bokeh)
        .def_ro("layers_pyramid", &DefocusStats::layers_pyramid)
        .def_ro("layers_vibrated", &DefocusStats::layers_vibrated)
        .def_ro("vibrate", &DefocusStats::vibrate, nb::rv_policy::reference_internal)
        .def_ro("max_radius_px", &DefocusStats::max_radius_px)
        .def("report", &DefocusStats::report);

    m.def("defocus",
          [](const nb::handle& input, std::optional<BlurField> blurfield, std::optional<Camera> camera,
             std::optional<DefocusOptions> options, DefocusStats* stats, const nb::object& progress, int threads,
             const nb::kwargs& kwargs) {
              ImageSet storage;
              const ImageSet& set = to_image_set(input, storage);
              if (set.empty()) raise(Status::error("defocus: the input has no image parts", StatusCode::InvalidArgument));
              Settings s;
              if (options) s.options = *options;
              apply_keywords(s, kwargs);
              // The camera and field as the CLI takes them: the reference
              // part's metadata with the lens overrides, focused at focus_at;
              // the thin lens.
              camera = camera_of(set, defocus_reference_part(set), s, camera, true);
              blurfield = field_of(*camera, s, blurfield, true);
              Result<ImageSet> result = ImageSet{};
              run_work(progress, threads, [&](const Exec& exec) {
                  result = defocus(set, *blurfield, *camera, s.options, stats, exec);
                  return result.status();
              });
              return std::move(result).value();
          },
          nb::arg("input"), nb::arg("blurfield") = nb::none(), nb::arg("camera") = nb::none(), nb::kw_only(),
          nb::arg("options") = nb::none(), nb::arg("stats") = nb::none(), nb::arg("progress") = nb::none(),
          nb::arg("threads") = 0, nb::arg("kwargs"),
          "Method 3: defocuses an ImageSet (deep, multipart, or RGBA + depth; an Image or list is copied in) into "
          "one flat part: R, G, B, A. blurfield defaults to the camera's thin lens, camera to the input's "
          "(resolve_camera with the lens keywords). Keywords: the CLI's flags without dashes; filter='bokeh' is "
          "--bokeh, filter='vibrate' --vibrate (method 4, with psf_field= and psf_samples=); focus_at=(x, y) is "
          "--focus-at X,Y.");

    nb::class_<PixelProbe>(m, "PixelProbe", "What probe() finds at a pixel (plate.h); NaN where unknown")
        .def_ro("x", &PixelProbe::x)
        .def_ro("y", &PixelProbe::y)
        .def_ro("depth", &PixelProbe::depth, "median depth of the 5x5 pixels around (+inf: sky)")
        .def_prop_ro("position", [](const PixelProbe& p) { return nb::make_tuple(p.position.x, p.position.y, p.position.z); },
                     "world position (NaN without a camera)")
        .def_ro("blur_px", &PixelProbe::blur_px, "blur radius in pixels (NaN without a camera and a lens or field)")
        .def_ro("mixed", &PixelProbe::mixed,
                "a silhouette pixel the defocus splits into a foreground and a background part (step 4's only "
                "with a lens or field)")
        .def_ro("fg_share", &PixelProbe::fg_share, "a split pixel's foreground share (else NaN)")
        .def_ro("fg_depth", &PixelProbe::fg_depth, "a split pixel's foreground depth (else NaN)")
        .def_ro("bg_depth", &PixelProbe::bg_depth, "a split pixel's background depth (else NaN)")
        .def_ro("fg_blur_px", &PixelProbe::fg_blur_px, "a split pixel's foreground blur radius (else NaN)")
        .def_ro("bg_blur_px", &PixelProbe::bg_blur_px, "a split pixel's background blur radius (else NaN)")
        .def("__repr__", [](const PixelProbe& p) {
            char b[320];
            std::snprintf(b, sizeof b, "PixelProbe(x=%d, y=%d, depth=%g, position=(%g, %g, %g), blur_px=%g", p.x, p.y,
                          p.depth, p.position.x, p.position.y, p.position.z, p.blur_px);
            std::string r = b;
            if (p.mixed) {
                std::snprintf(b, sizeof b, ", mixed=True, fg_share=%g, fg_depth=%g, bg_depth=%g", p.fg_share,
                              p.fg_depth, p.bg_depth);
                r += b;
            }
            return r + ")";
        });

    m.def("probe",
          [](const nb::handle& input, int x, int y, std::optional<BlurField> blurfield, std::optional<Camera> camera,
             const nb::kwargs& kwargs) {
              ImageSet storage;
              const ImageSet& set = to_image_set(input, storage);
              std::size_t part = 0;
              while (part < set.size() && set.is_deep(part)) ++part;
              if (part == set.size())
                  raise(Status::error("probe: the input has no flat part", StatusCode::InvalidArgument));
              Settings s;
              apply_keywords(s, kwargs, "probe");
              // As --probe: what is known, nothing asked for first.
              camera = camera_of(set, part, s, camera, false);
              if (camera) blurfield = field_of(*camera, s, blurfield, false);
              const Image& plate = set.flat(part);
              const int z = take(find_depth_channel(plate, s.options.source.depth_channel));
              if (z < 0)
                  raise(Status::error("probe: the input has no depth channel '" +
                                          (s.options.source.depth_channel.empty() ? std::string("Z")
                                                                                  : s.options.source.depth_channel) +
                                          "'",
                                      StatusCode::NotFound, "depth_channel"));
              return take(probe_plate(plate, z, s.options.source.depth_decode, s.options.cleanup,
                                      camera ? &*camera : nullptr, blurfield ? &*blurfield : nullptr, x, y));
          },
          nb::arg("input"), nb::arg("x"), nb::arg("y"), nb::arg("blurfield") = nb::none(),
          nb::arg("camera") = nb::none(), nb::arg("kwargs"),
          "--probe X,Y: depth, world position and blur at pixel (x, y) of the input's first flat part, its depth "
          "decoded and cleaned as defocus() does (the same keywords). Needs no lens: without a focal length only the "
          "depth, without an f-number and focus distance no blur (NaN).");
}

}  // namespace gdof::python
