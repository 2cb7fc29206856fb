// Denormals are flushed only inside the library's own work: the solvers set
// FTZ/DAZ per task and restore the thread's mode, so a caller (a host
// application's thread) keeps its floating-point mode, whatever it was; and
// the flush changes nothing visible (results equal a run on a thread that
// already flushes, to the last bit, and stay finite and conserving).
#include <gtest/gtest.h>

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>

#include <cmath>
#include <vector>

#include "gdof/diffusion.h"

using namespace gdof;

namespace {

constexpr unsigned kFtzDaz = 0x8040u;  // MXCSR flush-to-zero (bit 15), denormals-are-zero (bit 6)

// A bright square in a zero-padded layer: the Gaussian's tails decay into
// the denormal range far from it.
std::vector<float> padded_square(int w, int h) {
    std::vector<float> p(std::size_t(w) * h, 0.0f);
    for (int y = h / 2 - 3; y < h / 2 + 3; ++y)
        for (int x = w / 2 - 3; x < w / 2 + 3; ++x) p[std::size_t(y) * w + x] = 1.0f;
    return p;
}

std::vector<float> diffuse_on_this_thread(DiffusionSolver solver) {
    const int W = 300, H = 40;
    std::vector<float> p = padded_square(W, H), r(p.size(), 12.0f);
    DiffusionOptions s;
    s.solver = solver;
    Exec one;
    one.nthreads = 1;  // runs on the calling thread
    const Roi window{0, 0, W, H};
    EXPECT_TRUE(diffuse_planes(ImageView::planar(p.data(), 1, window), ConstImageView::planar(r.data(), 1, window), s, one)
                    .is_ok());
    return p;
}

}  // namespace

TEST(flush_denormals, CallerModeIsKeptAndResultsDoNotDependOnIt) {
    const unsigned original = _mm_getcsr();
    for (DiffusionSolver solver : {DiffusionSolver::Explicit, DiffusionSolver::Adi}) {
        SCOPED_TRACE(to_string(solver));
        _mm_setcsr(original & ~kFtzDaz);  // a caller that keeps denormals
        const std::vector<float> a = diffuse_on_this_thread(solver);
        EXPECT_EQ(_mm_getcsr() & kFtzDaz, 0u) << "the caller's thread was left flushing denormals";
        volatile float tiny = 1e-39f;
        volatile float half = tiny * 0.5f;
        EXPECT_GT(half, 0.0f);

        _mm_setcsr(original | kFtzDaz);  // a caller that already flushes
        const std::vector<float> b = diffuse_on_this_thread(solver);
        EXPECT_EQ(_mm_getcsr() & kFtzDaz, kFtzDaz) << "the caller's flush mode was cleared";
        _mm_setcsr(original);

        EXPECT_EQ(a, b);  // the work itself always flushes
        double total = 0, tail_min = 1;
        for (float v : a) {
            ASSERT_TRUE(std::isfinite(v));
            total += v;
            if (v > 0) tail_min = std::min(tail_min, double(v));
        }
        EXPECT_NEAR(total, 36.0, 36.0 * 1e-4);  // the square's energy
        EXPECT_GE(tail_min, 1.17e-38) << "a denormal was written";
    }
}

#else
TEST(flush_denormals, NotX86) { GTEST_SKIP() << "MXCSR is x86 only"; }
#endif
