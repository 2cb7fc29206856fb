// Image metadata that survives a read/write round trip. Each attribute keeps
// its name and its file type (an OIIO TypeDesc string such as "float",
// "int", "string", "matrix", "float[2]", "box2i"), so camera attributes like
// worldToCamera (matrix) or focalLength (float) are written back as they came.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gdof/export.h"
#include "gdof/math.h"

namespace gdof {

struct Attribute {
    std::string name;
    std::string type;             // OIIO TypeDesc string
    std::vector<double> numbers;  // numeric payload, row-major for matrices
    std::string text;             // string payload (type "string")
};

class GDOF_API Metadata {
public:
    const std::vector<Attribute>& attributes() const { return attrs_; }
    const Attribute* find(std::string_view name) const;
    bool has(std::string_view name) const { return find(name) != nullptr; }
    void set(Attribute a);  // replaces an attribute of the same name
    void erase(std::string_view name);

    void set_float(std::string name, double v);
    void set_int(std::string name, long long v);
    void set_string(std::string name, std::string v);
    void set_matrix(std::string name, const Mat44& m);

    std::optional<double> get_float(std::string_view name) const;  // float, double, int, half
    std::optional<std::string> get_string(std::string_view name) const;
    std::optional<Mat44> get_matrix(std::string_view name) const;  // 16 numbers

private:
    std::vector<Attribute> attrs_;
};

}  // namespace gdof
