// json_read::parse (json_read.h): the document through nlohmann's SAX
// interface, which hands every error (syntax, and numbers that overflow a
// double) the byte position, so one place turns it into line and column.
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "common/json_read.h"

namespace gdof::json_read {

namespace {

// Builds the document as json::parse would (a repeated key keeps the last
// value) and records the first error.
class DomBuilder : public nlohmann::json_sax<json> {
public:
    explicit DomBuilder(json& root) : root_(root) {}

    bool null() override { return put(nullptr); }
    bool boolean(bool v) override { return put(v); }
    bool number_integer(number_integer_t v) override { return put(v); }
    bool number_unsigned(number_unsigned_t v) override { return put(v); }
    bool number_float(number_float_t v, const string_t&) override { return put(v); }
    bool string(string_t& v) override { return put(std::move(v)); }
    bool binary(binary_t& v) override { return put(json::binary(std::move(v))); }
    bool start_object(std::size_t) override { return open(json::object()); }
    bool key(string_t& k) override {
        slot_ = &(*open_.back())[k];
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(json::array()); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t position, const std::string& token, const json::exception& e) override {
        error_position = position;
        error_token = token;
        error_what = e.what();
        error_id = e.id;
        return false;
    }

    std::size_t error_position = 0;
    std::string error_token, error_what;
    int error_id = 0;

private:
    // Where the next value goes: the root, the end of the open array, or the
    // slot of the last key of the open object. Pointers into open containers
    // stay valid: a container only grows while it is the innermost one.
    json* place(json v) {
        if (open_.empty()) {
            root_ = std::move(v);
            return &root_;
        }
        json& top = *open_.back();
        if (top.is_array()) {
            top.push_back(std::move(v));
            return &top.back();
        }
        *slot_ = std::move(v);
        return slot_;
    }
    bool put(json v) {
        place(std::move(v));
        return true;
    }
    bool open(json v) {
        open_.push_back(place(std::move(v)));
        return true;
    }
    bool close() {
        open_.pop_back();
        return true;
    }

    json& root_;
    std::vector<json*> open_;
    json* slot_ = nullptr;
};

// "line L, column C" (1-based, columns in bytes) of a byte offset.
std::string line_column(std::string_view text, std::size_t offset) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') ++line, column = 1;
        else ++column;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// nlohmann's message without its "[json.exception...] parse error at line
// L, column C: " head (this file gives the position itself).
std::string reason(const std::string& what) {
    std::string r = what;
    if (!r.empty() && r.front() == '[') {
        const auto close = r.find("] ");
        if (close != std::string::npos) r.erase(0, close + 2);
    }
    if (r.rfind("parse error", 0) == 0) {
        const auto colon = r.find(": ");
        if (colon != std::string::npos) r.erase(0, colon + 2);
    }
    return r;
}

}  // namespace

Result<json> parse(std::string_view text, Comments comments) {
    json root;
    DomBuilder builder(root);
    const bool ok = json::sax_parse(text.begin(), text.end(), &builder, json::input_format_t::json, /*strict=*/true,
                                    comments == Comments::Allowed);
    if (ok) return root;
    // The error was found at the last byte read; a number that overflows is
    // reported at its first digit (the token is the number's text).
    const bool overflow = builder.error_id == 406;  // out_of_range.406
    const std::size_t pos = std::min(builder.error_position, text.size());
    const std::size_t len = builder.error_token.size();
    const std::size_t at = overflow && len <= pos ? pos - len : (pos > 0 ? pos - 1 : 0);
    std::string what = reason(builder.error_what);
    if (overflow) what += " (numbers must be finite)";
    return Status::error("malformed JSON at " + line_column(text, at) + ": " + what, StatusCode::InvalidArgument);
}

}  // namespace gdof::json_read
