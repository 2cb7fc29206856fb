// Scene JSON parsing, OBJ loading (quads, negative indices, MTL) and errors.
#include <cmath>

#include "gdof/scene.h"
#include "scene_test_helpers.h"

using namespace gdof;
using gdof::test::ScratchDir;
using gdof::test::write_file;

namespace {

Result<Scene> parse_in(const ScratchDir& dir, const std::string& json) {
    write_file(dir.file("scene.json"), json);
    return load_scene(dir.file("scene.json"));
}

}  // namespace

TEST(scene_parse, plane_scene_flattens_to_world) {
    ScratchDir dir;
    gdof::test::write_quad_obj(dir);
    auto r = parse_in(dir, gdof::test::plane_scene_json());
    ASSERT_TRUE(r) << r.message();
    const Scene& s = r.value();
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.triangle_count(), 3u);          // quad -> 2, plus the lamp triangle
    EXPECT_EQ(s.emissive_triangle_count(), 1u);  // Ke from the MTL
    EXPECT_EQ(s.object_names.size(), 2u);
    EXPECT_EQ(s.camera.image_width(), 32);
    EXPECT_EQ(s.camera.image_height(), 24);
    // Transform: scale (10, 10, 1), rotate 10 deg about z, translate z -1.
    const TriangleMesh& m = s.meshes[0];
    const Vec3 v0 = m.vertex(0);  // (-1, -1, 0) local
    const double a = 10 * std::acos(-1.0) / 180;
    EXPECT_NEAR(v0.x, -10 * std::cos(a) + 10 * std::sin(a), 1e-5);
    EXPECT_NEAR(v0.y, -10 * std::sin(a) - 10 * std::cos(a), 1e-5);
    EXPECT_NEAR(v0.z, -1, 1e-6);
    EXPECT_EQ(s.materials[m.material[0]].name, "grey");
    EXPECT_NEAR(s.materials[m.material[0]].kd.x, 0.5, 1e-6);
    ASSERT_EQ(s.point_lights.size(), 1u);
    EXPECT_EQ(s.point_lights[0].intensity.y, 20);
    EXPECT_NEAR(s.environment.z, 0.1, 1e-12);
}

TEST(scene_parse, material_override_and_named_materials) {
    ScratchDir dir;
    gdof::test::write_quad_obj(dir);
    auto r = parse_in(dir, R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]},
        "materials": {"red": {"kd": [0.9, 0.1, 0.1]}},
        "meshes": [{"file": "quad.obj", "material": "red"}, {"file": "quad.obj", "material": {"ke": 2}}]})");
    ASSERT_TRUE(r) << r.message();
    const Scene& s = r.value();
    for (std::uint32_t mi : s.meshes[0].material) EXPECT_EQ(s.materials[mi].name, "red");
    for (std::uint32_t mi : s.meshes[1].material) EXPECT_EQ(s.materials[mi].ke.x, 2);
    EXPECT_EQ(s.emissive_triangle_count(), 3u);
}

TEST(scene_parse, hfov_and_lens) {
    ScratchDir dir;
    gdof::test::write_quad_obj(dir);
    auto r = parse_in(dir, R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "hfov_deg": 60,
        "resolution": [100, 50], "f_number": 2, "focus_distance": 5}, "meshes": [{"file": "quad.obj"}]})");
    ASSERT_TRUE(r) << r.message();
    EXPECT_NEAR(r->camera.hfov_deg(), 60, 1e-9);
    EXPECT_EQ(r->camera.lens().f_number, 2);
    EXPECT_EQ(r->camera.lens().focus_distance, 5);
}

