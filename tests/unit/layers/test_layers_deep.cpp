// layers_from_deep / flatten_deep / composite_layers on generated deep images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <vector>

#include "gdof/layers.h"

using namespace gdof;

namespace {

// Small deterministic generator (no implementation-defined distributions).
struct Rng {
    std::uint64_t s;
    explicit Rng(std::uint64_t seed) : s(seed * 2862933555777941757ULL + 3037000493ULL) {}
    std::uint32_t next() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return std::uint32_t(s >> 33);
    }
    double uniform() { return next() / 2147483648.0; }  // [0, 1)
    double uniform(double a, double b) { return a + (b - a) * uniform(); }
};

struct Cluster {
    double z0, z1;
    std::uint32_t id;
};
const Cluster kClusters[3] = {{1.0, 1.3, 7}, {3.0, 3.5, 17}, {12.0, 15.0, 27}};

// A deep image with three depth clusters, 0..4 samples per pixel in random
// (unsorted) order, a negative data-window origin and a uint id channel.
DeepImage make_deep(std::uint64_t seed = 1) {
    const Roi data{-5, 3, 43, 43}, display{0, 0, 40, 40};
    DeepImage d({{"R", PixelType::Half}, {"G", PixelType::Half}, {"B", PixelType::Half}, {"A", PixelType::Half},
                 {"Z", PixelType::Float}, {"id", PixelType::UInt}},
                data, display);
    Rng rng(seed);
    std::vector<std::uint32_t> counts(d.npixels());
    for (auto& c : counts) c = rng.next() % 5;
    EXPECT_TRUE(d.set_sample_counts(counts));
    for (std::size_t p = 0; p < d.npixels(); ++p)
        for (std::size_t k = d.first_sample(p); k < d.first_sample(p) + d.sample_count(p); ++k) {
            const Cluster& c = kClusters[rng.next() % 3];
            const double a = (rng.next() % 4 == 0) ? 1.0 : rng.uniform(0.1, 0.9);
            d.samples(0)[k] = float(a * rng.uniform());
            d.samples(1)[k] = float(a * rng.uniform());
            d.samples(2)[k] = float(a * rng.uniform());
            d.samples(3)[k] = float(a);
            d.samples(4)[k] = float(rng.uniform(c.z0, c.z1));
            d.usamples(5)[k] = c.id;
        }
    return d;
}

std::vector<const Image*> pointers(const std::vector<Layer>& layers) {
    std::vector<const Image*> out;
    for (const auto& l : layers) out.push_back(&l.image);
    return out;
}

// Largest |difference| of R, G, B, A between a composite and the flattening.
double max_diff(const Image& comp, const Image& flat) {
    double m = 0;
    const Roi w = flat.data_window();
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x)
            for (int c = 0; c < 4; ++c) m = std::max(m, double(std::fabs(comp.at(c, x, y) - flat.at(c, x, y))));
    return m;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(layers_deep, AutoFindsTheThreeClusters) {
    const DeepImage d = make_deep();
    auto r = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    // Covered depth ranges: inside each cluster, and equal to its samples' extremes.
    for (int k = 0; k < 3; ++k) {
        double lo = 1e30, hi = -1e30;
        const float* z = d.samples(4);
        for (std::size_t s = 0; s < d.total_samples(); ++s)
            if (d.usamples(5)[s] == kClusters[k].id) {
                lo = std::min(lo, double(z[s]));
                hi = std::max(hi, double(z[s]));
            }
        const Layer& L = (*r)[std::size_t(k)];
        EXPECT_EQ(L.depth_near, lo) << L.name;
        EXPECT_EQ(L.depth_far, hi) << L.name;
        EXPECT_GE(L.depth_near, kClusters[k].z0);
        EXPECT_LE(L.depth_far, kClusters[k].z1);
        EXPECT_NE(L.name.find("depth"), std::string::npos) << L.name;
        // Channels and invariants: A = 0 and Z NaN where uncovered, Z within the range where covered.
        const Image& img = L.image;
        ASSERT_EQ(img.channel_index("R"), 0);
        ASSERT_EQ(img.channel_index("A"), 3);
        ASSERT_EQ(img.channel_index("Z"), 4);
        EXPECT_EQ(img.display_window(), d.display_window());
        std::size_t covered = 0;
        for (std::size_t i = 0; i < img.npixels(); ++i) {
            const float a = img.plane(3)[i], z4 = img.plane(4)[i];
            if (std::isnan(z4)) {
                EXPECT_EQ(a, 0.0f);
            } else {
                ++covered;
                EXPECT_GE(z4, float(lo) * (1 - 1e-6f));
                EXPECT_LE(z4, float(hi) * (1 + 1e-6f));
            }
        }
        EXPECT_GT(covered, 100u);
    }
    // Layer windows are the coverage boxes (inside the data window).
    for (const auto& L : *r) {
        const Roi w = L.image.data_window();
        EXPECT_EQ(intersect(w, d.data_window()), w);
    }
}

