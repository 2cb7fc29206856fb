// Cancelled at any point, a defocus stops with Status::cancelled: never a
// crash, never a "success" made of half-done work, never another error.
// Every parallel loop stops at the first poll that sees the cancel, so each
// step must check before it uses what such a loop wrote (a Python Ctrl-C
// landing in the plate's depth cleanup crashed in the speckle removal's
// union-find, whose parents a cancelled loop had left unset).
//
// The inputs exercise every step of the plate path: holes (at a silhouette
// and inside a surface), speckles, noisy depth, a continuous floor, a
// foreground disc; each filter (diffusion, bokeh, vibrate), the ADI solver
// and a deep input run too, and so do the other long calls a host or
// Python can interrupt: a render and a light field's refocus. One thread
// makes the polls countable: the cancel comes at poll k = 0, 1, 2, ... up
// to the last poll of an uncancelled run (every poll of a short call, 300
// spread over a long one); two threads then cancel at polls spread over the
// same range.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "defocus_test_helpers.h"
#include "gdof/deep.h"
#include "gdof/defocus.h"
#include "gdof/image_set.h"
#include "gdof/lightfield.h"
#include "gdof/raytrace.h"
#include "lightfield_test_helpers.h"
#include "scene_test_helpers.h"
#include "test_support.h"

using namespace gdof;
using namespace gdof::test;

namespace {

const Roi kFrame{0, 0, 96, 64};
constexpr float kSpeckleDepth = 1.5f;

// The background without noise: the wall at 8 m, the floor below row 40
// rising from 3 m at the bottom row.
float background_depth(int y) { return y >= 40 ? 3.0f + 5.0f * float(63 - y) / 23.0f : 8.0f; }
// Distance from the disc's centre (30, 28); its radius is 12.
float from_disc_centre(int x, int y) { return std::hypot(float(x) - 30.0f, float(y) - 28.0f); }

// A textured wall at 8 m with noisy depth, a floor rising from 3 m (bottom
// row) to the wall, a disc at 2 m, holes (depth 0: a sensor's "no value") at
// the disc's silhouette and on the wall, and single-pixel speckles.
Image sensor_plate() {
    Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, kFrame);
    unsigned state = 12345;
    auto noise = [&] {
        state = state * 1103515245u + 12345u;
        return float((state >> 16) & 0x7fff) / 32767.0f - 0.5f;
    };
    for (int y = 0; y < kFrame.y1; ++y)
        for (int x = 0; x < kFrame.x1; ++x) {
            const float wall_noise = 1.0f + 0.01f * noise();
            float z = y >= 40 ? background_depth(y) : background_depth(y) * wall_noise;
            float rgb[3] = {texture(x, y, 0), texture(x, y, 1), texture(x, y, 2)};
            const float r = from_disc_centre(x, y);
            const bool disc = r <= 12.0f;
            if (disc) {
                z = 2.0f;
                rgb[0] = 0.9f, rgb[1] = 0.2f, rgb[2] = 0.1f;
            }
            const bool hole = (std::abs(r - 12.5f) < 1.0f && x > 30) || ((x - 70) * (x - 70) + (y - 15) * (y - 15) <= 9);
            if (hole) z = 0.0f;
            if ((x * 7 + y * 13) % 97 == 0 && !disc) z = kSpeckleDepth;
            for (int c = 0; c < 3; ++c) img.at(c, x, y) = rgb[c];
            img.at(3, x, y) = 1.0f;
            img.at(4, x, y) = z;
        }
    return img;
}

// The same scene as a deep image: the disc over the wall where it is
// semi-transparent at its rim (two samples), one sample elsewhere.
DeepImage deep_scene() {
    const Image p = sensor_plate();
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, kFrame, kFrame);
    std::vector<std::uint32_t> counts(kFrame.npixels());
    auto rim = [](int x, int y) {
        const float r = from_disc_centre(x, y);
        return r > 11.0f && r <= 12.0f;
    };
    for (int y = 0; y < kFrame.y1; ++y)
        for (int x = 0; x < kFrame.x1; ++x) counts[std::size_t(y * kFrame.x1 + x)] = rim(x, y) ? 2 : 1;
    EXPECT_TRUE(d.set_sample_counts(counts));
    std::size_t k = 0;
    for (int y = 0; y < kFrame.y1; ++y)
        for (int x = 0; x < kFrame.x1; ++x) {
            const float z = p.at(4, x, y);
            const float wall_z = background_depth(y);
            if (rim(x, y)) {
                const float front[5] = {0.45f, 0.1f, 0.05f, 0.5f, 2.0f};
                const float back[5] = {texture(x, y, 0), texture(x, y, 1), texture(x, y, 2), 1.0f, wall_z};
                for (int c = 0; c < 5; ++c) d.samples(c)[k] = front[c], d.samples(c)[k + 1] = back[c];
                k += 2;
            } else {
                for (int c = 0; c < 4; ++c) d.samples(c)[k] = p.at(c, x, y);
                d.samples(4)[k] = z > 0.0f && z != kSpeckleDepth ? z : wall_z;
                ++k;
            }
        }
    return d;
}

