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

// The folder for scratch files: $TMPDIR, else /dev/shm where it is (memory:
// on a disk file system, rewriting a file per input costs a flush on every
// close, which made fuzz_exr 2.7 and fuzz_obj 5 times slower per input), else /tmp.
inline std::string scratch_base() {
    if (const char* tmp = std::getenv("TMPDIR"); tmp && *tmp) return tmp;
    std::error_code ec;
    if (std::filesystem::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0) return "/dev/shm";
    return "/tmp";
}

inline const std::string& scratch_dir() {
    // Never freed: the exit handler that removes the folder runs after static destructors.
    static const std::string& dir = *new std::string([] {
        std::string base = scratch_base() + "/gdof_fuzz_" + std::to_string(::getpid());
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
