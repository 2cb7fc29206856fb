// Frame-sized scratch buffers that are not value-initialised: at 4K a plane
// zeroed by std::vector is a serial pass over fresh memory (page faults on
// one core) before the parallel loop that writes it anyway.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "gdof/exec.h"
#include "gdof/image.h"

namespace gdof {

// resize() leaves new elements unset: write every element, or fill it with
// parallel_assign.
template <class T>
using FrameBuffer = std::vector<T, DefaultInitAllocator<T>>;

// v = n copies of value, in rows of `width` in parallel.
template <class T>
void parallel_assign(FrameBuffer<T>& v, std::size_t n, T value, std::size_t width, const Exec& exec) {
    v.resize(n);
    const std::size_t w = std::max<std::size_t>(1, width);
    parallel_for(exec, long((n + w - 1) / w), [&](long r0, long r1) {
        std::fill(v.begin() + std::ptrdiff_t(std::size_t(r0) * w),
                  v.begin() + std::ptrdiff_t(std::min(n, std::size_t(r1) * w)), value);
    }, 64);
}

}  // namespace gdof