TEST(scene_parse, errors_name_the_key) {
    ScratchDir dir;
    gdof::test::write_quad_obj(dir);
    const std::string cam = R"("camera": {"position": [0,0,5], "look_at": [0,0,0]})";
    const std::vector<std::pair<std::string, std::string>> list = {
        {R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov": 3}, "meshes": [{"file": "quad.obj"}]})",
         "camera.fov: unknown key"},
        {R"({"camera": {"position": [0,0,5], "look_at": [0,0,5]}, "meshes": [{"file": "quad.obj"}]})",
         "camera.look_at: must differ"},
        {R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "up": [0,0,1]}, "meshes": [{"file": "quad.obj"}]})",
         "camera.up"},
        {R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "resolution": [0, 3]}, "meshes": [{"file": "quad.obj"}]})",
         "camera.resolution"},
        {R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "focal_length_mm": -1}, "meshes": [{"file": "quad.obj"}]})",
         "camera.focal_length_mm: must be > 0"},
        {"{" + cam + R"(, "meshes": [{"file": "missing.obj"}]})", "meshes[0].file: mesh file '"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj", "scale": 0}]})", "meshes[0].scale"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj", "material": "nope"}]})", "meshes[0].material: no material 'nope'"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj", "colour": 1}]})", "meshes[0].colour: unknown key"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj"}], "lights": [{"type": "spot"}]})",
         "lights[0].type: unknown light type 'spot'"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj"}], "lights": [{"type": "point"}]})", "lights[0].position: missing"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj"}], "environment": [1, -1, 0]})", "environment: must be >= 0"},
        {"{" + cam + R"(, "meshes": []})", "meshes: must be a non-empty array of meshes"},
        {"{" + cam + "}", "meshes: missing required key"},
        {R"({"meshes": [{"file": "quad.obj"}]})", "camera: missing"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj"}], "lights": [{"type": "point", "position": [0,0,1], "intensity": 1e300}]})",
         "lights[0].intensity: must be <= 1e20"},
        {"{" + cam + R"(, "meshes": [{"file": "quad.obj"}], "extra": 1})", "extra: unknown key"},
    };
    for (const auto& [json, expect] : list) {
        auto r = parse_in(dir, json);
        ASSERT_FALSE(r) << json;
        EXPECT_NE(r.message().find(expect), std::string::npos) << "got: " << r.message() << "\nwanted: " << expect;
        EXPECT_NE(r.message().find("scene.json"), std::string::npos) << r.message();
    }
}

TEST(scene_parse, malformed_json_names_line_and_column) {
    ScratchDir dir;
    auto r = parse_in(dir, "{\n  \"camera\": {\n    \"position\": [0, 0, 5],,\n  }\n}\n");
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("line 3"), std::string::npos) << r.message();
}

TEST(scene_parse, missing_scene_file) {
    auto r = load_scene("/nonexistent/gdof/scene.json");
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("/nonexistent/gdof/scene.json"), std::string::npos);
}

TEST(scene_obj, nan_vertex_and_bad_index_are_errors) {
    ScratchDir dir;
    write_file(dir.file("nan.obj"), "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    auto r = load_obj(dir.file("nan.obj"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find("nan.obj"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("line 2: vertex"), std::string::npos) << r.message();

    write_file(dir.file("range.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    auto r2 = load_obj(dir.file("range.obj"));
    ASSERT_FALSE(r2);
    EXPECT_NE(r2.message().find("range.obj"), std::string::npos) << r2.message();

    write_file(dir.file("empty.obj"), "# nothing\nv 0 0 0\n");
    auto r3 = load_obj(dir.file("empty.obj"));
    ASSERT_FALSE(r3);
    EXPECT_NE(r3.message().find("no faces"), std::string::npos) << r3.message();

    auto r4 = load_obj(dir.file("absent.obj"));
    ASSERT_FALSE(r4);
    EXPECT_NE(r4.message().find("absent.obj"), std::string::npos) << r4.message();
}

TEST(scene_obj, quads_and_negative_indices) {
    ScratchDir dir;
    gdof::test::write_quad_obj(dir);
    auto r = load_obj(dir.file("quad.obj"));
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->shapes.size(), 2u);
    EXPECT_EQ(r->shapes[0].name, "plane");
    ASSERT_EQ(r->shapes[0].vertex.size(), 6u);
    // (-4 -3 -2 -1) = (1 2 3 4): two triangles over vertices 0..3, each used.
    std::vector<int> used(4, 0);
    for (int v : r->shapes[0].vertex) {
        ASSERT_GE(v, 0);
        ASSERT_LT(v, 4);
        ++used[std::size_t(v)];
    }
    for (int u : used) EXPECT_GE(u, 1);
    EXPECT_EQ(r->shapes[1].vertex, (std::vector<int>{4, 5, 6}));
    ASSERT_EQ(r->materials.size(), 2u);
    EXPECT_TRUE(r->materials[1].emissive());
}
