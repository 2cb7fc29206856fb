#include "defocus_params.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "gdof/io/psf_field_io.h"

namespace gdof::ofx {

namespace {

const std::vector<std::string> kKinds = {"thin_lens", "focal_planes", "region", "image_map"};
const std::vector<std::string> kInterpolations = {"linear", "smooth"};
const std::vector<std::string> kShapes = {"sphere", "box", "plane"};
const std::vector<std::string> kModes = {"focus", "blur"};
const std::vector<std::string> kChannels = {"R", "G", "B", "A"};
const std::vector<std::string> kPasses = {"depth", "position"};
const std::vector<std::string> kEncodings = {"metric", "inverse", "scaled", "near_far_linear", "near_far_inverse"};
// Choice params are saved by index: new options go last.
const std::vector<std::string> kSolvers = {"adi", "explicit", "auto"};
const std::vector<std::string> kAnalyses = {"frame", "region"};
const std::vector<std::string> kFilters = {"diffusion", "bokeh", "vibrate"};
const std::vector<std::string> kApertures = {"disc", "polygon", "image"};

// Index of `value` in `options` (a descriptor's default).
int option_index(const std::vector<std::string>& options, const std::string& value) {
    const auto it = std::find(options.begin(), options.end(), value);
    return it == options.end() ? 0 : int(it - options.begin());
}

std::string depth_name(int i) { return "depths_" + std::to_string(i + 1); }

}  // namespace

void describe_defocus_params(ParamDefiner& d) {
    const DefocusParams def;
    d.set_group("");
    d.choice("kind", "Blur Field", kKinds, 0,
             "What places the blur: thin_lens (a real camera), focal_planes (sharp depths, blur between), "
             "region (a sphere / box / slab of focus or of blur), image_map (the Blur Map clip)");
    d.number("max_radius", "Max Blur (px)", def.max_radius, 0, 1000, 0, 100,
             "Largest blur radius in pixels at full resolution: the field is clamped to it, and the output grows by it");

    d.group("grp_lens", "Camera / Lens");
    d.set_group("grp_lens");
    d.number("focal_length_mm", "Focal Length (mm)", def.focal_length_mm, 0.1, 10000, 10, 300,
             "Focal length of the camera that saw the depth pass (also the thin lens)");
    d.number("sensor_width_mm", "Sensor Width (mm)", def.sensor_width_mm, 0.1, 1000, 5, 70, "Sensor width matching the image width");
    d.number("f_number", "f-number", def.f_number, 0.1, 1000, 1, 32, "thin_lens: aperture f-number");
    d.number("focus_distance", "Focus Distance", def.focus_distance, 1e-4, 1e9, 0.1, 100, "thin_lens: focus distance in scene units");
    d.boolean("use_focus_at", "Focus at Point", def.use_focus_at,
              "thin_lens: focus at the depth of the Focus At point (median of the 5x5 valid depths around it) "
              "instead of Focus Distance (--focus-at)");
    d.point2("focus_at", "Focus At", def.focus_at, "The point of the image whose depth the lens focuses at");
    d.number("scene_unit_mm", "Scene Unit (mm)", def.scene_unit_mm, 1e-6, 1e9, 1, 1000, "Millimetres per scene unit (1000: metres)");

    d.group("grp_planes", "Focal Planes");
    d.set_group("grp_planes");
    d.integer("depths_count", "Number of Planes", 2, 1, kMaxFocalPlanes, "How many of the depths below are in focus");
    const double depth_defaults[kMaxFocalPlanes] = {2, 10, 20, 40, 80, 160};
    for (int i = 0; i < kMaxFocalPlanes; ++i)
        d.number(depth_name(i).c_str(), ("Depth " + std::to_string(i + 1)).c_str(), depth_defaults[i], 1e-6, 1e9, 0.1, 100,
                 "A depth that is exactly in focus (scene units)");
    d.number("max_blur", "Max Blur Between (px)", def.max_blur, 0, 1000, 0, 64, "The blur the ramps between planes reach (pixels)");
    d.number("slope", "Slope (px/unit)", def.slope, 0, 1e6, 0, 50,
             "Ramp steepness in pixels per scene unit; 0: the ramps meet half way between planes");
    d.choice("interpolation", "Interpolation", kInterpolations, 1, "Ramp shape (focal planes and region falloff)");

    d.group("grp_region", "Region");
    d.set_group("grp_region");
    d.choice("shape", "Shape", kShapes, 0, "sphere (center, radius), box (center, size), plane (center, normal, thickness)");
    d.choice("mode", "Mode", kModes, 0, "focus: sharp inside, blurred outside; blur: blurred inside");
    d.point3("center", "Center", def.center, "World position of the shape (a point on the plane)");
    d.number("radius", "Radius", def.radius, 0, 1e9, 0, 10, "Sphere radius (scene units)");
    d.point3("size", "Size", def.size, "Box edge lengths (scene units)");
    d.point3("normal", "Normal", def.normal, "Plane normal");
    d.number("thickness", "Thickness", def.thickness, 0, 1e9, 0, 10, "Plane slab thickness (scene units)");
    d.number("blur", "Blur (px)", def.blur, 0, 1000, 0, 64, "Blur outside (focus) or inside (blur) the shape, pixels");
    d.number("falloff", "Falloff", def.falloff, 0, 1e9, 0, 10, "Ramp width outside the surface (scene units)");

    d.group("grp_map", "Blur Map");
    d.set_group("grp_map");
    d.choice("map_channel", "Map Channel", kChannels, 3, "Channel of the Blur Map clip");
    d.number("map_scale", "Map Scale (px)", def.map_scale, 0, 1e6, 0, 64, "Blur in pixels for a map value of 1");

    d.group("grp_depth", "Depth");
    d.set_group("grp_depth");
    d.choice("depth_pass", "Depth Pass", kPasses, 0,
             "depth: one channel of the Depth clip; position: its R, G, B are world positions P.x, P.y, P.z");
    d.choice("depth_channel", "Depth Channel", kChannels, 0, "Channel of the Depth clip holding depth");
    d.choice("depth_encoding", "Depth Encoding", kEncodings, 0,
             "metric (depth = v * scale), inverse (scale / v: 1/Z), scaled (0 = invalid), near_far_linear / "
             "near_far_inverse (normalised 0..1 between near and far)");
    d.number("depth_scale", "Depth Scale", def.depth_scale, 1e-12, 1e12, 0.001, 1000, "metric / scaled / inverse encodings");
    d.number("depth_near", "Depth Near", def.depth_near, 1e-9, 1e12, 0.01, 100, "near_far_* encodings: depth of 0");
    d.number("depth_far", "Depth Far", def.depth_far, 1e-9, 1e12, 0.01, 1000, "near_far_* encodings: depth of 1");

    d.group("grp_diffusion", "Diffusion");
    d.set_group("grp_diffusion");
    d.choice("solver", "Solver", kSolvers, option_index(kSolvers, def.solver),
             "auto: per layer, the faster of the two for its blur; adi: cost independent of the blur; explicit: the paper's reference");
    d.integer("adi_steps", "ADI Steps", 0, 0, 1000, "ADI sub-steps (quality); 0: automatic");
    d.boolean("pyramid", "Pyramid", def.pyramid,
              "on (default): blurs above 6 px solved on coarser levels and blended per pixel, many times faster "
              "(as the CLI's --pyramid on); off: every layer at full resolution (the reference)");
    d.integer("layers", "Layers", 0, 0, 1024, "Depth layers: 0 = automatic (split at depth gaps), N = N slices even in 1/depth");
    d.boolean("cut_by_blur", "Cut Layers by Blur", true,
              "Automatic layers only: also cut by blur, so a blurred object in front of a sharper part of a "
              "continuous depth range (a ground plane) spreads over it (plates under diffusion: at such "
              "silhouettes only; the "
              "default, as the CLI's --layers auto); off: cut at depth gaps only (--layers auto:gaps)");
    d.choice("analysis", "Layer Analysis", kAnalyses, 0,
             "frame: layers and blur are analysed on the whole source frame, so tiles match the full render; "
             "region: only the render region plus the blur margin is read (faster on large plates, tiles may differ "
             "slightly at layer edges)");
    d.set_group("");

    d.group("grp_bokeh", "Filter and Aperture");
    d.set_group("grp_bokeh");
    d.choice("filter", "Filter", kFilters, 0,
             "diffusion: each layer blurred by the heat equation (a Gaussian point-spread function); bokeh: each "
             "layer spread over the aperture's shape (discs, polygons, an image), with the same layers and "
             "visibility (the CLI's --bokeh); vibrate: method 4, the generalized PSF field: the layers moved per "
             "aperture sample by the PSF field's displacement, composited with visibility and averaged (the CLI's "
             "--vibrate)");
    const Aperture a;
    d.choice("aperture", "Aperture", kApertures, 0,
             "bokeh: the iris shape; vibrate: the domain of the aperture samples; image takes the Aperture clip "
             "(grey or colour) as the kernel");
    d.integer("blades", "Blades", a.blades, 3, 64, "polygon: the number of blades");
    d.number("rotation", "Rotation (deg)", a.rotation_deg, -360, 360, -180, 180,
             "polygon / image: counter-clockwise turn (0: a polygon vertex points right)");
    d.number("roundness", "Roundness", a.roundness, 0, 1, 0, 1, "polygon: blades bent from straight (0) to a circle (1)");
    d.number("squeeze", "Anamorphic Squeeze", a.squeeze, 0.1, 10, 0.5, 2,
             "the shape's width divided by it (2: the oval bokeh of a 2x anamorphic lens)");
    d.number("cats_eye", "Cat's Eye", a.cats_eye, 0, 1, 0, 1,
             "mechanical vignetting: towards the frame corners the shape is cut into a cat's eye (bokeh, vibrate)");
    d.text("psf_field", "PSF Field File", "", kOfxParamStringIsFilePath,
           "vibrate: the PSF-field JSON (defocus, swirl, depth, image_map, sum, blend; as the CLI's --psf-field); empty: "
           "the defocus field, B(x) times the aperture sample");
    d.integer("psf_samples", "PSF Samples", 0, 0, 65536,
              "vibrate: aperture samples (--psf-samples); 0: the file's \"samples\", else automatic from the largest "
              "displacement");
    d.set_group("");
}

DefocusParams read_defocus_params(const ParamReader& r) {
    DefocusParams p;
    p.kind = r.option("kind", kKinds);
    p.max_radius = r.number("max_radius");
    p.focal_length_mm = r.number("focal_length_mm");
    p.sensor_width_mm = r.number("sensor_width_mm");
    p.f_number = r.number("f_number");
    p.focus_distance = r.number("focus_distance");
    p.use_focus_at = r.boolean("use_focus_at");
    p.focus_at = r.point2("focus_at");
    p.scene_unit_mm = r.number("scene_unit_mm");
    const int n = r.integer("depths_count");
    if (n < 1 || n > kMaxFocalPlanes)
        fail("parameter 'depths_count': must be 1.." + std::to_string(kMaxFocalPlanes) + ", got " + std::to_string(n));
    for (int i = 0; i < n; ++i) p.depths.push_back(r.number(depth_name(i).c_str()));
    p.max_blur = r.number("max_blur");
    p.slope = r.number("slope");
    p.interpolation = r.option("interpolation", kInterpolations);
    p.shape = r.option("shape", kShapes);
    p.mode = r.option("mode", kModes);
    p.center = r.point3("center");
    p.radius = r.number("radius");
    p.size = r.point3("size");
    p.normal = r.point3("normal");
    p.thickness = r.number("thickness");
    p.blur = r.number("blur");
    p.falloff = r.number("falloff");
    p.map_channel = r.option("map_channel", kChannels);
    p.map_scale = r.number("map_scale");
    p.depth_pass = r.option("depth_pass", kPasses);
    p.depth_channel = r.option("depth_channel", kChannels);
    p.depth_encoding = r.option("depth_encoding", kEncodings);
    p.depth_scale = r.number("depth_scale");
    p.depth_near = r.number("depth_near");
    p.depth_far = r.number("depth_far");
    p.solver = r.option("solver", kSolvers);
    p.adi_steps = r.integer("adi_steps");
    p.pyramid = r.boolean("pyramid");
    p.layers = r.integer("layers");
    p.cut_by_blur = r.boolean("cut_by_blur");
    p.analysis = r.option("analysis", kAnalyses);
    p.filter = r.option("filter", kFilters);
    p.aperture = r.option("aperture", kApertures);
    p.blades = r.integer("blades");
    p.rotation = r.number("rotation");
    p.roundness = r.number("roundness");
    p.squeeze = r.number("squeeze");
    p.cats_eye = r.number("cats_eye");
    p.psf_field = r.text("psf_field");
    p.psf_samples = r.integer("psf_samples");
    return p;
}

std::string blur_field_json(const DefocusParams& p, double scale) {
    using json = nlohmann::json;
    auto vec = [](const std::array<double, 3>& v) { return json::array({v[0], v[1], v[2]}); };
    json node;
    node["kind"] = p.kind;
    if (p.kind == "thin_lens") {
        node["focal_length_mm"] = p.focal_length_mm;
        node["f_number"] = p.f_number;
        node["focus_distance"] = p.focus_distance;
        node["sensor_width_mm"] = p.sensor_width_mm;
        node["scene_unit_mm"] = p.scene_unit_mm;
    } else if (p.kind == "focal_planes") {
        node["depths"] = p.depths;
        node["max_blur"] = p.max_blur * scale;
        if (p.slope > 0) node["slope"] = p.slope * scale;
        node["interpolation"] = p.interpolation;
    } else if (p.kind == "region") {
        node["shape"] = p.shape;
        node["mode"] = p.mode;
        node["blur"] = p.blur * scale;
        node["falloff"] = p.falloff;
        node["interpolation"] = p.interpolation;
        if (p.shape == "sphere") {
            node["center"] = vec(p.center);
            node["radius"] = p.radius;
        } else if (p.shape == "box") {
            node["center"] = vec(p.center);
            node["size"] = vec(p.size);
        } else {
            node["point"] = vec(p.center);
            node["normal"] = vec(p.normal);
            node["thickness"] = p.thickness;
        }
    } else {  // image_map
        node["image"] = "blur_map";
        node["channel"] = p.map_channel;
        node["scale"] = p.map_scale * scale;
    }
    json top;
    top["blurfield"] = node;
    top["max_radius"] = max_radius_px(p, scale);
    return top.dump();
}

LensOverrides lens_overrides(const DefocusParams& p) {
    LensOverrides o;
    o.focal_length_mm = p.focal_length_mm;
    o.sensor_width_mm = p.sensor_width_mm;
    o.f_number = p.f_number;
    o.focus_distance = p.focus_distance;
    o.scene_unit_mm = p.scene_unit_mm;
    return o;
}

Result<DefocusOptions> defocus_settings(const DefocusParams& p) {
    DefocusOptions s;
    auto solver = parse_diffusion_solver(p.solver.c_str());
    if (!solver) return solver.status().prefix("parameter 'solver'");
    s.diffusion.solver = *solver;
    s.diffusion.adi_steps = p.adi_steps;
    s.diffusion.pyramid = p.pyramid;
    auto split = parse_layer_split(p.layers > 0 ? std::to_string(p.layers) : std::string(p.cut_by_blur ? "auto" : "auto:gaps"));
    if (!split) return split.status().prefix("parameter 'layers'");
    s.split = *split;
    s.filter = p.filter == "bokeh" ? DefocusFilter::Bokeh : p.filter == "vibrate" ? DefocusFilter::Vibrate : DefocusFilter::Diffusion;
    s.aperture.kind = p.aperture == "polygon" ? Aperture::Kind::Polygon
                      : p.aperture == "image" ? Aperture::Kind::Image : Aperture::Kind::Disc;
    s.aperture.blades = p.blades;
    s.aperture.rotation_deg = p.rotation;
    s.aperture.roundness = p.roundness;
    s.aperture.squeeze = p.squeeze;
    s.aperture.cats_eye = p.cats_eye;
    if (s.filter == DefocusFilter::Vibrate) {
        if (p.psf_samples < 0 || p.psf_samples > 65536)
            return Status::error("parameter 'psf_samples': must be 0 (automatic) to 65536, got " + std::to_string(p.psf_samples),
                                 StatusCode::InvalidArgument, "psf_samples");
        s.vibrate.samples = p.psf_samples;
        if (!p.psf_field.empty()) {
            auto field = io::read_psf_field(p.psf_field);
            if (!field) return field.status().prefix("parameter 'psf_field'");
            s.psf_field = std::move(field).value();
        }
    }
    s.source.depth_channel = "Z";
    if (p.depth_pass == "position") {
        s.source.position_channels = "P";  // Z is computed from P: metric
        return s;
    }
    auto enc = parse_depth_encoding(p.depth_encoding);
    if (!enc) return enc.status().prefix("parameter 'depth_encoding'");
    s.source.depth_decode.encoding = *enc;
    s.source.depth_decode.scale = p.depth_scale;
    s.source.depth_decode.near = p.depth_near;
    s.source.depth_decode.far = p.depth_far;
    if (Status st = s.source.depth_decode.validate(); !st) return st.prefix("parameters depth_scale / depth_near / depth_far");
    return s;
}

}  // namespace gdof::ofx
