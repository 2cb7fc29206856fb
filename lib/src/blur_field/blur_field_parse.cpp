// BlurField JSON parser: {"blurfield": {...}, "max_radius": ...}.
// Every error names the key path; malformed JSON reports line and column.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "blur_field/blur_field_nodes.h"
#include "common/json_util.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using namespace json_util;
const auto& num_str = format_number;

// One JSON object being read: checks key names up front and types/values per key.
class Obj {
public:
    Obj(const json& j, std::string path) : j_(j), path_(std::move(path)) {
        if (!j.is_object()) fail(path_, "must be an object, got " + type_name(j));
    }
    const std::string& path() const { return path_; }
    std::string key_path(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
    bool has(const std::string& k) const { return j_.contains(k); }
    const json& at(const std::string& k) const { return j_.at(k); }

    // Every key must be in `allowed` (what = "a thin_lens blur field" etc.).
    void allow_only(const std::vector<std::string>& allowed, const std::string& what) const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
                fail(key_path(it.key()), "unknown key for " + what + " (allowed: " + join(allowed) + ")");
    }
    void require(const std::string& k, const std::string& why = "") const {
        if (!has(k)) fail(key_path(k), "missing required key" + (why.empty() ? "" : " (" + why + ")"));
    }

    double number(const std::string& k) const {
        require(k);
        return to_number(at(k), key_path(k));
    }
    double number_or(const std::string& k, double def) const { return has(k) ? to_number(at(k), key_path(k)) : def; }

    std::string string(const std::string& k) const {
        require(k);
        const json& v = at(k);
        if (!v.is_string()) fail(key_path(k), "must be a string, got " + type_name(v));
        return v.get<std::string>();
    }
    std::string choice(const std::string& k, const std::vector<std::string>& options, const std::string& def) const {
        if (!has(k)) return def;
        const std::string s = string(k);
        if (std::find(options.begin(), options.end(), s) == options.end())
            fail(key_path(k), "must be one of " + join(options) + ", got \"" + s + "\"");
        return s;
    }
    Vec3 vec3(const std::string& k) const {
        require(k);
        return to_vec3(at(k), key_path(k));
    }