struct Case {
    std::string name;
    ImageSet input;
    DefocusOptions options;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    ImageSet plate;
    plate.parts.emplace_back(sensor_plate());
    ImageSet deep;
    deep.parts.emplace_back(deep_scene());
    DefocusOptions diffuse, adi, bokeh, vibrate;
    adi.diffusion.solver = DiffusionSolver::Adi;
    adi.diffusion.pyramid = false;
    bokeh.filter = DefocusFilter::Bokeh;
    vibrate.filter = DefocusFilter::Vibrate;
    vibrate.vibrate.samples = 8;
    out.push_back({"plate, diffusion", plate, diffuse});
    out.push_back({"plate, ADI at full resolution", plate, adi});
    out.push_back({"plate, bokeh", plate, bokeh});
    out.push_back({"plate, vibrate", plate, vibrate});
    out.push_back({"deep, diffusion", deep, diffuse});
    out.push_back({"deep, bokeh", deep, bokeh});
    return out;
}

BlurField lens() {
    // 35 mm over 36 mm on 96 px, focus 2 m: about 5 px of blur at 8 m.
    auto f = BlurField::parse(
        R"({"blurfield": {"kind": "thin_lens", "focal_length_mm": 35, "f_number": 0.125, "focus_distance": 2, "sensor_width_mm": 36}})");
    EXPECT_TRUE(f) << f.message();
    return f.value();
}

// Float channels through plane(), UInt ones (a render's ids) through uplane().
bool same_bits(const Image& x, const Image& y) {
    if (x.data_window() != y.data_window() || x.nchannels() != y.nchannels()) return false;
    const std::size_t n = x.npixels();
    for (int c = 0; c < x.nchannels() && n; ++c) {
        const void *a = x.plane(c), *b = y.plane(c);
        if (!a && !b) a = x.uplane(c), b = y.uplane(c);
        if (!a && !b) continue;
        if (!a || !b) return false;
        if (std::memcmp(a, b, n * sizeof(float)) != 0) return false;
    }
    return true;
}

bool same_bits(const ImageSet& a, const ImageSet& b) {
    if (a.parts.size() != b.parts.size()) return false;
    for (std::size_t p = 0; p < a.parts.size(); ++p)
        if (!same_bits(a.flat(p), b.flat(p))) return false;
    return true;
}

// `call` cancelled at every poll on one thread, and at polls spread over
// the same range on two: Status::cancelled whenever the cancel was seen,
// else the uncancelled result, bit for bit.
template <class Call>
void cancel_at_every_poll(const std::string& name, Call call) {
    SCOPED_TRACE(name);
    std::atomic<long> polls{0};
    Exec count;
    count.nthreads = 1;
    count.cancelled = [&] {
        ++polls;
        return false;
    };
    auto full = call(count);
    if (!full && full.message().find("without Embree") != std::string::npos) GDOF_SKIP_OR_FAIL(full.message());
    ASSERT_TRUE(full) << full.message();
    const long n = polls.load();
    ASSERT_GT(n, 2);
    std::cout << "[ measured ] " << name << ": " << n << " polls\n";
    auto run = [&](int threads, long k) {
        std::atomic<long> seen{0};
        std::atomic<bool> fired{false};
        Exec e;
        e.nthreads = threads;
        e.cancelled = [&] {
            if (seen++ < k) return false;
            fired = true;
            return true;
        };
        auto r = call(e);
        if (fired) {
            ASSERT_FALSE(r) << "cancelled at poll " << k << " (" << threads << " threads) but it succeeded";
            EXPECT_EQ(r.status().code(), StatusCode::Cancelled) << k << ": " << r.message();
        } else {
            ASSERT_TRUE(r) << k << ": " << r.message();
            EXPECT_TRUE(same_bits(*r, *full)) << k;
        }
    };
    // Every poll up to 300 of them, else every (n / 300)-th: each loop of a
    // long call still gets cancelled somewhere inside (sanitizer builds run
    // this too).
    for (long k = 0; k <= n; k += std::max(1L, n / 300)) run(1, k);
    for (long k = 0; k <= n; k += std::max(1L, n / 30)) run(2, k);
}

}  // namespace

TEST(cancel_anywhere, DefocusWithEveryFilterAndInput) {
    const BlurField field = lens();
    const Camera cam = test_camera(kFrame);
    for (const Case& c : cases())
        cancel_at_every_poll(c.name, [&](const Exec& e) { return defocus(c.input, field, cam, c.options, nullptr, e); });
}

TEST(cancel_anywhere, RenderThroughABlurField) {
    test::ScratchDir dir;
    test::write_quad_obj(dir);
    auto scene = parse_scene(test::plane_scene_json("", 24, 16), dir.path().string());
    ASSERT_TRUE(scene) << scene.message();
    auto field = BlurField::parse(R"({"blurfield": {"kind": "focal_planes", "depths": [2, 6], "max_blur": 3}})");
    ASSERT_TRUE(field) << field.message();
    RenderOptions rs;
    rs.spp = 2;
    rs.tile_size = 4;
    rs.blur_field = &field.value();
    cancel_at_every_poll("render", [&](const Exec& e) { return render(*scene, rs, nullptr, e); });
}

TEST(cancel_anywhere, LightFieldRefocus) {
    test::Plane near{1.3, Roi{8, 6, 24, 18}, test::smooth_texture(1.0)};
    test::Plane far{-0.4, Roi{}, test::smooth_texture(2.0)};
    const LightField lf = test::make_planes_lightfield(3, 3, 32, 24, {near, far});
    cancel_at_every_poll("refocus", [&](const Exec& e) { return refocus(lf, {0.7, 1.0}, e); });
}
