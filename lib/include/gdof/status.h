// Errors in gdof: the library never prints or exits. Every fallible call
// returns a Status (or a Result<T>) whose message names the culprit: the file,
// channel, JSON key or parameter. Front ends (CLI, OFX) decide how to show it.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "gdof/export.h"

namespace gdof {

// What kind of failure, so front ends react without reading message text.
enum class StatusCode {
    Ok,
    Failed,           // anything else (bad data, a computation that cannot be done)
    InvalidArgument,  // a setting or parameter out of range or malformed
    NotFound,         // a file, channel, key or attribute that is not there
    Io,               // reading or writing a file failed
    Cancelled,        // Exec::cancelled returned true
};
GDOF_API const char* to_string(StatusCode code);

class [[nodiscard]] Status {
public:
    Status() = default;  // success
    static Status ok() { return {}; }
    // `subject`: the setting the error is about, by its canonical name (the
    // JSON key / API field, e.g. "focal_length_mm", "depth_channel"); front
    // ends map it to their own name (the CLI flag --focal-length-mm, the OFX
    // parameter) without parsing the message.
    static Status error(std::string message, StatusCode code = StatusCode::Failed, std::string subject = {}) {
        Status s;
        s.code_ = code == StatusCode::Ok ? StatusCode::Failed : code;
        s.message_ = std::move(message);
        s.subject_ = std::move(subject);
        return s;
    }
    // "<what> cancelled" ("cancelled" for an empty what).
    static Status cancelled(const std::string& what = {}) {
        return error(what.empty() ? std::string("cancelled") : what + " cancelled", StatusCode::Cancelled);
    }
    bool is_ok() const { return code_ == StatusCode::Ok; }
    explicit operator bool() const { return is_ok(); }
    StatusCode code() const { return code_; }
    const std::string& message() const { return message_; }
    const std::string& subject() const { return subject_; }
    // Adds context in front: "reading 'a.exr': channel 'Z' not found".
    Status& prefix(const std::string& context) {
        if (!is_ok()) message_ = context + ": " + message_;
        return *this;
    }

private:
    StatusCode code_ = StatusCode::Ok;
    std::string message_;
    std::string subject_;
};

// A value or an error. Small on purpose: no exceptions cross the API.
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Status error) : v_(std::move(error)) {}
    bool is_ok() const { return std::holds_alternative<T>(v_); }
    explicit operator bool() const { return is_ok(); }
    T& value() & { return std::get<T>(v_); }
    const T& value() const& { return std::get<T>(v_); }
    T&& value() && { return std::get<T>(std::move(v_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }
    Status status() const { return is_ok() ? Status::ok() : std::get<Status>(v_); }
    const std::string& message() const {
        static const std::string empty;
        return is_ok() ? empty : std::get<Status>(v_).message();
    }

private:
    std::variant<T, Status> v_;
};

}  // namespace gdof