    static double to_number(const json& v, const std::string& path) {
        if (!v.is_number()) fail(path, "must be a number, got " + type_name(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(path, "must be finite, got " + num_str(d));
        return d;
    }
    static Vec3 to_vec3(const json& v, const std::string& path) {
        if (!v.is_array() || v.size() != 3) fail(path, "must be an array of 3 numbers, got " + type_name(v));
        return {to_number(v[0], path + "[0]"), to_number(v[1], path + "[1]"), to_number(v[2], path + "[2]")};
    }

private:
    const json& j_;
    std::string path_;
};

void check_min(double v, double lo, const std::string& path, bool strict) {
    if (strict ? !(v > lo) : !(v >= lo)) fail(path, std::string("must be ") + (strict ? "> " : ">= ") + num_str(lo) + ", got " + num_str(v));
}

class Parser {
public:
    explicit Parser(const BlurField::Context& ctx) : ctx_(ctx) {}

    bf::NodePtr node(const json& j, const std::string& path) {
        Obj o(j, path);
        const std::string kind = o.string("kind");
        if (kind == "thin_lens") return thin_lens(o);
        if (kind == "focal_planes") return focal_planes(o);
        if (kind == "region") return region(o);
        if (kind == "image_map") return image_map(o);
        if (kind == "min" || kind == "max" || kind == "add" || kind == "mul") return nary(o, kind);
        if (kind == "scale") return scale(o);
        if (kind == "clamp") return clamp(o);
        fail(o.key_path("kind"),
             "unknown kind \"" + kind + "\" (expected thin_lens, focal_planes, region, image_map, min, max, add, mul, scale or clamp)");
    }

private:
    bf::NodePtr thin_lens(const Obj& o) {
        o.allow_only({"kind", "comment", "focal_length_mm", "f_number", "focus_distance", "sensor_width_mm", "scene_unit_mm"},
                     "a thin_lens blur field");
        ThinLens l;
        l.focal_length_mm = o.number("focal_length_mm");
        check_min(l.focal_length_mm, 0, o.key_path("focal_length_mm"), true);
        l.f_number = o.number("f_number");
        check_min(l.f_number, 0, o.key_path("f_number"), true);
        l.focus_distance = o.number("focus_distance");
        check_min(l.focus_distance, 0, o.key_path("focus_distance"), true);
        l.sensor_width_mm = o.number_or("sensor_width_mm", 36.0);
        check_min(l.sensor_width_mm, 0, o.key_path("sensor_width_mm"), true);
        l.scene_unit_mm = o.number_or("scene_unit_mm", 1000.0);
        check_min(l.scene_unit_mm, 0, o.key_path("scene_unit_mm"), true);
        l.image_width_px = 1;
        if (!(l.focus_distance * l.scene_unit_mm > l.focal_length_mm))
            fail(o.key_path("focus_distance"), "must be beyond the focal length (" + num_str(l.focal_length_mm / l.scene_unit_mm) +
                                                   " scene units), got " + num_str(l.focus_distance));
        // Values valid one by one can still overflow together (f_number 1e-300):
        // ThinLens::validate says which combination (its message names the keys).
        if (Status st = l.validate(); !st) fail(o.key_path("f_number"), st.message());
        return bf::make_thin_lens(l);
    }

    bf::NodePtr focal_planes(const Obj& o) {
        o.allow_only({"kind", "comment", "depths", "max_blur", "slope", "interpolation"}, "a focal_planes blur field");
        o.require("depths");
        const json& arr = o.at("depths");
        const std::string dp = o.key_path("depths");
        if (!arr.is_array() || arr.empty()) fail(dp, "must be a non-empty array of depths, got " + type_name(arr));
        bf::FocalPlanesSpec s;
        for (std::size_t i = 0; i < arr.size(); ++i) {
            const std::string p = dp + "[" + std::to_string(i) + "]";
            const double d = Obj::to_number(arr[i], p);
            check_min(d, 0, p, true);
            s.depths.push_back(d);
        }
        std::sort(s.depths.begin(), s.depths.end());
        for (std::size_t i = 1; i < s.depths.size(); ++i)
            if (s.depths[i] == s.depths[i - 1]) fail(dp, "depth " + num_str(s.depths[i]) + " is listed twice");
        s.smooth = o.choice("interpolation", {"linear", "smooth"}, "linear") == "smooth";
        if (!o.has("max_blur") && !o.has("slope")) fail(o.key_path("max_blur"), "missing: give max_blur, slope or both");
        s.max_blur = o.number_or("max_blur", kInf);
        if (o.has("max_blur")) check_min(s.max_blur, 0, o.key_path("max_blur"), false);
        s.slope = o.number_or("slope", 0.0);
        if (o.has("slope")) check_min(s.slope, 0, o.key_path("slope"), true);
        if (!o.has("slope") && s.depths.size() == 1)
            fail(o.key_path("slope"), "missing required key (with a single depth, the ramp needs a slope)");
        if (s.smooth && !o.has("max_blur"))
            fail(o.key_path("max_blur"), "missing required key (interpolation \"smooth\" needs max_blur)");
        return bf::make_focal_planes(s);
    }

    bf::NodePtr region(const Obj& o) {
        const std::string shape = o.string("shape");
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
            fail(o.key_path("shape"), "must be one of sphere, box, plane, got \"" + shape + "\"");
        }
        o.allow_only(keys, "a " + shape + " region");
        s.focus_mode = o.choice("mode", {"focus", "blur"}, "focus") == "focus";
        s.blur = o.number("blur");
        check_min(s.blur, 0, o.key_path("blur"), false);
        s.falloff = o.number_or("falloff", 0.0);
        check_min(s.falloff, 0, o.key_path("falloff"), false);
        s.smooth = o.choice("interpolation", {"linear", "smooth"}, "smooth") == "smooth";
        if (s.shape == bf::Shape::Sphere) {
            s.center = o.vec3("center");
            s.radius = o.number("radius");
            check_min(s.radius, 0, o.key_path("radius"), false);
        } else if (s.shape == bf::Shape::Box) {
            const bool minmax = o.has("min") || o.has("max");
            const bool cs = o.has("center") || o.has("size");
            if (minmax && cs) fail(o.path(), "a box takes either min/max or center/size, not both");
            if (!minmax && !cs) fail(o.key_path("center"), "missing: a box needs min/max or center/size");
            if (minmax) {
                const Vec3 lo = o.vec3("min"), hi = o.vec3("max");
                if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z))
                    fail(o.key_path("max"), "must be >= min in every component");
                s.center = (lo + hi) * 0.5;
                s.half_size = (hi - lo) * 0.5;
            } else {
                s.center = o.vec3("center");
                const Vec3 size = o.vec3("size");
                const std::string sp = o.key_path("size");
                check_min(size.x, 0, sp + "[0]", false);
                check_min(size.y, 0, sp + "[1]", false);
                check_min(size.z, 0, sp + "[2]", false);
                s.half_size = size * 0.5;
            }
            if (o.has("rotation_deg")) {
                // Box axes rotated about x, then y, then z (degrees, world axes).
                const Vec3 a = o.vec3("rotation_deg") * (std::numbers::pi / 180.0);
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
            s.point = o.vec3("point");
            const Vec3 n = o.vec3("normal");
            if (!(length(n) > 0)) fail(o.key_path("normal"), "must not be the zero vector");
            s.normal = normalize(n);
            const double t = o.number_or("thickness", 0.0);
            check_min(t, 0, o.key_path("thickness"), false);
            s.half_thickness = 0.5 * t;
        }
        return bf::make_region(s);
    }

