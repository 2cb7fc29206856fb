// Fault injection for the tests (docs/reliability.md, "Fault injection"):
// child processes the test controls (stderr to a file, a file-size limit,
// an unprivileged user, signals at chosen moments), a small tmpfs as a full
// disk, and polling for files and open descriptors.
#pragma once

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace gdof::test {

namespace fs = std::filesystem;

// The user an unwritable folder is tested as when the tests run as root
// (root writes through permission bits).
constexpr uid_t kNobody = 65534;

struct ChildOptions {
    std::string log;          // stdout and stderr go here ("" : /dev/null)
    long file_size_limit = -1;  // RLIMIT_FSIZE in bytes (ulimit -f), -1 none
    bool as_nobody = false;   // drop to uid/gid 65534 when root
};

// Forks; the child applies `o` and runs `body` (exec or work), then exits
// with its return value. Only async-signal-safe calls happen before `body`.
inline pid_t fork_child(const ChildOptions& o, const std::function<int()>& body) {
    const pid_t pid = ::fork();
    if (pid != 0) return pid;
    const int fd = ::open(o.log.empty() ? "/dev/null" : o.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) ::dup2(fd, 1), ::dup2(fd, 2);
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::signal(SIGXFSZ, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    if (o.file_size_limit >= 0) {
        rlimit r{rlim_t(o.file_size_limit), rlim_t(o.file_size_limit)};
        if (::setrlimit(RLIMIT_FSIZE, &r) != 0) ::_exit(120);
    }
    if (o.as_nobody && ::geteuid() == 0) {
        if (::setgroups(0, nullptr) != 0 || ::setgid(kNobody) != 0 || ::setuid(kNobody) != 0) ::_exit(121);
    }
    ::_exit(body());
}

// Starts `program` with `args` as a child (see fork_child).
inline pid_t spawn(const std::string& program, const std::vector<std::string>& args, const ChildOptions& o = {}) {
    std::vector<std::string> all{program};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    return fork_child(o, [&] {
        ::execv(argv[0], argv.data());
        return 127;
    });
}

// Waits for a child (at most `timeout`, then kills it): its exit code, or
// 128 + the signal that ended it, as a shell reports it.
inline int wait_exit(pid_t pid, std::chrono::seconds timeout = std::chrono::seconds(300)) {
    const auto t0 = std::chrono::steady_clock::now();
    int status = 0;
    for (;;) {
        const pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid) break;
        if (r < 0) return -1;
        if (std::chrono::steady_clock::now() - t0 > timeout) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            return -2;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Polls `ready` every millisecond until it holds (true) or `timeout` passes (false).
inline bool wait_for(const std::function<bool()>& ready, std::chrono::seconds timeout = std::chrono::seconds(120)) {
    const auto t0 = std::chrono::steady_clock::now();
    while (!ready()) {
        if (std::chrono::steady_clock::now() - t0 > timeout) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
}

// True while process `pid` has `path` open.
inline bool has_open(pid_t pid, const std::string& path) {
    std::error_code ec;
    const std::string want = fs::weakly_canonical(path, ec).string();
    for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
        std::error_code ec2;
        if (fs::read_symlink(e.path(), ec2).string() == want) return true;
    }
    return false;
}

// The temporary files of gdof's atomic writes in a folder.
inline std::vector<std::string> temp_files(const std::string& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().find(".gdof-tmp-") != std::string::npos) out.push_back(e.path().filename());
    return out;
}

// A tmpfs of `bytes` mounted on a new folder (a full disk on demand);
// unmounted when destroyed. mounted() is false where mounting is not
// allowed (not root, no CAP_SYS_ADMIN, some CI containers); why() says why.
class SmallTmpfs {
public:
    SmallTmpfs(const std::string& dir, long bytes) : dir_(dir) {
        fs::create_directories(dir_);
        const std::string opts = "size=" + std::to_string(bytes) + ",mode=0777";
        if (::mount("tmpfs", dir_.c_str(), "tmpfs", 0, opts.c_str()) == 0) mounted_ = true;
        else why_ = std::string("cannot mount a tmpfs on ") + dir_ + " (" + std::strerror(errno) +
                    "; needs root with CAP_SYS_ADMIN)";
    }
    ~SmallTmpfs() {
        if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
    }
    SmallTmpfs(const SmallTmpfs&) = delete;
    SmallTmpfs& operator=(const SmallTmpfs&) = delete;
    bool mounted() const { return mounted_; }
    const std::string& why() const { return why_; }

private:
    std::string dir_;
    bool mounted_ = false;
    std::string why_;
};

}  // namespace gdof::test
