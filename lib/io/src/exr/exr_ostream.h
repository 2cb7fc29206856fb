// An OpenEXR output stream over a POSIX file that keeps the first write
// error and checks the close. OpenEXR's own file stream ignores errors of the
// writes made while the output file is destroyed (the offset tables) and of
// the close (where NFS reports some), and its messages name the temporary
// file; this one reports every error through finish(), naming the target
// and the system's reason ("No space left on device").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <OpenEXR/ImfIO.h>

namespace gdof::io::detail {

class CheckedOStream : public Imf::OStream {
public:
    // Creates (truncates) `path`; `display` is the name messages use.
    CheckedOStream(const std::string& path, const std::string& display);
    ~CheckedOStream() override;
    CheckedOStream(const CheckedOStream&) = delete;
    CheckedOStream& operator=(const CheckedOStream&) = delete;

    void write(const char c[], int n) override;  // throws on error
    uint64_t tellp() override;
    void seekp(uint64_t pos) override;

    // Flushes and closes; "" on success, else the first error's message.
    std::string finish();

private:
    void flush();  // throws on error (and remembers it)
    [[noreturn]] void fail(const std::string& what);

    int fd_ = -1;
    std::string display_;
    std::vector<char> buffer_;
    uint64_t pos_ = 0;          // logical position
    uint64_t buffer_start_ = 0;  // file offset of buffer_[0]
    std::string error_;
};

}  // namespace gdof::io::detail
