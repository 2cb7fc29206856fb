// Atomic writes: a temporary file beside the target, renamed over it on
// success, removed on any failure. The temporary name keeps the extension so
// OIIO still picks the format from it.
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "files/files.h"

namespace gdof::io::detail {

namespace fs = std::filesystem;

std::string temp_path_for(const std::string& target) {
    static std::atomic<unsigned long> counter{0};
    fs::path t(target);
    std::string name = t.filename().string();
    std::string ext = t.extension().string();  // ".exr", or "" without one
    std::string tmp = "." + name + ".gdof-tmp-" + std::to_string(long(::getpid())) + "-" +
                      std::to_string(counter.fetch_add(1)) + ext;
    return (t.parent_path() / tmp).string();
}

Status atomic_write(const std::string& target, const std::function<Status(const std::string& tmp)>& writer) {
    fs::path t(target);
    if (t.filename().empty() || target.back() == '/')
        return Status::error(quoted(target) + ": not a file name");
    fs::path dir = t.parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        return Status::error(quoted(target) + ": folder '" + dir.string() + "' does not exist");
    if (fs::is_directory(t, ec)) return Status::error(quoted(target) + ": is a folder");

    const std::string tmp = temp_path_for(target);
    Status st;
    try {
        st = writer(tmp);
    } catch (const std::exception& e) {
        st = Status::error(quoted(target) + ": cannot write (" + e.what() + ")");
    } catch (...) {
        st = Status::error(quoted(target) + ": cannot write (unknown error)");
    }
    if (st && !fs::exists(tmp, ec)) st = Status::error(quoted(target) + ": cannot write (no output produced)");
    if (st && std::rename(tmp.c_str(), target.c_str()) != 0)
        st = Status::error(quoted(target) + ": cannot rename the temporary file into place (" +
                           std::string(std::strerror(errno)) + ")");
    if (!st) fs::remove(tmp, ec);
    return st;
}

}  // namespace gdof::io::detail
