// Scene JSON -> gdof::Scene (format: docs/scene.md), read with json_read.
// Meshes are read and flattened to world space here.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>

#include "gdof/scene.h"
#include "gdof/text_file.h"
#include "common/json_read.h"

namespace gdof {

namespace {

namespace fs = std::filesystem;

using json_read::Object;
using json_read::Value;
using json_read::fail;

// One number for all three components, or [x, y, z].
Vec3 uniform_or_vec3(const Value& v) {
    if (!v.raw().is_number()) return v.vec3();
    const double d = v.number();
    return {d, d, d};
}

// A colour: [r, g, b] or one number for grey; every value in 0..kMaxSceneColour.
Vec3 colour(const Value& v) {
    const Vec3 c = uniform_or_vec3(v);
    if (c.x < 0 || c.y < 0 || c.z < 0) v.fail("must be >= 0");
    if (std::max({c.x, c.y, c.z}) > kMaxSceneColour)
        v.fail("must be <= 1e20 (the float beauty would overflow), got " + v.raw().dump());
    return c;
}

// camera.aperture: the CLI form ("polygon:6:15,roundness=0.2") or an
// object with the same names (shape, blades, rotation, roundness, squeeze,
// cats_eye, image). An image path is resolved against the scene's folder;
// the front end reads it.
Aperture parse_aperture_value(const Value& v, const std::string& base_dir) {
    Aperture a;
    if (v.raw().is_string()) {
        auto r = parse_aperture(v.string());
        if (!r) v.fail(r.message());
        a = std::move(r).value();
    } else {
        const Object o = v.object({"shape", "blades", "rotation", "roundness", "squeeze", "cats_eye", "image"}, {"shape"});
        const std::string shape = o.get("shape").choice({"disc", "polygon", "image"});
        a.kind = shape == "disc" ? Aperture::Kind::Disc : shape == "polygon" ? Aperture::Kind::Polygon : Aperture::Kind::Image;
        if (const auto x = o.find("blades")) a.blades = int(std::clamp(x->integer(), -1LL, 1000LL));
        if (const auto x = o.find("rotation")) a.rotation_deg = x->number();
        if (const auto x = o.find("roundness")) a.roundness = x->number();
        if (const auto x = o.find("squeeze")) a.squeeze = x->number();
        if (const auto x = o.find("cats_eye")) a.cats_eye = x->number();
        if (const auto x = o.find("image")) a.image_path = x->string();
        if (a.kind == Aperture::Kind::Image && a.image_path.empty()) o.require("image", "for shape \"image\"");
    }
    if (a.kind != Aperture::Kind::Image) {
        if (Status st = validate(a); !st) {
            const std::string key = st.subject().empty() ? std::string() : st.subject();
            (key.empty() || v.raw().is_string() ? v : Value(v.raw(), json_read::key_path(v.path(), key))).fail(st.message());
        }
    } else if (!a.image_path.empty() && fs::path(a.image_path).is_relative() && !base_dir.empty()) {
        a.image_path = (fs::path(base_dir) / a.image_path).string();
    }
    return a;
}

CameraDesc parse_camera(const Value& v) {
    const Object o = v.object({"position", "look_at", "up", "focal_length_mm", "sensor_width_mm", "hfov_deg",
                               "resolution", "f_number", "focus_distance", "scene_unit_mm", "aperture"},
                              {"position", "look_at"});
    CameraDesc d;
    d.position = o.get("position").vec3();
    d.look_at = o.get("look_at").vec3();
    if (const auto x = o.find("up")) d.up = x->vec3();
    if (const auto x = o.find("focal_length_mm")) d.focal_length_mm = x->positive();
    if (const auto x = o.find("sensor_width_mm")) d.sensor_width_mm = x->positive();
    if (const auto x = o.find("hfov_deg")) {
        d.hfov_deg = x->positive();
        if (d.hfov_deg >= 180) x->fail("must be < 180");
    }
    if (const auto x = o.find("resolution")) {
        const json_read::json& r = x->raw();
        if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer() ||
            r[0].get<long>() <= 0 || r[1].get<long>() <= 0 || r[0].get<long>() > 65536 || r[1].get<long>() > 65536)
            x->fail("must be [width, height], positive integers up to 65536");
        d.display_window = {0, 0, r[0].get<int>(), r[1].get<int>()};
    }
    if (const auto x = o.find("f_number")) d.f_number = x->positive();
    if (const auto x = o.find("focus_distance")) d.focus_distance = x->positive();
    if (const auto x = o.find("scene_unit_mm")) d.scene_unit_mm = x->positive();
    Vec3 fwd = d.look_at - d.position;
    if (length(fwd) <= 0) fail("camera.look_at", "must differ from camera.position");
    if (length(cross(normalize(fwd), d.up)) < 1e-9) fail("camera.up", "must not be parallel to the viewing direction");
    return d;
}

Material parse_material(const Value& v, const std::string& name) {
    const Object o = v.object({"kd", "ke"});
    Material m;
    m.name = name;
    if (const auto x = o.find("kd")) m.kd = colour(*x);
    if (const auto x = o.find("ke")) m.ke = colour(*x);
    return m;
}

// Local -> world: scale, then rotate about x, y, z (degrees), then translate.
struct Transform {
    Vec3 scale{1, 1, 1}, rotate_deg{0, 0, 0}, translate{0, 0, 0};
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // column vectors: p' = R p

