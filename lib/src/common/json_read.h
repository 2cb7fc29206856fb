// Reading gdof's JSON files (blur fields, stack manifests, focus surfaces,
// scenes, render and light-field stack specs) one way: syntax errors give the
// line and column; an object knows its allowed and required keys; numbers
// follow one policy (finite, +inf only where a key allows the string "inf",
// NaN never); every error names the key path and becomes one Status format,
// "<source>: <path>: <what>", with the key as its subject. Not installed.
//
// Inside a reader, errors are thrown (json_read::Error) and caught by
// read_document at the parser's API boundary: no exception leaves the library.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/format_number.h"
#include "gdof/export.h"
#include "gdof/math.h"
#include "gdof/status.h"

namespace gdof::json_read {

using json = nlohmann::json;

enum class Comments { Rejected, Allowed };  // "//" and "/* */" comments in the text
enum class Infinity { Rejected, Allowed };  // Allowed: the string "inf" reads as +inf

// An error inside a reader: "<path>: <what>", its code, and the key it is about.
struct GDOF_API Error {
    std::string message;
    StatusCode code = StatusCode::InvalidArgument;
    std::string subject;
};

// Throws Error{"<path>: <what>"}; the subject is the last key of the path.
[[noreturn]] GDOF_API void fail(const std::string& path, const std::string& what,
                                StatusCode code = StatusCode::InvalidArgument);
// A library error about the value at `path`: its message, its code kept (and
// its subject, for an empty path).
[[noreturn]] GDOF_API void fail(const std::string& path, const Status& status);

// Message pieces: "string \"abc\"", "number", "array" ...; numbers with 10
// significant digits ("inf", "nan" for the non-finite); "a, b, c".
GDOF_API std::string type_name(const json& j);
using ::gdof::format_number;  // common/format_number.h
GDOF_API std::string join(const std::vector<std::string>& items);

// Paths: key_path("references[2]", "f_number") = "references[2].f_number",
// key_path("", "coc_px") = "coc_px"; index_path("depths", 3) = "depths[3]";
// subject_of("references[2].f_number") = "f_number" (the last key, no index).
GDOF_API std::string key_path(const std::string& path, const std::string& key);
GDOF_API std::string index_path(const std::string& path, std::size_t index);
GDOF_API std::string subject_of(const std::string& path);

// The parsed document, or InvalidArgument "malformed JSON at line L, column C:
// <reason>" (the position of the offending token; a number that overflows a
// double is such an error too).
GDOF_API Result<json> parse(std::string_view text, Comments comments = Comments::Rejected);

// "<source>: <message>" (just the message for an empty source), code and subject kept.
GDOF_API Status to_status(const Error& error, const std::string& source);
GDOF_API Status with_source(const Status& status, const std::string& source);

// Range checks for numbers already read: "must be > lo, got v" / "must be >= lo, got v".
GDOF_API void check_above(double v, double lo, const std::string& path);
GDOF_API void check_at_least(double v, double lo, const std::string& path);

class Object;

// One JSON value and where it sits in the document (the path; "" for the
// document itself, shown as "top level"). Typed reads fail naming the path.
class GDOF_API Value {
public:
    Value(const json& j, std::string path) : j_(&j), path_(std::move(path)) {}

    const json& raw() const { return *j_; }
    const std::string& path() const { return path_; }
    std::string where() const { return path_.empty() ? std::string("top level") : path_; }
    [[noreturn]] void fail(const std::string& what, StatusCode code = StatusCode::InvalidArgument) const;

    // A finite number; with Infinity::Allowed also the string "inf" (+inf).
    double number(Infinity inf = Infinity::Rejected) const;
    double positive(Infinity inf = Infinity::Rejected) const;      // > 0
    double non_negative(Infinity inf = Infinity::Rejected) const;  // >= 0
    long long integer() const;
    bool boolean() const;
    std::string string() const;
    std::string choice(const std::vector<std::string>& options) const;  // one of the strings
    Vec3 vec3() const;                                                  // [x, y, z], finite
    std::vector<Value> array() const;
    // "must be a non-empty array of <of>, got ..." when empty or not an array.
    std::vector<Value> non_empty_array(const std::string& of = {}) const;
    Object object() const;
    Object object(std::vector<std::string> allowed, const std::vector<std::string>& required = {}) const;

private:
    const json* j_;
    std::string path_;
};

// A JSON object. With an allowed list, any other key is an error naming it
// and listing the allowed ones ("<path>.<key>: unknown key (allowed: ...)");
// the required keys are then checked in order ("<path>.<key>: missing
// required key", NotFound). get() requires a key where it is read.
class GDOF_API Object {
public:
    explicit Object(const Value& v);  // must be an object; any keys
    Object(const Value& v, const std::vector<std::string>& allowed, const std::vector<std::string>& required = {});

    const std::string& path() const { return v_.path(); }
    std::string path(const std::string& key) const { return key_path(v_.path(), key); }
    const Value& value() const { return v_; }
    [[noreturn]] void fail(const std::string& what, StatusCode code = StatusCode::InvalidArgument) const {
        v_.fail(what, code);
    }

    void allow_only(const std::vector<std::string>& allowed) const;
    void require(const std::string& key, const std::string& why = {}) const;  // NotFound; "(why)" appended
    bool has(const std::string& key) const { return v_.raw().contains(key); }
    Value get(const std::string& key, const std::string& why = {}) const;  // required
    std::optional<Value> find(const std::string& key) const;
    std::vector<std::string> keys() const;  // in the document's (sorted) order

private:
    Value v_;
};

// Runs body(); an Error it throws comes back as the Status "<source>: ..."
// (see to_status), as does an exception of the JSON library.
template <class F>
auto catch_errors(const std::string& source, F&& body) -> Result<std::invoke_result_t<F>> {
    try {
        return body();
    } catch (const Error& e) {
        return to_status(e, source);
    } catch (const json::exception& e) {
        return with_source(Status::error(e.what()), source);
    }
}

// Parses `text` and runs read(root) on it under catch_errors; a syntax error
// comes back as "<source>: malformed JSON at line L, column C: ...".
template <class F>
auto read_document(std::string_view text, const std::string& source, F&& read, Comments comments = Comments::Rejected)
    -> Result<std::invoke_result_t<F, const Value&>> {
    Result<json> doc = parse(text, comments);
    if (!doc) return with_source(doc.status(), source);
    return catch_errors(source, [&] { return read(Value(doc.value(), "")); });
}

}  // namespace gdof::json_read
