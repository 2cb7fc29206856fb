// Scene JSON -> gdof::Scene (format: docs/scene.md). Meshes are read and
// flattened to world space here.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gdof/scene.h"
#include "common/json_util.h"

namespace gdof {

namespace {

namespace fs = std::filesystem;

using namespace json_util;

void check_keys(const json& j, const std::string& key, const std::set<std::string>& allowed) {
    if (!j.is_object()) fail(key, "must be an object");
    for (auto it = j.begin(); it != j.end(); ++it)
        if (!allowed.count(it.key())) fail(key.empty() ? it.key() : key + "." + it.key(), "unknown key");
}

double number(const json& j, const std::string& key) {
    if (!j.is_number()) fail(key, "must be a number");
    double v = j.get<double>();
    if (!std::isfinite(v)) fail(key, "must be finite");
    return v;
}

double positive(const json& j, const std::string& key) {
    double v = number(j, key);
    if (v <= 0) fail(key, "must be > 0, got " + j.dump());
    return v;
}

Vec3 vec3(const json& j, const std::string& key) {
    if (!j.is_array() || j.size() != 3) fail(key, "must be an array of 3 numbers");
    return {number(j[0], key + "[0]"), number(j[1], key + "[1]"), number(j[2], key + "[2]")};
}

// A colour: [r, g, b] or one number for grey; every value in 0..kMaxSceneColour.
Vec3 colour(const json& j, const std::string& key) {
    Vec3 c = j.is_number() ? Vec3{number(j, key), number(j, key), number(j, key)} : vec3(j, key);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(key, "must be >= 0");
    if (std::max({c.x, c.y, c.z}) > kMaxSceneColour)
        fail(key, "must be <= 1e20 (the float beauty would overflow), got " + j.dump());
    return c;
}

CameraDesc parse_camera(const json& j) {
    check_keys(j, "camera", {"position", "look_at", "up", "focal_length_mm", "sensor_width_mm", "hfov_deg",
                             "resolution", "f_number", "focus_distance", "scene_unit_mm"});
    CameraDesc d;
    if (!j.contains("position")) fail("camera.position", "missing");
    if (!j.contains("look_at")) fail("camera.look_at", "missing");
    d.position = vec3(j["position"], "camera.position");
    d.look_at = vec3(j["look_at"], "camera.look_at");
    if (j.contains("up")) d.up = vec3(j["up"], "camera.up");
    if (j.contains("focal_length_mm")) d.focal_length_mm = positive(j["focal_length_mm"], "camera.focal_length_mm");
    if (j.contains("sensor_width_mm")) d.sensor_width_mm = positive(j["sensor_width_mm"], "camera.sensor_width_mm");
    if (j.contains("hfov_deg")) {
        d.hfov_deg = positive(j["hfov_deg"], "camera.hfov_deg");
        if (d.hfov_deg >= 180) fail("camera.hfov_deg", "must be < 180");
    }
    if (j.contains("resolution")) {
        const json& r = j["resolution"];
        if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer() ||
            r[0].get<long>() <= 0 || r[1].get<long>() <= 0 || r[0].get<long>() > 65536 || r[1].get<long>() > 65536)
            fail("camera.resolution", "must be [width, height], positive integers up to 65536");
        d.display_window = {0, 0, r[0].get<int>(), r[1].get<int>()};
    }
    if (j.contains("f_number")) d.f_number = positive(j["f_number"], "camera.f_number");
    if (j.contains("focus_distance")) d.focus_distance = positive(j["focus_distance"], "camera.focus_distance");
    if (j.contains("scene_unit_mm")) d.scene_unit_mm = positive(j["scene_unit_mm"], "camera.scene_unit_mm");
    Vec3 fwd = d.look_at - d.position;
    if (length(fwd) <= 0) fail("camera.look_at", "must differ from camera.position");
    if (length(cross(normalize(fwd), d.up)) < 1e-9) fail("camera.up", "must not be parallel to the viewing direction");
    return d;
}

Material parse_material(const json& j, const std::string& key, const std::string& name) {
    check_keys(j, key, {"kd", "ke"});
    Material m;
    m.name = name;
    if (j.contains("kd")) m.kd = colour(j["kd"], key + ".kd");
    if (j.contains("ke")) m.ke = colour(j["ke"], key + ".ke");
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

    void parse_mesh(const json& j, std::size_t index) {
        const std::string key = "meshes[" + std::to_string(index) + "]";
        check_keys(j, key, {"file", "name", "translate", "rotate_deg", "scale", "material"});
        if (!j.contains("file") || !j["file"].is_string()) fail(key + ".file", "missing (the OBJ file to load)");
        std::string file = j["file"].get<std::string>();
        fs::path p(file);
        if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
        if (!fs::exists(p)) fail(key + ".file", "mesh file '" + p.string() + "' not found");
        Transform xf;
        if (j.contains("translate")) xf.translate = vec3(j["translate"], key + ".translate");
        if (j.contains("rotate_deg")) xf.rotate_deg = vec3(j["rotate_deg"], key + ".rotate_deg");
        if (j.contains("scale")) {
            const json& s = j["scale"];
            xf.scale = s.is_number() ? Vec3{number(s, key + ".scale"), number(s, key + ".scale"),
                                            number(s, key + ".scale")}
                                     : vec3(s, key + ".scale");
            if (xf.scale.x == 0 || xf.scale.y == 0 || xf.scale.z == 0) fail(key + ".scale", "must not be 0");
        }
        xf.build();
        std::optional<std::uint32_t> override_mat;
        if (j.contains("material")) {
            const json& m = j["material"];
            if (m.is_string()) {
                auto it = named.find(m.get<std::string>());
                if (it == named.end()) fail(key + ".material", "no material '" + m.get<std::string>() + "' in materials");
                override_mat = it->second;
            } else {
                override_mat = add_material(parse_material(m, key + ".material", key));
            }
        }
        Result<ObjModel> obj = load_obj(p.string());
        if (!obj) fail(key + ".file", obj.message());
        const ObjModel& model = obj.value();

        // Materials of this OBJ, added once.
        std::vector<std::uint32_t> mat_index;
        std::optional<std::uint32_t> default_mat;
        if (!override_mat)
            for (const Material& m : model.materials) mat_index.push_back(add_material(m));

        TriangleMesh mesh;
        std::string label = j.contains("name") && j["name"].is_string() ? j["name"].get<std::string>()
                                                                         : p.filename().string();
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

    void parse_light(const json& j, std::size_t index) {
        const std::string key = "lights[" + std::to_string(index) + "]";
        if (!j.is_object()) fail(key, "must be an object");
        if (!j.contains("type") || !j["type"].is_string()) fail(key + ".type", "missing (\"point\")");
        const std::string type = j["type"].get<std::string>();
        if (type != "point") fail(key + ".type", "unknown light type '" + type + "' (known: point; area lights are emissive materials)");
        check_keys(j, key, {"type", "position", "intensity"});
        PointLight l;
        if (!j.contains("position")) fail(key + ".position", "missing");
        l.position = vec3(j["position"], key + ".position");
        if (j.contains("intensity")) l.intensity = colour(j["intensity"], key + ".intensity");
        scene.point_lights.push_back(l);
    }

    void parse(const json& root) {
        check_keys(root, "", {"camera", "meshes", "materials", "lights", "environment"});
        if (!root.contains("camera")) fail("camera", "missing");
        scene.camera_desc = parse_camera(root["camera"]);
        auto cam = Camera::create(scene.camera_desc);
        if (!cam) fail("camera", cam.message());
        scene.camera = cam.value();
        if (root.contains("materials")) {
            const json& ms = root["materials"];
            if (!ms.is_object()) fail("materials", "must be an object of name: {kd, ke}");
            for (auto it = ms.begin(); it != ms.end(); ++it)
                named[it.key()] = add_material(parse_material(it.value(), "materials." + it.key(), it.key()));
        }
        if (root.contains("environment")) scene.environment = colour(root["environment"], "environment");
        if (!root.contains("meshes") || !root["meshes"].is_array() || root["meshes"].empty())
            fail("meshes", "missing (a non-empty array of meshes)");
        for (std::size_t i = 0; i < root["meshes"].size(); ++i) parse_mesh(root["meshes"][i], i);
        if (root.contains("lights")) {
            if (!root["lights"].is_array()) fail("lights", "must be an array");
            for (std::size_t i = 0; i < root["lights"].size(); ++i) parse_light(root["lights"][i], i);
        }
    }
};

// "line L, column C" for a byte offset into the text.
std::string line_col(std::string_view text, std::size_t byte) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') ++line, col = 1;
        else ++col;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

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
    json root;
    try {
        root = json::parse(json_text.begin(), json_text.end());
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        auto pos = what.find("syntax error");
        return Status::error(source + ": malformed JSON at " + line_col(json_text, e.byte > 0 ? e.byte - 1 : 0) +
                             (pos != std::string::npos ? ": " + what.substr(pos) : std::string()));
    }
    Builder b;
    b.base_dir = base_dir;
    try {
        b.parse(root);
    } catch (const JsonError& e) {
        return Status::error(source + ": " + e.message);
    } catch (const json::exception& e) {
        return Status::error(source + ": " + e.what());
    }
    return std::move(b.scene);
}

Result<Scene> load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Status::error("scene '" + path + "': cannot be opened");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    fs::path dir = fs::path(path).parent_path();
    auto r = parse_scene(text, dir.string(), "scene '" + path + "'");
    if (r) r.value().path = path;
    return r;
}

}  // namespace gdof
