// Writes whose every error counts: short writes retried, failures (a full
// disk, a file-size limit) reported with the system's reason, the close
// checked too. The image writers' own streams drop some of these errors.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "files/files.h"

namespace gdof::io::detail {

bool pwrite_all(int fd, const void* data, std::size_t n, std::uint64_t offset) {
    const char* p = static_cast<const char*>(data);
    std::size_t done = 0;
    while (done < n) {
        const ssize_t w = ::pwrite(fd, p + done, n - done, off_t(offset + done));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            if (w == 0) errno = EIO;
            return false;
        }
        done += std::size_t(w);
    }
    return true;
}

Status write_file(const std::string& path, const std::string& display, const void* data, std::size_t n) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) return Status::error(quoted(display) + ": cannot create the file (" + std::strerror(errno) + ")", StatusCode::Io);
    const bool ok = pwrite_all(fd, data, n, 0);
    const int write_errno = errno;
    const bool closed = ::close(fd) == 0;
    if (!ok || !closed)
        return Status::error(quoted(display) + ": cannot write (" + std::strerror(ok ? errno : write_errno) + ")",
                             StatusCode::Io);
    return Status::ok();
}

}  // namespace gdof::io::detail