    bf::NodePtr image_map(const Obj& o) {
        o.allow_only({"kind", "comment", "image", "channel", "scale"}, "an image_map blur field");
        const std::string ref = o.string("image");
        const double scale = o.number_or("scale", 1.0);
        check_min(scale, 0, o.key_path("scale"), false);
        std::shared_ptr<const Image> img;
        if (auto it = ctx_.images.find(ref); it != ctx_.images.end()) {
            img = it->second;
        } else if (ctx_.load_image) {
            std::filesystem::path p(ref);
            if (p.is_relative() && !ctx_.base_dir.empty()) p = std::filesystem::path(ctx_.base_dir) / p;
            auto r = ctx_.load_image(p.string());
            if (!r) fail(o.key_path("image"), "cannot load \"" + p.string() + "\": " + r.message());
            img = r.value();
        } else {
            fail(o.key_path("image"), "no image named \"" + ref + "\" was supplied (and no image loader is set)");
        }
        if (!img) fail(o.key_path("image"), "image \"" + ref + "\" is null");
        int channel = -1;
        if (o.has("channel")) {
            const std::string name = o.string("channel");
            channel = img->channel_index(name);
            if (channel < 0) {
                std::vector<std::string> names;
                for (const auto& c : img->channels()) names.push_back(c.name);
                fail(o.key_path("channel"), "image \"" + ref + "\" has no channel \"" + name + "\" (channels: " + join(names) + ")");
            }
        } else {
            if (img->nchannels() == 0) fail(o.key_path("image"), "image \"" + ref + "\" has no channels");
            channel = 0;
        }
        if (img->display_window().empty()) fail(o.key_path("image"), "image \"" + ref + "\" has an empty display window");
        return bf::make_image_map(std::move(img), channel, scale, ref);
    }

