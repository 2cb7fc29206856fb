// BlurField JSON parser: {"blurfield": {...}, "max_radius": ...}, read with
// json_read (errors name the key path; malformed JSON gives line and column).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "blur_field/blur_field_nodes.h"
#include "blur_field/context_image.h"
#include "common/json_read.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using json_read::Object;
using json_read::Value;
using json_read::check_at_least;
using json_read::check_above;
using json_read::fail;
using json_read::join;
std::string num_str(double v) { return format_number(v); }

// Optional number with a default.
double number_or(const Object& o, const std::string& k, double def) {
    const auto v = o.find(k);
    return v ? v->number() : def;
}

// "interpolation" / "mode": one of `options`, or `def` when absent.
std::string choice_or(const Object& o, const std::string& k, const std::vector<std::string>& options,
                      const std::string& def) {
    const auto v = o.find(k);
    return v ? v->choice(options) : def;
}

class Parser {
public:
    explicit Parser(const BlurField::Context& ctx) : ctx_(ctx) {}

    bf::NodePtr node(const Value& v) {
        const Object o = v.object();
        const std::string kind = o.get("kind").string();
        if (kind == "thin_lens") return thin_lens(o);
        if (kind == "focal_planes") return focal_planes(o);
        if (kind == "region") return region(o);
        if (kind == "image_map") return image_map(o);
        if (kind == "min" || kind == "max" || kind == "add" || kind == "mul") return nary(o, kind);
        if (kind == "scale") return scale(o);
        if (kind == "clamp") return clamp(o);
        fail(o.path("kind"),
             "unknown kind \"" + kind + "\" (expected thin_lens, focal_planes, region, image_map, min, max, add, mul, scale or clamp)");
    }

private:
    bf::NodePtr thin_lens(const Object& o) {
        o.allow_only({"kind", "comment", "focal_length_mm", "f_number", "focus_distance", "sensor_width_mm", "scene_unit_mm"});
        ThinLens l;
        l.focal_length_mm = o.get("focal_length_mm").positive();
        l.f_number = o.get("f_number").positive();
        l.focus_distance = o.get("focus_distance").positive();
        l.sensor_width_mm = number_or(o, "sensor_width_mm", 36.0);
        check_above(l.sensor_width_mm, 0, o.path("sensor_width_mm"));
        l.scene_unit_mm = number_or(o, "scene_unit_mm", 1000.0);
        check_above(l.scene_unit_mm, 0, o.path("scene_unit_mm"));
        l.image_width_px = 1;
        if (!(l.focus_distance * l.scene_unit_mm > l.focal_length_mm))
            fail(o.path("focus_distance"), "must be beyond the focal length (" + num_str(l.focal_length_mm / l.scene_unit_mm) +
                                                   " scene units), got " + num_str(l.focus_distance));
        // Values valid one by one can still overflow together (f_number 1e-300):
        // ThinLens::validate says which combination (its message names the keys).
        if (Status st = l.validate(); !st) fail(o.path("f_number"), st);
        return bf::make_thin_lens(l);
    }

    bf::NodePtr focal_planes(const Object& o) {
        o.allow_only({"kind", "comment", "depths", "max_blur", "slope", "interpolation"});
        const Value depths = o.get("depths");
        bf::FocalPlanesSpec s;
        for (const Value& d : depths.non_empty_array("depths")) s.depths.push_back(d.positive());
        std::sort(s.depths.begin(), s.depths.end());
        for (std::size_t i = 1; i < s.depths.size(); ++i)
            if (s.depths[i] == s.depths[i - 1]) depths.fail("depth " + num_str(s.depths[i]) + " is listed twice");
        s.smooth = choice_or(o, "interpolation", {"linear", "smooth"}, "linear") == "smooth";
        if (!o.has("max_blur") && !o.has("slope"))
            fail(o.path("max_blur"), "missing: give max_blur, slope or both", StatusCode::NotFound);
        s.max_blur = number_or(o, "max_blur", kInf);
        if (o.has("max_blur")) check_at_least(s.max_blur, 0, o.path("max_blur"));
        s.slope = number_or(o, "slope", 0.0);
        if (o.has("slope")) check_above(s.slope, 0, o.path("slope"));
        if (s.depths.size() == 1) o.require("slope", "with a single depth, the ramp needs a slope");
        if (s.smooth) o.require("max_blur", "interpolation \"smooth\" needs max_blur");
        return bf::make_focal_planes(s);
    }