    void build() {
        auto rot = [](int axis, double deg, double m[3][3]) {
            double a = deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
            int i = (axis + 1) % 3, k = (axis + 2) % 3;
            double t[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
            t[i][i] = c, t[i][k] = -s, t[k][i] = s, t[k][k] = c;
            double out[3][3];
            for (int a1 = 0; a1 < 3; ++a1)
                for (int b = 0; b < 3; ++b) {
                    out[a1][b] = 0;
                    for (int q = 0; q < 3; ++q) out[a1][b] += t[a1][q] * m[q][b];
                }
            for (int a1 = 0; a1 < 3; ++a1)
                for (int b = 0; b < 3; ++b) m[a1][b] = out[a1][b];
        };
        rot(0, rotate_deg.x, r);
        rot(1, rotate_deg.y, r);
        rot(2, rotate_deg.z, r);
    }
    Vec3 apply_r(const Vec3& p) const {
        return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z, r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z,
                r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z};
    }
    Vec3 point(const Vec3& p) const { return apply_r({p.x * scale.x, p.y * scale.y, p.z * scale.z}) + translate; }
    // Normals: inverse transpose (rotation is orthonormal, so R * S^-1).
    Vec3 normal(const Vec3& n) const {
        Vec3 m = apply_r({n.x / scale.x, n.y / scale.y, n.z / scale.z});
        double l = length(m);
        return l > 0 ? m / l : m;
    }
};

struct Builder {
    Scene scene;
    std::string base_dir;
    std::map<std::string, std::uint32_t> named;  // scene material name -> index

    std::uint32_t add_material(const Material& m) {
        scene.materials.push_back(m);
        return std::uint32_t(scene.materials.size() - 1);
    }

    void parse_mesh(const Value& item) {
        const Object o = item.object({"file", "name", "translate", "rotate_deg", "scale", "material"});
        const std::string& key = o.path();
        std::string file = o.get("file", "the OBJ file to load").string();
        fs::path p(file);
        if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
        if (!fs::exists(p)) fail(o.path("file"), "mesh file '" + p.string() + "' not found", StatusCode::NotFound);
        Transform xf;
        if (const auto x = o.find("translate")) xf.translate = x->vec3();
        if (const auto x = o.find("rotate_deg")) xf.rotate_deg = x->vec3();
        if (const auto x = o.find("scale")) {
            xf.scale = uniform_or_vec3(*x);
            if (xf.scale.x == 0 || xf.scale.y == 0 || xf.scale.z == 0) x->fail("must not be 0");
        }
        xf.build();
        std::optional<std::uint32_t> override_mat;
        if (const auto m = o.find("material")) {
            if (m->raw().is_string()) {
                const std::string name = m->string();
                auto it = named.find(name);
                if (it == named.end()) m->fail("no material '" + name + "' in materials", StatusCode::NotFound);
                override_mat = it->second;
            } else {
                override_mat = add_material(parse_material(*m, key));
            }
        }
        Result<ObjModel> obj = load_obj(p.string());
        if (!obj) fail(o.path("file"), obj.status());
        const ObjModel& model = obj.value();

        // Materials of this OBJ, added once.
        std::vector<std::uint32_t> mat_index;
        std::optional<std::uint32_t> default_mat;
        if (!override_mat)
            for (const Material& m : model.materials) mat_index.push_back(add_material(m));

        TriangleMesh mesh;
        const auto name = o.find("name");
        std::string label = name && name->raw().is_string() ? name->string() : p.filename().string();
        mesh.name = key + " (" + label + ")";
        const std::size_t nv = model.positions.size() / 3;
        mesh.positions.resize(model.positions.size());
        for (std::size_t v = 0; v < nv; ++v) {
            Vec3 w = xf.point({model.positions[3 * v], model.positions[3 * v + 1], model.positions[3 * v + 2]});
            mesh.positions[3 * v] = float(w.x), mesh.positions[3 * v + 1] = float(w.y),
            mesh.positions[3 * v + 2] = float(w.z);
        }
        bool any_normals = false;
        for (const ObjModel::Shape& s : model.shapes)
            for (int n : s.normal) any_normals |= n >= 0;
        for (const ObjModel::Shape& s : model.shapes) {
            scene.object_names.push_back(label + (s.name.empty() ? "" : ":" + s.name));
            const auto oid = std::uint32_t(scene.object_names.size());
            const std::size_t nt = s.vertex.size() / 3;
            for (std::size_t t = 0; t < nt; ++t) {
                Vec3 c[3];
                for (int k = 0; k < 3; ++k) {
                    mesh.indices.push_back(std::uint32_t(s.vertex[3 * t + std::size_t(k)]));
                    c[k] = mesh.vertex(mesh.indices.back());
                }
                Vec3 ng = cross(c[1] - c[0], c[2] - c[0]);
                ng = length(ng) > 0 ? normalize(ng) : Vec3{0, 0, 1};
                if (any_normals)
                    for (int k = 0; k < 3; ++k) {
                        int ni = s.normal[3 * t + std::size_t(k)];
                        Vec3 n = ni < 0 ? ng
                                        : xf.normal({model.normals[3 * std::size_t(ni)], model.normals[3 * std::size_t(ni) + 1],
                                                     model.normals[3 * std::size_t(ni) + 2]});
                        mesh.normals.insert(mesh.normals.end(), {float(n.x), float(n.y), float(n.z)});
                    }
                std::uint32_t mi;
                if (override_mat) mi = *override_mat;
                else if (s.material[t] >= 0) mi = mat_index[std::size_t(s.material[t])];
                else {
                    if (!default_mat) {
                        Material dm;
                        dm.name = "default";
                        default_mat = add_material(dm);
                    }
                    mi = *default_mat;
                }
                mesh.material.push_back(mi);
                mesh.object_id.push_back(oid);
            }
        }
        scene.meshes.push_back(std::move(mesh));
    }

