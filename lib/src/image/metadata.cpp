#include "gdof/metadata.h"

#include <algorithm>

namespace gdof {

const Attribute* Metadata::find(std::string_view name) const {
    for (const auto& a : attrs_)
        if (a.name == name) return &a;
    return nullptr;
}

void Metadata::set(Attribute a) {
    for (auto& e : attrs_)
        if (e.name == a.name) {
            e = std::move(a);
            return;
        }
    attrs_.push_back(std::move(a));
}

void Metadata::erase(std::string_view name) {
    attrs_.erase(std::remove_if(attrs_.begin(), attrs_.end(), [&](const Attribute& a) { return a.name == name; }),
                 attrs_.end());
}

void Metadata::set_float(std::string name, double v) { set({std::move(name), "float", {v}, {}}); }
void Metadata::set_int(std::string name, long long v) { set({std::move(name), "int", {double(v)}, {}}); }
void Metadata::set_string(std::string name, std::string v) { set({std::move(name), "string", {}, std::move(v)}); }
void Metadata::set_matrix(std::string name, const Mat44& m) {
    Attribute a{std::move(name), "matrix", {}, {}};
    for (const auto& row : m.m)
        for (double v : row) a.numbers.push_back(v);
    set(std::move(a));
}

std::optional<double> Metadata::get_float(std::string_view name) const {
    const Attribute* a = find(name);
    if (!a || a->numbers.size() != 1) return std::nullopt;
    return a->numbers[0];
}

std::optional<std::string> Metadata::get_string(std::string_view name) const {
    const Attribute* a = find(name);
    if (!a || a->type != "string") return std::nullopt;
    return a->text;
}

std::optional<Mat44> Metadata::get_matrix(std::string_view name) const {
    const Attribute* a = find(name);
    if (!a || a->numbers.size() != 16) return std::nullopt;
    return Mat44::from_row_major(a->numbers.data());
}

}  // namespace gdof
