// keep_freed_memory (exec.h): glibc's allocator tuned for a process that
// allocates and frees frame-sized buffers layer after layer.
#include "gdof/exec.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gdof {

void keep_freed_memory() {
#if defined(__GLIBC__)
    // Blocks above the mmap threshold (128 KiB .. 32 MiB, adaptive) are
    // mapped per allocation and unmapped on free, so each layer's buffers
    // fault in fresh zeroed pages again (~15% of a 4K frame's time). Serve
    // them from the heap and keep freed memory for the next layer.
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    mallopt(M_TOP_PAD, 256 << 20);
#endif
}

}  // namespace gdof
