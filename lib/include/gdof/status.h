// Errors in gdof: the library never prints or exits. Every fallible call
// returns a Status (or a Result<T>) whose message names the culprit: the file,
// channel, JSON key or parameter. Front ends (CLI, OFX) decide how to show it.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace gdof {

class [[nodiscard]] Status {
public:
    Status() = default;  // success
    static Status ok() { return {}; }
    static Status error(std::string message) {
        Status s;
        s.failed_ = true;
        s.message_ = std::move(message);
        return s;
    }
    bool is_ok() const { return !failed_; }
    explicit operator bool() const { return !failed_; }
    const std::string& message() const { return message_; }
    // Adds context in front: "reading 'a.exr': channel 'Z' not found".
    Status& prefix(const std::string& context) {
        if (failed_) message_ = context + ": " + message_;
        return *this;
    }

private:
    bool failed_ = false;
    std::string message_;
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
    Status status() const { return is_ok() ? Status::ok() : std::get<Status>(v_); }
    const std::string& message() const {
        static const std::string empty;
        return is_ok() ? empty : std::get<Status>(v_).message();
    }

private:
    std::variant<T, Status> v_;
};

}  // namespace gdof
