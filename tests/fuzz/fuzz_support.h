// Shared by the fuzz harnesses: the input as text, split into parts, or
// written to a file of this process's scratch folder (parsers that take a
// path read it from there). One process runs many inputs, so the folder is
// made once and removed at exit.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>

namespace gdof::fuzz {

inline std::string text(const std::uint8_t* data, std::size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

// The text before and after the first `marker` (all of it and "" without one).
inline std::pair<std::string, std::string> split(const std::string& s, std::string_view marker) {
    const std::size_t at = s.find(marker);
    if (at == std::string::npos) return {s, std::string()};
    return {s.substr(0, at), s.substr(at + marker.size())};
}

inline const std::string& scratch_dir() {
    // Never freed: the exit handler that removes the folder runs after static destructors.
    static const std::string& dir = *new std::string([] {
        const char* tmp = std::getenv("TMPDIR");
        std::string base = std::string(tmp && *tmp ? tmp : "/tmp") + "/gdof_fuzz_" + std::to_string(::getpid());
        std::filesystem::remove_all(base);
        std::filesystem::create_directories(base);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratch_dir(), ec);
        });
        return base;
    }());
    return dir;
}

// Writes bytes to scratch_dir()/name and returns the path.
inline std::string write_file(const std::string& name, std::string_view bytes) {
    const std::string path = scratch_dir() + "/" + name;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

}  // namespace gdof::fuzz
