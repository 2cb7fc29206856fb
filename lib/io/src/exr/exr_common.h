// Small OpenEXR helpers shared by exr_read.cpp and exr_write.cpp (internal).
#pragma once

#include <string>

#include <OpenEXR/ImfCompression.h>

namespace gdof::io::detail {

// OIIO-style name: "none", "rle", "zips", "zip", "piz", "pxr24", "b44",
// "b44a", "dwaa", "dwab".
std::string compression_name(Imf::Compression c);
// Parses "name" or "name:level" (level: zip 0..9, dwaa/dwab quality).
// Returns false for an unknown name. level is < 0 when absent.
bool parse_compression(const std::string& text, Imf::Compression& c, double& level);
// Initialises OpenEXR once (thread-safe). OpenEXR 3.1's "idmanifest"
// attribute reader consumes 4 bytes more than the attribute holds (it reads an
// 8-byte size but assumes 4), which garbles the next attribute's name
// ("lineOrder" comes out as "Order"); the type is therefore unregistered so
// id manifests are read and written as opaque bytes, exactly as stored.
void ensure_exr_setup();
// Threads OpenEXR may use to (de)compress one file: the process's TBB limit.
int exr_thread_count();

// OpenEXR compresses and decompresses on a worker pool that is empty unless
// the application sizes it (empty, every file ran on one core: a 4K RGBA +
// AOV zip file took 2.7 s to write on two cores). One of these per file read
// or written sizes the pool to exr_thread_count() while any file is in
// flight and empties it after the last, so no threads linger between files:
// a process that forks while idle (Python's multiprocessing, a farm wrapper)
// gives its child an empty pool, where an idle sized one would deadlock the
// child's first read (fork copies no threads).
class ExrThreads {
public:
    ExrThreads();
    ~ExrThreads();
    ExrThreads(const ExrThreads&) = delete;
    ExrThreads& operator=(const ExrThreads&) = delete;
};

}  // namespace gdof::io::detail
