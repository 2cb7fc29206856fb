// Helpers for the numerical stress suite (tests/unit/<capability>/test_stress_*.cpp):
// a seeded random source whose seed is printed with every failure, extreme
// value generators, and checks for non-finite output.
//
// Every stress test starts with GDOF_STRESS_RNG(rng, <default seed>); set
// GDOF_STRESS_SEED=<n> in the environment to rerun the whole suite with
// another seed (a failure message names the seed it ran with).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gdof/image.h"

namespace gdof::test {

constexpr double kStressInf = std::numeric_limits<double>::infinity();
constexpr double kStressNaN = std::numeric_limits<double>::quiet_NaN();
constexpr float kDenormF = 1.0e-41f;  // a float denormal (below FLT_MIN = 1.2e-38)

class StressRng {
public:
    explicit StressRng(std::uint32_t default_seed) : seed_(default_seed) {
        if (const char* s = std::getenv("GDOF_STRESS_SEED")) seed_ = std::uint32_t(std::strtoul(s, nullptr, 10));
        gen_.seed(seed_);
    }
    std::uint32_t seed() const { return seed_; }
    std::mt19937& gen() { return gen_; }

    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen_); }
    // log-uniform in [a, b], 0 < a < b.
    double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
    int integer(int a, int b) { return std::uniform_int_distribution<int>(a, b)(gen_); }
    bool chance(double p) { return uniform(0.0, 1.0) < p; }
    template <class T>
    const T& pick(const std::vector<T>& v) { return v[std::size_t(integer(0, int(v.size()) - 1))]; }

    // A depth along the viewing axis for the stress ranges: log-uniform in
    // [1e-4, 1e7] mostly, sometimes exactly an end, +inf, or a float denormal.
    double depth() {
        const int k = integer(0, 19);
        if (k == 0) return 1e-4;
        if (k == 1) return 1e7;
        if (k == 2) return kStressInf;
        if (k == 3) return double(kDenormF);
        return log_uniform(1e-4, 1e7);
    }
    // A pixel value: ordinary, HDR up to 1e6, exactly 0, or a float denormal.
    float pixel() {
        const int k = integer(0, 9);
        if (k == 0) return 0.0f;
        if (k == 1) return kDenormF;
        if (k <= 3) return float(log_uniform(1.0, 1e6));
        return float(uniform(0.0, 1.0));
    }

private:
    std::uint32_t seed_;
    std::mt19937 gen_;
};

// Declares `var` (a StressRng) and adds its seed to every failure message of the test.
#define GDOF_STRESS_RNG(var, default_seed)                                                                 \
    ::gdof::test::StressRng var(default_seed);                                                             \
    SCOPED_TRACE(::testing::Message() << "stress seed " << var.seed() << " (rerun: GDOF_STRESS_SEED="     \
                                      << var.seed() << ")")

// "" if every float channel of `img` is finite, else where the first bad value is.
inline std::string first_nonfinite(const Image& img) {
    const Roi w = img.data_window();
    for (int c = 0; c < img.nchannels(); ++c) {
        const float* p = img.plane(c);
        if (!p) continue;
        for (std::size_t i = 0; i < img.npixels(); ++i)
            if (!std::isfinite(p[i])) {
                std::ostringstream o;
                o << "channel '" << img.channel(c).name << "' is " << p[i] << " at pixel ("
                  << w.x0 + int(i % std::size_t(w.width())) << ", " << w.y0 + int(i / std::size_t(w.width())) << ")";
                return o.str();
            }
    }
    return {};
}

// A number with every digit (for messages that must reproduce a failure).
inline std::string num(double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
}

struct Size {
    int w, h;
};
// 1x1, 10000x1, 1x10000, or random sides up to max_side.
inline Size random_size(StressRng& rng, int max_side) {
    switch (rng.integer(0, 5)) {
        case 0: return {1, 1};
        case 1: return {10000, 1};
        case 2: return {1, 10000};
        default: return {rng.integer(1, max_side), rng.integer(1, max_side)};
    }
}

inline bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

}  // namespace gdof::test
