// CheckedOStream (exr_ostream.h): writes buffered in 1 MiB blocks, each block
// written at its offset (pwrite_all), errors kept until finish().
#include "exr/exr_ostream.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "files/files.h"

namespace gdof::io::detail {

namespace {
constexpr std::size_t kBlock = std::size_t(1) << 20;
}

CheckedOStream::CheckedOStream(const std::string& path, const std::string& display)
    : Imf::OStream(path.c_str()), display_(display) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd_ < 0) fail("cannot create the file");
    buffer_.reserve(kBlock);
}

CheckedOStream::~CheckedOStream() {
    if (fd_ >= 0) ::close(fd_);
}

void CheckedOStream::fail(const std::string& what) {
    const std::string reason = std::strerror(errno);
    if (error_.empty()) error_ = quoted(display_) + ": " + what + " (" + reason + ")";
    throw std::runtime_error(error_);
}

void CheckedOStream::flush() {
    if (!error_.empty()) throw std::runtime_error(error_);
    if (!pwrite_all(fd_, buffer_.data(), buffer_.size(), buffer_start_)) fail("cannot write");
    buffer_start_ += buffer_.size();
    buffer_.clear();
}

void CheckedOStream::write(const char c[], int n) {
    if (!error_.empty()) throw std::runtime_error(error_);
    if (n <= 0) return;
    if (buffer_.size() + std::size_t(n) > kBlock) flush();
    if (std::size_t(n) > kBlock) {  // a large chunk goes out directly
        buffer_.assign(c, c + n);
        flush();
    } else {
        buffer_.insert(buffer_.end(), c, c + n);
    }
    pos_ += uint64_t(n);
}

uint64_t CheckedOStream::tellp() { return pos_; }

void CheckedOStream::seekp(uint64_t pos) {
    if (pos == pos_) return;
    flush();
    pos_ = buffer_start_ = pos;
}

std::string CheckedOStream::finish() {
    if (error_.empty() && fd_ >= 0) {
        try {
            flush();
        } catch (const std::exception&) {
        }
    }
    if (fd_ >= 0) {
        const int fd = fd_;
        fd_ = -1;
        if (::close(fd) != 0 && error_.empty()) error_ = quoted(display_) + ": cannot write (" + std::strerror(errno) + ")";
    }
    return error_;
}

}  // namespace gdof::io::detail
