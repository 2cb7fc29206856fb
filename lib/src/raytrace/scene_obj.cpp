// OBJ + MTL reading through tinyobjloader (Debian's libtinyobjloader-dev).
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <tiny_obj_loader.h>

#include "gdof/scene.h"
#include "gdof/text_file.h"

namespace gdof {

std::size_t ObjModel::triangle_count() const {
    std::size_t n = 0;
    for (const Shape& s : shapes) n += s.vertex.size() / 3;
    return n;
}

namespace {

// tinyobjloader's messages carry newlines; keep them on one line.
std::string one_line(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

// tinyobjloader reads "nan" / "inf" / garbage coordinates as 0; check the
// v / vn lines first so such files are errors that name the line.
Status check_coordinates(const std::string& text, const std::string& where) {
    std::size_t line = 0, pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find_first_of("\r\n", pos);
        if (end == std::string::npos) end = text.size();
        // CRLF counts as one line break, a lone CR as one too.
        ++line;
        std::string l = text.substr(pos, end - pos);
        pos = end + ((end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n') ? 2 : 1);
        std::size_t b = l.find_first_not_of(" \t");
        if (b == std::string::npos) continue;
        const bool v = l.compare(b, 2, "v ") == 0 || l.compare(b, 2, "v\t") == 0;
        const bool vn = l.compare(b, 3, "vn ") == 0 || l.compare(b, 3, "vn\t") == 0;
        if (!v && !vn) continue;
        const char* c = l.c_str() + b + (v ? 1 : 2);
        for (int k = 0; k < 3; ++k) {
            char* e = nullptr;
            const double x = std::strtod(c, &e);
            if (e == c || !std::isfinite(x))
                return Status::error(where + ": line " + std::to_string(line) + ": " + (v ? "vertex" : "normal") +
                                     " coordinate " + std::to_string(k + 1) + " is not a finite number");
            c = e;
        }
    }
    return Status::ok();
}

}  // namespace

Result<ObjModel> load_obj(const std::string& path) {
    const std::string where = "OBJ '" + path + "'";
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;  // quads and n-gons become fans
    config.vertex_color = false;
    const Result<std::string> text = read_text(path, "OBJ");
    if (!text) return text.status();
    if (Status st = check_coordinates(text.value(), where); !st) return st;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        std::string err = one_line(reader.Error());
        return Status::error(where + ": " + (err.empty() ? std::string("cannot be read") : err));
    }
    // tinyobjloader also reports some errors without failing.
    if (!reader.Error().empty()) return Status::error(where + ": " + one_line(reader.Error()));

    ObjModel model;
    if (!reader.Warning().empty()) model.warnings.push_back(one_line(reader.Warning()));
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    model.positions.assign(attrib.vertices.begin(), attrib.vertices.end());
    model.normals.assign(attrib.normals.begin(), attrib.normals.end());
    for (std::size_t i = 0; i < model.positions.size(); ++i)
        if (!std::isfinite(model.positions[i]))
            return Status::error(where + ": vertex " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");
    for (std::size_t i = 0; i < model.normals.size(); ++i)
        if (!std::isfinite(model.normals[i]))
            return Status::error(where + ": normal " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");

    for (const tinyobj::material_t& m : reader.GetMaterials()) {
        Material mat;
        mat.name = m.name;
        mat.kd = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
        mat.ke = {m.emission[0], m.emission[1], m.emission[2]};
        // "Kd 1e400" parses as inf and would make every pixel it lights inf.
        for (const auto& [key, c] : {std::pair{"Kd", mat.kd}, std::pair{"Ke", mat.ke}})
            if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) ||
                std::max({c.x, c.y, c.z}) > kMaxSceneColour)
                return Status::error(where + ": material '" + m.name + "' (its MTL file): " + key +
                                     " must be finite and <= 1e20");
        model.materials.push_back(mat);
    }

    const int nv = int(model.positions.size() / 3), nn = int(model.normals.size() / 3);
    const int nm = int(model.materials.size());
    for (const tinyobj::shape_t& s : reader.GetShapes()) {
        ObjModel::Shape shape;
        shape.name = s.name;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < s.mesh.num_face_vertices.size(); ++f) {
            const std::size_t fv = s.mesh.num_face_vertices[f];
            if (fv != 3) return Status::error(where + ": shape '" + s.name + "': face with " + std::to_string(fv) +
                                              " vertices after triangulation");
            for (std::size_t k = 0; k < 3; ++k) {
                const tinyobj::index_t& idx = s.mesh.indices[offset + k];
                if (idx.vertex_index < 0 || idx.vertex_index >= nv)
                    return Status::error(where + ": shape '" + s.name + "' face " + std::to_string(f + 1) +
                                         ": vertex index out of range");
                shape.vertex.push_back(idx.vertex_index);
                shape.normal.push_back(idx.normal_index >= 0 && idx.normal_index < nn ? idx.normal_index : -1);
            }
            const int mid = f < s.mesh.material_ids.size() ? s.mesh.material_ids[f] : -1;
            shape.material.push_back(mid >= 0 && mid < nm ? mid : -1);
            offset += fv;
        }
        if (!shape.vertex.empty()) model.shapes.push_back(std::move(shape));
    }
    if (model.shapes.empty()) return Status::error(where + ": no faces");
    return model;
}

}  // namespace gdof