    bf::NodePtr nary(const Obj& o, const std::string& kind) {
        o.allow_only({"kind", "comment", "children"}, "a " + kind + " blur field");
        o.require("children");
        const json& arr = o.at("children");
        if (!arr.is_array() || arr.empty())
            fail(o.key_path("children"), "must be a non-empty array of blur fields, got " + type_name(arr));
        std::vector<bf::NodePtr> children;
        for (std::size_t i = 0; i < arr.size(); ++i)
            children.push_back(node(arr[i], o.key_path("children") + "[" + std::to_string(i) + "]"));
        const bf::Op op = kind == "min" ? bf::Op::Min : kind == "max" ? bf::Op::Max : kind == "add" ? bf::Op::Add : bf::Op::Mul;
        return bf::make_nary(op, std::move(children));
    }

    bf::NodePtr scale(const Obj& o) {
        o.allow_only({"kind", "comment", "child", "factor"}, "a scale blur field");
        o.require("child");
        const double f = o.number("factor");
        check_min(f, 0, o.key_path("factor"), false);
        return bf::make_scale(node(o.at("child"), o.key_path("child")), f);
    }

    bf::NodePtr clamp(const Obj& o) {
        o.allow_only({"kind", "comment", "child", "min", "max"}, "a clamp blur field");
        o.require("child");
        if (!o.has("min") && !o.has("max")) fail(o.key_path("max"), "missing: give min, max or both");
        const double lo = o.number_or("min", 0.0);
        check_min(lo, 0, o.key_path("min"), false);
        const double hi = o.number_or("max", kInf);
        if (o.has("max")) check_min(hi, lo, o.key_path("max"), false);
        return bf::make_clamp(node(o.at("child"), o.key_path("child")), lo, hi);
    }

    const BlurField::Context& ctx_;
};

// "line L, column C" of the first occurrence of a literal in the text.
std::string locate(std::string_view text, const std::string& literal) {
    const auto pos = text.find(literal);
    if (pos == std::string_view::npos) return {};
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < pos; ++i) {
        if (text[i] == '\n') ++line, col = 1;
        else ++col;
    }
    return " at line " + std::to_string(line) + ", column " + std::to_string(col);
}

}  // namespace

Result<BlurField> BlurField::parse(std::string_view text, const Context& ctx) {
    json j;
    try {
        j = json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
        return Status::error(std::string("blur field JSON: ") + e.what());
    } catch (const json::out_of_range& e) {
        // Number overflow (e.g. 1e400): find the literal for a position.
        std::string msg = e.what();
        std::string where;
        const auto q1 = msg.find('\''), q2 = msg.rfind('\'');
        if (q1 != std::string::npos && q2 > q1) where = locate(text, msg.substr(q1 + 1, q2 - q1 - 1));
        return Status::error("blur field JSON: " + msg + where + " (numbers must be finite)");
    } catch (const json::exception& e) {
        return Status::error(std::string("blur field JSON: ") + e.what());
    }
    try {
        if (!j.is_object()) fail("top level", "must be an object {\"blurfield\": {...}}, got " + type_name(j));
        Obj top(j, "");
        if (!top.has("blurfield") && top.has("kind"))
            fail("blurfield", "missing required key (the file must be {\"blurfield\": {\"kind\": ...}}, "
                              "found a bare blur field object at the top level)");
        top.allow_only({"blurfield", "max_radius", "comment"}, "a blur field file");
        top.require("blurfield");
        double max_radius = kInf;
        if (top.has("max_radius")) {
            max_radius = Obj::to_number(top.at("max_radius"), "max_radius");
            check_min(max_radius, 0, "max_radius", false);
        }
        Parser p(ctx);
        bf::NodePtr root = p.node(top.at("blurfield"), "blurfield");
        if (std::isfinite(max_radius)) root = bf::make_clamp(std::move(root), 0.0, max_radius);
        return BlurField(std::move(root), max_radius);
    } catch (const JsonError& e) {
        return Status::error(e.message);
    } catch (const json::exception& e) {
        return Status::error(std::string("blur field JSON: ") + e.what());
    }
}

}  // namespace gdof