    bf::NodePtr region(const Object& o) {
        const std::string shape = o.get("shape").string();
        std::vector<std::string> keys = {"kind", "comment", "shape", "mode", "blur", "falloff", "interpolation"};
        bf::RegionSpec s;
        if (shape == "sphere") {
            keys.insert(keys.end(), {"center", "radius"});
            s.shape = bf::Shape::Sphere;
        } else if (shape == "box") {
            keys.insert(keys.end(), {"min", "max", "center", "size", "rotation_deg"});
            s.shape = bf::Shape::Box;
        } else if (shape == "plane") {
            keys.insert(keys.end(), {"point", "normal", "thickness"});
            s.shape = bf::Shape::Plane;
        } else {
            o.get("shape").fail("must be one of sphere, box, plane, got \"" + shape + "\"");
        }
        o.allow_only(keys);
        s.focus_mode = choice_or(o, "mode", {"focus", "blur"}, "focus") == "focus";
        s.blur = o.get("blur").non_negative();
        s.falloff = number_or(o, "falloff", 0.0);
        check_at_least(s.falloff, 0, o.path("falloff"));
        s.smooth = choice_or(o, "interpolation", {"linear", "smooth"}, "smooth") == "smooth";
        if (s.shape == bf::Shape::Sphere) {
            s.center = o.get("center").vec3();
            s.radius = o.get("radius").non_negative();
        } else if (s.shape == bf::Shape::Box) {
            const bool minmax = o.has("min") || o.has("max");
            const bool cs = o.has("center") || o.has("size");
            if (minmax && cs) o.fail("a box takes either min/max or center/size, not both");
            if (!minmax && !cs) fail(o.path("center"), "missing: a box needs min/max or center/size", StatusCode::NotFound);
            if (minmax) {
                const Vec3 lo = o.get("min").vec3(), hi = o.get("max").vec3();
                if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z))
                    fail(o.path("max"), "must be >= min in every component");
                s.center = (lo + hi) * 0.5;
                s.half_size = (hi - lo) * 0.5;
            } else {
                s.center = o.get("center").vec3();
                const Vec3 size = o.get("size").vec3();
                const std::string sp = o.path("size");
                check_at_least(size.x, 0, sp + "[0]");
                check_at_least(size.y, 0, sp + "[1]");
                check_at_least(size.z, 0, sp + "[2]");
                s.half_size = size * 0.5;
            }
            if (const auto r = o.find("rotation_deg")) {
                // Box axes rotated about x, then y, then z (degrees, world axes).
                const Vec3 a = r->vec3() * (std::numbers::pi / 180.0);
                auto rot = [&](Vec3 v) {
                    v = {v.x, v.y * std::cos(a.x) - v.z * std::sin(a.x), v.y * std::sin(a.x) + v.z * std::cos(a.x)};
                    v = {v.x * std::cos(a.y) + v.z * std::sin(a.y), v.y, -v.x * std::sin(a.y) + v.z * std::cos(a.y)};
                    v = {v.x * std::cos(a.z) - v.y * std::sin(a.z), v.x * std::sin(a.z) + v.y * std::cos(a.z), v.z};
                    return v;
                };
                s.rot_x = rot({1, 0, 0});
                s.rot_y = rot({0, 1, 0});
                s.rot_z = rot({0, 0, 1});
            }
        } else {
            s.point = o.get("point").vec3();
            const Vec3 n = o.get("normal").vec3();
            if (!(length(n) > 0)) fail(o.path("normal"), "must not be the zero vector");
            s.normal = normalize(n);
            const double t = number_or(o, "thickness", 0.0);
            check_at_least(t, 0, o.path("thickness"));
            s.half_thickness = 0.5 * t;
        }
        return bf::make_region(s);
    }

    bf::NodePtr image_map(const Object& o) {
        o.allow_only({"kind", "comment", "image", "channel", "scale"});
        const std::string ref = o.get("image").string();
        const double scale = number_or(o, "scale", 1.0);
        check_at_least(scale, 0, o.path("scale"));
        std::shared_ptr<const Image> img = blur_field_detail::context_image(ctx_, ref, o.path("image"));
        int channel = -1;
        if (const auto ch = o.find("channel")) {
            const std::string name = ch->string();
            channel = img->channel_index(name);
            if (channel < 0) {
                std::vector<std::string> names;
                for (const auto& c : img->channels()) names.push_back(c.name);
                fail(o.path("channel"), "image \"" + ref + "\" has no channel \"" + name + "\" (channels: " + join(names) + ")",
                     StatusCode::NotFound);
            }
        } else {
            channel = 0;
        }
        return bf::make_image_map(std::move(img), channel, scale, ref);
    }

    bf::NodePtr nary(const Object& o, const std::string& kind) {
        o.allow_only({"kind", "comment", "children"});
        std::vector<bf::NodePtr> children;
        for (const Value& c : o.get("children").non_empty_array("blur fields")) children.push_back(node(c));
        const bf::Op op = kind == "min" ? bf::Op::Min : kind == "max" ? bf::Op::Max : kind == "add" ? bf::Op::Add : bf::Op::Mul;
        return bf::make_nary(op, std::move(children));
    }

    bf::NodePtr scale(const Object& o) {
        o.allow_only({"kind", "comment", "child", "factor"});
        o.require("child");
        const double f = o.get("factor").non_negative();
        return bf::make_scale(node(o.get("child")), f);
    }

    bf::NodePtr clamp(const Object& o) {
        o.allow_only({"kind", "comment", "child", "min", "max"});
        o.require("child");
        if (!o.has("min") && !o.has("max")) fail(o.path("max"), "missing: give min, max or both", StatusCode::NotFound);
        const double lo = number_or(o, "min", 0.0);
        check_at_least(lo, 0, o.path("min"));
        const double hi = number_or(o, "max", kInf);
        if (o.has("max")) check_at_least(hi, lo, o.path("max"));
        return bf::make_clamp(node(o.get("child")), lo, hi);
    }

    const BlurField::Context& ctx_;
};

}  // namespace

Result<BlurField> BlurField::parse(std::string_view text, const Context& ctx) {
    return json_read::read_document(text, "", [&](const Value& root) {
        if (!root.raw().is_object()) root.fail("must be an object {\"blurfield\": {...}}, got " + json_read::type_name(root.raw()));
        const Object top = root.object();
        if (!top.has("blurfield") && top.has("kind"))
            fail("blurfield", "missing required key (the file must be {\"blurfield\": {\"kind\": ...}}, "
                              "found a bare blur field object at the top level)",
                 StatusCode::NotFound);
        top.allow_only({"blurfield", "max_radius", "comment"});
        top.require("blurfield");
        double max_radius = kInf;
        if (const auto m = top.find("max_radius")) max_radius = m->non_negative();
        Parser p(ctx);
        bf::NodePtr root_node = p.node(top.get("blurfield"));
        if (std::isfinite(max_radius)) root_node = bf::make_clamp(std::move(root_node), 0.0, max_radius);
        return BlurField(std::move(root_node), max_radius);
    });
}

}  // namespace gdof
