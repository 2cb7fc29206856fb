// Atomic writes: a temporary file beside the target, renamed over it on
// success, removed on any failure or cancellation. The temporary name keeps
// the extension (OIIO picks the format from it) and carries the host and
// process id, so a run killed outright (kill -9) leaves a file that says
// whose it is, and the next write of the same target on that host removes it
// once that process is gone.
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>

#include "files/files.h"

namespace gdof::io::detail {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
    char buf[256] = {};
    if (::gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "host";
    std::string h(buf);
    for (char& c : h)
        if (c == '/' || c == '-') c = '_';  // '-' separates the fields of the name
    return h;
}

// "." + name + ".gdof-tmp-" + host + "-": what every temporary file of
// `target` written on this host starts with.
std::string temp_prefix(const fs::path& target) {
    return "." + target.filename().string() + ".gdof-tmp-" + host_name() + "-";
}

bool process_alive(long pid) { return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM); }

// Removes the temporary files of `target` left by processes of this host
// that no longer run (killed while writing). Others' files are left alone.
void remove_stale_temps(const fs::path& target) {
    const std::string prefix = temp_prefix(target);
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        std::size_t used = 0;
        long pid = 0;
        try {
            pid = std::stol(name.substr(prefix.size()), &used);
        } catch (...) {
            continue;
        }
        if (used == 0 || process_alive(pid)) continue;
        std::error_code rm;
        fs::remove(it->path(), rm);
    }
}

}  // namespace

std::string temp_path_for(const std::string& target) {
    static std::atomic<unsigned long> counter{0};
    fs::path t(target);
    std::string tmp = temp_prefix(t) + std::to_string(long(::getpid())) + "-" +
                      std::to_string(counter.fetch_add(1)) + t.extension().string();
    return (t.parent_path() / tmp).string();
}

Status check_target(const std::string& target) {
    fs::path t(target);
    if (target.empty()) return Status::error("no output file name given");
    if (t.filename().empty() || target.back() == '/') return Status::error(quoted(target) + ": not a file name");
    const fs::path dir = t.parent_path().empty() ? fs::path(".") : t.parent_path();
    std::error_code ec;
    if (!fs::exists(dir, ec))
        return Status::error(quoted(target) + ": folder '" + dir.string() + "' does not exist", StatusCode::NotFound);
    if (!fs::is_directory(dir, ec)) return Status::error(quoted(target) + ": '" + dir.string() + "' is not a folder");
    if (fs::is_directory(t, ec)) return Status::error(quoted(target) + ": is a folder");
    // The temporary file is created in the folder, so it needs write and search
    // rights (of the effective user: a setuid or seteuid caller's).
    if (::faccessat(AT_FDCWD, dir.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
        return Status::error(quoted(target) + ": cannot write in folder '" + dir.string() + "' (" +
                                 std::strerror(errno) + ")",
                             StatusCode::Io);
    return Status::ok();
}

Status atomic_write(const std::string& target, const std::function<Status(const std::string& tmp)>& writer,
                    const std::function<bool()>& cancelled) {
    if (Status st = check_target(target); !st) return st;
    remove_stale_temps(fs::path(target));

    const std::string tmp = temp_path_for(target);
    Status st;
    try {
        st = writer(tmp);
    } catch (const std::exception& e) {
        st = Status::error(quoted(target) + ": cannot write (" + e.what() + ")");
    } catch (...) {
        st = Status::error(quoted(target) + ": cannot write (unknown error)");
    }
    std::error_code ec;
    if (st && !fs::exists(tmp, ec)) st = Status::error(quoted(target) + ": cannot write (no output produced)");
    // The folder removed or made read-only during the work: that is the cause to name.
    if (!st)
        if (Status now = check_target(target); !now) st = now;
    // A signal during the write: the finished temporary file is dropped, not renamed.
    if (st && cancelled && cancelled()) st = Status::cancelled(quoted(target) + ": write");
    if (st && std::rename(tmp.c_str(), target.c_str()) != 0)
        st = Status::error(quoted(target) + ": cannot rename the temporary file into place (" +
                           std::string(std::strerror(errno)) + ")");
    if (!st) fs::remove(tmp, ec);
    return st;
}

}  // namespace gdof::io::detail