TEST(layers_deep, AutoKeepsAtMostMaxLayers) {
    const DeepImage d = make_deep();
    LayerSplit s;
    s.max_layers = 2;
    auto r = layers_from_deep(d, s);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 2u);
    // The wider gap (log 3.5 -> log 12 vs log 1.3 -> log 3) is kept: clusters 0+1 vs 2.
    EXPECT_LT((*r)[0].depth_far, 3.6);
    EXPECT_GE((*r)[1].depth_near, 12.0);
}

TEST(layers_deep, ContinuousDepthsGiveOneLayer) {
    const Roi win{0, 0, 64, 64};
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, win, win);
    EXPECT_TRUE(d.set_sample_counts(std::vector<std::uint32_t>(d.npixels(), 1)));
    for (std::size_t p = 0; p < d.npixels(); ++p) {
        d.samples(3)[p] = 1.0f;
        d.samples(4)[p] = float(1.0 + 9.0 * double(p) / double(d.npixels()));  // 1..10, no gaps
    }
    auto r = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r->size(), 1u);
}

TEST(layers_deep, CountGivesEqualInverseDepthExtents) {
    const DeepImage d = make_deep();
    double zmin = 1e30, zmax = 0;
    for (std::size_t s = 0; s < d.total_samples(); ++s) {
        zmin = std::min(zmin, double(d.samples(4)[s]));
        zmax = std::max(zmax, double(d.samples(4)[s]));
    }
    for (int n : {1, 4, 7}) {
        LayerSplit s;
        s.mode = LayerSplit::Mode::Count;
        s.count = n;
        auto r = layers_from_deep(d, s);
        ASSERT_TRUE(r) << r.message();
        ASSERT_EQ(r->size(), std::size_t(n));
        const double step = (1.0 / zmin - 1.0 / zmax) / n;
        EXPECT_NEAR((*r).front().slice_near, zmin, 1e-9);
        EXPECT_NEAR((*r).back().slice_far, zmax, 1e-6);
        for (int k = 0; k < n; ++k) {
            const Layer& L = (*r)[std::size_t(k)];
            EXPECT_NEAR(1.0 / L.slice_near - 1.0 / L.slice_far, step, 1e-9) << "layer " << k;
            if (k + 1 < n) {
                EXPECT_EQ(L.slice_far, (*r)[std::size_t(k) + 1].slice_near);
            }
            if (!L.image.data_window().empty()) {
                EXPECT_GE(L.depth_near, L.slice_near);
                EXPECT_LE(L.depth_far, L.slice_far * (1 + 1e-12));
            } else {
                EXPECT_TRUE(std::isnan(L.depth_near));
            }
        }
    }
}

TEST(layers_deep, ByIdGivesOneLayerPerId) {
    const DeepImage d = make_deep();
    LayerSplit s;
    s.mode = LayerSplit::Mode::ById;
    auto r = layers_from_deep(d, s);
    ASSERT_TRUE(r) << r.message();
    ASSERT_EQ(r->size(), 3u);
    // Ordered front to back: ids 7, 17, 27 (clusters near to far).
    EXPECT_EQ((*r)[0].name, "id 7");
    EXPECT_EQ((*r)[1].name, "id 17");
    EXPECT_EQ((*r)[2].name, "id 27");
    // A layer pixel is covered exactly where the pixel has a sample of that id.
    for (int k = 0; k < 3; ++k) {
        const Image& img = (*r)[std::size_t(k)].image;
        const Roi w = d.data_window();
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x) {
                const std::size_t p = d.pixel_index(x, y);
                bool has = false;
                for (std::size_t q = d.first_sample(p); q < d.first_sample(p) + d.sample_count(p); ++q)
                    has = has || d.usamples(5)[q] == kClusters[k].id;
                const bool covered = img.data_window().contains(x, y) && !std::isnan(img.at(4, x, y));
                ASSERT_EQ(has, covered) << "id " << kClusters[k].id << " at " << x << "," << y;
            }
    }
    // Errors name the missing or non-uint channel.
    s.id_channel = "objid";
    auto bad = layers_from_deep(d, s);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("'objid'"), std::string::npos) << bad.message();
    s.id_channel = "Z";
    auto notuint = layers_from_deep(d, s);
    ASSERT_FALSE(notuint);
    EXPECT_NE(notuint.message().find("'Z'"), std::string::npos) << notuint.message();
}

