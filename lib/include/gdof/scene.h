// Scenes for the ray tracer (method 1): a JSON file naming a camera, OBJ
// meshes with their transforms and materials, and lights. docs/scene.md has
// the format, every key and its default.
//
// Everything is flattened to world-space triangle meshes when loaded, so the
// ray tracer (raytrace.h) needs no transforms at render time.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "gdof/aperture.h"
#include "gdof/camera.h"
#include "gdof/export.h"
#include "gdof/math.h"
#include "gdof/status.h"

namespace gdof {

// The largest colour value a scene accepts (JSON colours and intensities, MTL
// Kd / Ke). The beauty is float: a light of 1e20 seen from 1e-4 scene units
// (inverse square: 1e28) still sums within float range (3.4e38); a light of
// 1e300 rendered +inf.
inline constexpr double kMaxSceneColour = 1e20;

// A diffuse material, optionally emissive (an area light).
struct Material {
    std::string name;
    Vec3 kd{0.8, 0.8, 0.8};  // diffuse colour (albedo), linear RGB
    Vec3 ke{0, 0, 0};        // emitted radiance, linear RGB
    bool emissive() const { return ke.x > 0 || ke.y > 0 || ke.z > 0; }
};

// Triangles in world space. Per-triangle arrays have triangle_count() entries.
struct TriangleMesh {
    std::string name;                     // scene key path, e.g. "meshes[1] (bunny.obj)"
    std::vector<float> positions;         // xyz per vertex
    std::vector<std::uint32_t> indices;   // 3 vertex indices per triangle
    std::vector<float> normals;           // 9 per triangle (one per corner) or empty: flat shading
    std::vector<std::uint32_t> material;  // per triangle, index into Scene::materials
    std::vector<std::uint32_t> object_id; // per triangle, 1-based index into Scene::object_names
    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t vertex_count() const { return positions.size() / 3; }
    Vec3 vertex(std::size_t v) const {
        return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
    }
};

struct PointLight {
    Vec3 position;
    Vec3 intensity{1, 1, 1};  // radiant intensity (W/sr per channel): irradiance = I cos / d^2
};

struct GDOF_API Scene {
    std::string path;          // file it was read from ("" for a string)
    CameraDesc camera_desc;    // as given (lens data included when set)
    Aperture aperture;         // camera.aperture (disc when absent); an image kernel's file is not read
    Camera camera;             // built from camera_desc
    std::vector<Material> materials;
    std::vector<TriangleMesh> meshes;
    std::vector<PointLight> point_lights;
    Vec3 environment{0, 0, 0};             // constant radiance seen by rays that miss
    std::vector<std::string> object_names; // object id k is object_names[k - 1]; id 0 = nothing

    std::size_t triangle_count() const;
    // Number of triangles with an emissive material.
    std::size_t emissive_triangle_count() const;
};

// Reads a scene JSON file; relative mesh paths are taken from its folder.
// Errors name the file, the key path ("meshes[2].file") and, for malformed
// JSON, the line and column.
GDOF_API Result<Scene> load_scene(const std::string& path);
// The same from text; `base_dir` resolves relative paths, `source` names the
// text in error messages.
GDOF_API Result<Scene> parse_scene(std::string_view json_text, const std::string& base_dir,
                                   const std::string& source = "scene");

// An OBJ file as read (object space): polygons triangulated (quads and
// n-gons as fans), negative (relative) indices resolved, materials from the
// MTL files it names (Kd, Ke; a material without Kd gets the default).
struct GDOF_API ObjModel {
    struct Shape {
        std::string name;
        std::vector<int> vertex;    // 3 per triangle, into ObjModel::positions / 3
        std::vector<int> normal;    // 3 per triangle, into normals / 3, -1 = none
        std::vector<int> material;  // per triangle, into materials, -1 = none
    };
    std::vector<float> positions;  // xyz
    std::vector<float> normals;    // xyz
    std::vector<Shape> shapes;
    std::vector<Material> materials;
    std::vector<std::string> warnings;  // from the loader (e.g. a missing MTL file)
    std::size_t triangle_count() const;
};

// Reads an OBJ (+ MTL) file. Errors name the file (and the line when the
// loader reports one); non-finite vertices and out-of-range indices are errors.
GDOF_API Result<ObjModel> load_obj(const std::string& path);

}  // namespace gdof