    void parse_light(const Value& v) {
        const Object o = v.object();
        const Value t = o.get("type", "\"point\"");
        const std::string type = t.string();
        if (type != "point") t.fail("unknown light type '" + type + "' (known: point; area lights are emissive materials)");
        o.allow_only({"type", "position", "intensity"});
        PointLight l;
        l.position = o.get("position").vec3();
        if (const auto x = o.find("intensity")) l.intensity = colour(*x);
        scene.point_lights.push_back(l);
    }

    void parse(const Value& root) {
        const Object o = root.object({"camera", "meshes", "materials", "lights", "environment"});
        const Value camera = o.get("camera");
        scene.camera_desc = parse_camera(camera);
        if (camera.raw().contains("aperture"))
            scene.aperture = parse_aperture_value(Value(camera.raw()["aperture"], json_read::key_path("camera", "aperture")), base_dir);
        auto cam = Camera::create(scene.camera_desc);
        if (!cam) camera.fail(cam.message(), cam.status().code());
        scene.camera = cam.value();
        if (const auto ms = o.find("materials")) {
            if (!ms->raw().is_object()) ms->fail("must be an object of name: {kd, ke}");
            const Object materials = ms->object();
            for (const std::string& name : materials.keys())
                named[name] = add_material(parse_material(materials.get(name), name));
        }
        if (const auto x = o.find("environment")) scene.environment = colour(*x);
        for (const Value& m : o.get("meshes", "a non-empty array of meshes").non_empty_array("meshes")) parse_mesh(m);
        if (const auto ls = o.find("lights"))
            for (const Value& l : ls->array()) parse_light(l);
    }
};

}  // namespace

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const TriangleMesh& m : meshes) n += m.triangle_count();
    return n;
}

std::size_t Scene::emissive_triangle_count() const {
    std::size_t n = 0;
    for (const TriangleMesh& m : meshes)
        for (std::uint32_t mi : m.material) n += materials[mi].emissive() ? 1 : 0;
    return n;
}

Result<Scene> parse_scene(std::string_view json_text, const std::string& base_dir, const std::string& source) {
    return json_read::read_document(json_text, source, [&](const Value& root) {
        Builder b;
        b.base_dir = base_dir;
        b.parse(root);
        return std::move(b.scene);
    });
}

Result<Scene> load_scene(const std::string& path) {
    const Result<std::string> text = read_text(path, "scene");
    if (!text) return text.status();
    fs::path dir = fs::path(path).parent_path();
    auto r = parse_scene(text.value(), dir.string(), "scene '" + path + "'");
    if (r) r.value().path = path;
    return r;
}

}  // namespace gdof