TEST(layers_deep, CompositeOfLayersEqualsFlatten) {
    const DeepImage d = make_deep();
    auto flat = flatten_deep(d);
    ASSERT_TRUE(flat) << flat.message();
    std::vector<LayerSplit> splits(5);
    splits[1].mode = LayerSplit::Mode::Count;
    splits[1].count = 4;
    splits[2].mode = LayerSplit::Mode::Count;
    splits[2].count = 9;
    splits[3].mode = LayerSplit::Mode::ById;
    splits[4].max_layers = 2;
    for (const auto& s : splits) {
        auto r = layers_from_deep(d, s);
        ASSERT_TRUE(r) << r.message();
        // A window larger than the image (layers partly outside is fine).
        const Roi window = d.data_window().grown(3);
        Image comp = composite_layers(pointers(*r), window).value();
        EXPECT_EQ(comp.data_window(), window);
        EXPECT_LE(max_diff(comp, *flat), 1e-6) << int(s.mode) << " " << s.count;
        // Nothing outside the layers.
        for (int c = 0; c < 4; ++c) EXPECT_EQ(comp.at(c, window.x0, window.y0), 0.0f);
    }
}

TEST(layers_deep, FlattenIsFrontToBackOver) {
    const Roi win{10, 20, 13, 21};
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, win, Roi{0, 0, 32, 32});
    EXPECT_TRUE(d.set_sample_counts({3, 0, 2}));
    auto set = [&](std::size_t k, float r, float g, float b, float a, float z) {
        d.samples(0)[k] = r;
        d.samples(1)[k] = g;
        d.samples(2)[k] = b;
        d.samples(3)[k] = a;
        d.samples(4)[k] = z;
    };
    // Pixel (10,20): stored back-to-front-ish, unsorted.
    set(0, 0.2f, 0.1f, 0.0f, 0.5f, 5.0f);
    set(1, 0.3f, 0.3f, 0.3f, 0.6f, 2.0f);
    set(2, 0.0f, 0.1f, 0.4f, 0.5f, 3.0f);
    // Pixel (12,20): an opaque front sample hides the rest.
    set(3, 0.9f, 0.9f, 0.9f, 1.0f, 4.0f);
    set(4, 0.5f, 0.5f, 0.5f, 1.0f, 1.5f);
    auto f = flatten_deep(d);
    ASSERT_TRUE(f) << f.message();
    // Hand-written over: z 2 (a .6), then z 3 (a .5) under t = .4, then z 5 (a .5) under t = .2.
    const double R = 0.3 + 0.4 * 0.0 + 0.2 * 0.2;
    const double G = 0.3 + 0.4 * 0.1 + 0.2 * 0.1;
    const double B = 0.3 + 0.4 * 0.4 + 0.2 * 0.0;
    const double A = 0.6 + 0.4 * 0.5 + 0.2 * 0.5;
    EXPECT_NEAR(f->at(0, 10, 20), R, 1e-6);
    EXPECT_NEAR(f->at(1, 10, 20), G, 1e-6);
    EXPECT_NEAR(f->at(2, 10, 20), B, 1e-6);
    EXPECT_NEAR(f->at(3, 10, 20), A, 1e-6);
    EXPECT_EQ(f->at(4, 10, 20), 2.0f);  // nearest sample
    EXPECT_EQ(f->at(3, 11, 20), 0.0f);
    EXPECT_TRUE(std::isnan(f->at(4, 11, 20)));
    EXPECT_EQ(f->at(0, 12, 20), 0.5f);
    EXPECT_EQ(f->at(3, 12, 20), 1.0f);
    EXPECT_EQ(f->at(4, 12, 20), 1.5f);
    EXPECT_EQ(f->display_window(), (Roi{0, 0, 32, 32}));

    // One layer (all samples): Z is the contribution-weighted mean depth.
    LayerSplit one;
    one.mode = LayerSplit::Mode::Count;
    one.count = 1;
    auto l = layers_from_deep(d, one);
    ASSERT_TRUE(l) << l.message();
    ASSERT_EQ(l->size(), 1u);
    const double wz = (0.6 * 2.0 + 0.2 * 3.0 + 0.1 * 5.0) / (0.6 + 0.2 + 0.1);
    EXPECT_NEAR((*l)[0].image.at(4, 10, 20), wz, 1e-6);
    EXPECT_EQ((*l)[0].image.at(4, 12, 20), 1.5f);  // the hidden sample contributes nothing
}

