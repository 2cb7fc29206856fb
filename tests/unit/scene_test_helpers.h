// Small scenes written to a scratch folder for the scene / ray-tracer tests.
#pragma once

#include <fstream>
#include <string>

#include "test_support.h"

namespace gdof::test {

inline void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A unit quad (two triangles after triangulation) in the plane z = 0,
// x, y in [-1, 1], written as one quad face with negative indices; material
// "grey" from quad.mtl; plus a small emissive triangle "lamp" at z = 3.
inline void write_quad_obj(const ScratchDir& dir) {
    write_file(dir.file("quad.mtl"), "newmtl grey\nKd 0.5 0.5 0.5\n\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\n");
    write_file(dir.file("quad.obj"),
               "mtllib quad.mtl\n"
               "o plane\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl grey\nf -4 -3 -2 -1\n"
               "o lamp\nv -0.01 -0.01 3\nv 0.01 -0.01 3\nv 0 0.01 3\nusemtl lamp\nf 5 6 7\n");
}

// A camera at z = 5 looking down -z at quad.obj scaled 10x, rotated 10 deg
// about z and moved to z = -1 (the plane fills the view; the lamp, triangle 2,
// ends up at z = 2), a point light.
inline std::string plane_scene_json(const std::string& extra_camera = "", int w = 32, int h = 24) {
    return R"({
  "camera": {"position": [0.3, 0.2, 5], "look_at": [0, 0, 0], "up": [0, 1, 0],
             "focal_length_mm": 35, "sensor_width_mm": 36, "resolution": [)" +
           std::to_string(w) + ", " + std::to_string(h) + "]" + extra_camera + R"(},
  "meshes": [{"file": "quad.obj", "scale": [10, 10, 1], "rotate_deg": [0, 0, 10], "translate": [0, 0, -1]}],
  "lights": [{"type": "point", "position": [1, 2, 4], "intensity": 20}],
  "environment": [0.1, 0.1, 0.1]
})";
}

}  // namespace gdof::test
