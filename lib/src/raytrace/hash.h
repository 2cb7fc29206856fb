// Counter-based randomness of the ray tracer: hashes of (seed, pixel,
// sample), so every number is the same whatever thread or tile computes it.
#pragma once

#include <cstdint>

namespace gdof::rt {

inline std::uint64_t mix64(std::uint64_t z) {  // splitmix64 finaliser
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
inline std::uint64_t hash(std::uint64_t a, std::uint64_t b) { return mix64(a * 0x9e3779b97f4a7c15ull + mix64(b)); }

// A small counter-based stream: the same (seed, pixel, sample) always gives
// the same numbers, whatever thread runs it.
struct Rng {
    std::uint64_t key = 0, counter = 0;
    Rng(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) : key(hash(hash(seed, pixel), sample)) {}
    double next() { return double(mix64(key + 0x9e3779b97f4a7c15ull * ++counter) >> 11) * 0x1.0p-53; }
};

}  // namespace gdof::rt