TEST(layers_deep, BadSamplesAreErrorsNamingThePixel) {
    DeepImage d = make_deep();
    // Find a pixel with samples and poison one.
    const Roi w = d.data_window();
    int px = 0, py = 0;
    std::size_t k = 0;
    for (int y = w.y0; y < w.y1 && !k; ++y)
        for (int x = w.x0; x < w.x1 && !k; ++x) {
            const std::size_t p = d.pixel_index(x, y);
            if (d.sample_count(p) >= 2) {
                px = x;
                py = y;
                k = d.first_sample(p) + 1;
            }
        }
    ASSERT_NE(k, 0u);
    const std::string where = "(" + std::to_string(px) + ", " + std::to_string(py) + ")";
    DeepImage nz = d;
    nz.samples(4)[k] = std::nanf("");
    auto a = flatten_deep(nz);
    ASSERT_FALSE(a);
    EXPECT_NE(a.message().find(where), std::string::npos) << a.message();
    EXPECT_NE(a.message().find("Z"), std::string::npos) << a.message();
    auto b = layers_from_deep(nz, LayerSplit{});
    ASSERT_FALSE(b);
    EXPECT_NE(b.message().find(where), std::string::npos) << b.message();
    DeepImage na = d;
    na.samples(3)[k] = INFINITY;
    auto c = layers_from_deep(na, LayerSplit{});
    ASSERT_FALSE(c);
    EXPECT_NE(c.message().find(where), std::string::npos) << c.message();
    EXPECT_NE(c.message().find("alpha"), std::string::npos) << c.message();
    // +inf depth (sky) is fine and lands in the farthest layer.
    DeepImage sky = d;
    sky.samples(4)[k] = INFINITY;
    auto s = layers_from_deep(sky, LayerSplit{});
    ASSERT_TRUE(s) << s.message();
    EXPECT_TRUE(std::isinf(s->back().depth_far));
    // No Z channel.
    DeepImage noz({{"R"}, {"G"}, {"B"}, {"A"}}, Roi{0, 0, 2, 2}, Roi{0, 0, 2, 2});
    auto e = layers_from_deep(noz, LayerSplit{});
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("'Z'"), std::string::npos) << e.message();
}

TEST(layers_deep, IndependentOfThreadCount) {
    const DeepImage d = make_deep(5);
    Exec one;
    one.nthreads = 1;
    Exec many;
    many.nthreads = 4;
    auto a = layers_from_deep(d, LayerSplit{}, {}, one);
    auto b = layers_from_deep(d, LayerSplit{}, {}, many);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->size(), b->size());
    for (std::size_t l = 0; l < a->size(); ++l) {
        const Image& x = (*a)[l].image;
        const Image& y = (*b)[l].image;
        ASSERT_EQ(x.data_window(), y.data_window());
        for (int c = 0; c < x.nchannels(); ++c)
            for (std::size_t i = 0; i < x.npixels(); ++i) ASSERT_TRUE(same_bits(x.plane(c)[i], y.plane(c)[i]));
    }
}

TEST(layers_deep, EmptyDeepImage) {
    const Roi win{0, 0, 4, 3};
    DeepImage d({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, win, win);
    auto f = flatten_deep(d);
    ASSERT_TRUE(f) << f.message();
    EXPECT_EQ(f->at(3, 1, 1), 0.0f);
    auto l = layers_from_deep(d, LayerSplit{});
    ASSERT_TRUE(l) << l.message();
    for (const auto& L : *l) EXPECT_TRUE(L.image.data_window().empty());
    Image comp = composite_layers(pointers(*l), win).value();
    EXPECT_EQ(comp.at(3, 1, 1), 0.0f);
}
