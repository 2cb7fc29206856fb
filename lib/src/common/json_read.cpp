// Typed reads, key checks and error formatting of json_read.h. The syntax
// side (positions) is in json_read_parse.cpp.
#include "common/json_read.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gdof::json_read {

void fail(const std::string& path, const std::string& what, StatusCode code) {
    throw Error{path.empty() ? what : path + ": " + what, code, subject_of(path)};
}

void fail(const std::string& path, const Status& status) {
    if (!path.empty()) fail(path, status.message(), status.code());
    throw Error{status.message(), status.code(), status.subject()};
}

std::string type_name(const json& j) {
    if (j.is_string()) return "string \"" + j.get<std::string>() + "\"";
    return j.type_name();
}

std::string join(const std::vector<std::string>& items) {
    std::string s;
    for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
    return s;
}

std::string key_path(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

std::string index_path(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }

std::string subject_of(const std::string& path) {
    std::string s = path;
    while (!s.empty() && s.back() == ']') {
        const auto open = s.rfind('[');
        if (open == std::string::npos) break;
        s.erase(open);
    }
    const auto dot = s.rfind('.');
    return dot == std::string::npos ? s : s.substr(dot + 1);
}

Status to_status(const Error& error, const std::string& source) {
    return Status::error(source.empty() ? error.message : source + ": " + error.message, error.code, error.subject);
}

Status with_source(const Status& status, const std::string& source) {
    if (status.is_ok() || source.empty()) return status;
    return Status::error(source + ": " + status.message(), status.code(), status.subject());
}

void check_above(double v, double lo, const std::string& path) {
    if (!(v > lo)) fail(path, "must be > " + format_number(lo) + ", got " + format_number(v));
}

void check_at_least(double v, double lo, const std::string& path) {
    if (!(v >= lo)) fail(path, "must be >= " + format_number(lo) + ", got " + format_number(v));
}

// ---- Value ----

void Value::fail(const std::string& what, StatusCode code) const { json_read::fail(where(), what, code); }

double Value::number(Infinity inf) const {
    const bool allow_inf = inf == Infinity::Allowed;
    if (allow_inf && j_->is_string() && j_->get<std::string>() == "inf") return std::numeric_limits<double>::infinity();
    if (!j_->is_number()) fail(std::string("must be a number") + (allow_inf ? " or \"inf\"" : "") + ", got " + type_name(*j_));
    // Text never holds a non-finite number (an overflow is a syntax error);
    // a document built in memory can.
    const double d = j_->get<double>();
    if (!std::isfinite(d)) fail(std::string("must be finite") + (allow_inf ? " or \"inf\"" : "") + ", got " + format_number(d));
    return d;
}

double Value::positive(Infinity inf) const {
    const double d = number(inf);
    check_above(d, 0, where());
    return d;
}

double Value::non_negative(Infinity inf) const {
    const double d = number(inf);
    check_at_least(d, 0, where());
    return d;
}

long long Value::integer() const {
    if (!j_->is_number_integer()) fail("must be an integer, got " + type_name(*j_));
    return j_->get<long long>();
}

bool Value::boolean() const {
    if (!j_->is_boolean()) fail("must be true or false, got " + type_name(*j_));
    return j_->get<bool>();
}

std::string Value::string() const {
    if (!j_->is_string()) fail("must be a string, got " + type_name(*j_));
    return j_->get<std::string>();
}

std::string Value::choice(const std::vector<std::string>& options) const {
    const std::string s = string();
    if (std::find(options.begin(), options.end(), s) == options.end())
        fail("must be one of " + join(options) + ", got \"" + s + "\"");
    return s;
}

Vec3 Value::vec3() const {
    if (!j_->is_array() || j_->size() != 3) fail("must be an array of 3 numbers, got " + type_name(*j_));
    const std::vector<Value> a = array();
    return {a[0].number(), a[1].number(), a[2].number()};
}

std::vector<Value> Value::array() const {
    if (!j_->is_array()) fail("must be an array, got " + type_name(*j_));
    std::vector<Value> out;
    out.reserve(j_->size());
    for (std::size_t i = 0; i < j_->size(); ++i) out.emplace_back((*j_)[i], index_path(path_, i));
    return out;
}

std::vector<Value> Value::non_empty_array(const std::string& of) const {
    if (!j_->is_array() || j_->empty())
        fail("must be a non-empty array" + (of.empty() ? std::string() : " of " + of) + ", got " + type_name(*j_));
    return array();
}

Object Value::object() const { return Object(*this); }

Object Value::object(std::vector<std::string> allowed, const std::vector<std::string>& required) const {
    return Object(*this, allowed, required);
}

// ---- Object ----

Object::Object(const Value& v) : v_(v) {
    if (!v.raw().is_object()) v.fail("must be an object, got " + type_name(v.raw()));
}

Object::Object(const Value& v, const std::vector<std::string>& allowed, const std::vector<std::string>& required)
    : Object(v) {
    allow_only(allowed);
    for (const std::string& k : required) require(k);
}

void Object::allow_only(const std::vector<std::string>& allowed) const {
    for (auto it = v_.raw().begin(); it != v_.raw().end(); ++it)
        if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
            json_read::fail(path(it.key()), "unknown key (allowed: " + join(allowed) + ")");
}

void Object::require(const std::string& key, const std::string& why) const {
    if (!has(key))
        json_read::fail(path(key), "missing required key" + (why.empty() ? std::string() : " (" + why + ")"),
                        StatusCode::NotFound);
}

Value Object::get(const std::string& key, const std::string& why) const {
    require(key, why);
    return Value(v_.raw().at(key), path(key));
}

std::optional<Value> Object::find(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return Value(v_.raw().at(key), path(key));
}

std::vector<std::string> Object::keys() const {
    std::vector<std::string> out;
    for (auto it = v_.raw().begin(); it != v_.raw().end(); ++it) out.push_back(it.key());
    return out;
}

}  // namespace gdof::json_read
