// Layers and flattening on the real deep EXRs under ../shared/data (skipped
// when absent): our flatten against OpenImageIO's, the three Weta files
// against their composite, and the id split of deep_with_id_11.exr.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "gdof/io/image_io.h"
#include "gdof/layers.h"
#include "test_support.h"

using namespace gdof;

namespace {

struct Diff {
    double max_abs = 0;
    double max_rel = 0;  // |d| / max(1, |ref|)
    std::size_t n = 0;
};

// Compares RGBA(+Z when both finite) of our flat image against an OIIO flat
// image over our data window (OIIO outside its window: 0).
Diff compare_to_oiio(const Image& ours, const OIIO::ImageBuf& ref, bool with_z, double* z_max = nullptr) {
    Diff d;
    const auto& spec = ref.spec();
    const char* names[5] = {"R", "G", "B", "A", "Z"};
    int rc[5];
    for (int c = 0; c < 5; ++c) rc[c] = spec.channelindex(names[c]);
    const Roi w = ours.data_window();
    double zm = 0;
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            for (int c = 0; c < 4; ++c) {
                const double a = ours.at(c, x, y);
                const double b = rc[c] >= 0 ? ref.getchannel(x, y, 0, rc[c]) : 0.0;
                const double e = std::fabs(a - b);
                d.max_abs = std::max(d.max_abs, e);
                d.max_rel = std::max(d.max_rel, e / std::max(1.0, std::fabs(b)));
                ++d.n;
            }
            if (with_z && rc[4] >= 0) {
                const double a = ours.at(4, x, y);
                const double b = ref.getchannel(x, y, 0, rc[4]);
                if (std::isfinite(a) && std::isfinite(b) && ours.at(3, x, y) > 0)
                    zm = std::max(zm, std::fabs(a - b) / std::max(1.0, std::fabs(b)));
            }
        }
    if (z_max) *z_max = zm;
    return d;
}

// All samples of several deep images in one (union window), channels R,G,B,A,Z.
DeepImage merge(const std::vector<const DeepImage*>& parts) {
    Roi win;
    for (const DeepImage* p : parts) win = unite(win, p->data_window());
    DeepImage out({{"R"}, {"G"}, {"B"}, {"A"}, {"Z"}}, win, parts[0]->display_window());
    std::vector<std::uint32_t> counts(out.npixels(), 0);
    for (const DeepImage* p : parts) {
        const Roi pw = p->data_window();
        for (int y = pw.y0; y < pw.y1; ++y)
            for (int x = pw.x0; x < pw.x1; ++x) counts[out.pixel_index(x, y)] += p->sample_count(p->pixel_index(x, y));
    }
    EXPECT_TRUE(out.set_sample_counts(counts));
    std::vector<std::uint32_t> filled(out.npixels(), 0);
    for (const DeepImage* p : parts) {
        int ch[5];
        const char* names[5] = {"R", "G", "B", "A", "Z"};
        for (int c = 0; c < 5; ++c) ch[c] = p->channel_index(names[c]);
        const Roi pw = p->data_window();
        for (int y = pw.y0; y < pw.y1; ++y)
            for (int x = pw.x0; x < pw.x1; ++x) {
                const std::size_t sp = p->pixel_index(x, y), op = out.pixel_index(x, y);
                for (std::uint32_t k = 0; k < p->sample_count(sp); ++k) {
                    const std::size_t dst = out.first_sample(op) + filled[op]++;
                    for (int c = 0; c < 5; ++c) out.samples(c)[dst] = p->samples(ch[c])[p->first_sample(sp) + k];
                }
            }
    }
    return out;
}

std::vector<const Image*> pointers(const std::vector<Layer>& layers) {
    std::vector<const Image*> out;
    for (const auto& l : layers) out.push_back(&l.image);
    return out;
}

}  // namespace

TEST(layers_shared, FlattenMatchesOiioAndLayersRecompose) {
    for (const char* name : {"Balls.exr", "Trunks.exr", "Leaves.exr"}) {
        GDOF_REQUIRE_SHARED(path, std::string("exr/deep_lowres_left/") + name);
        auto set = io::read_image(path);
        ASSERT_TRUE(set) << set.message();
        ASSERT_TRUE(set->is_deep(0));
        const DeepImage& deep = set->deep(0);
        auto flat = flatten_deep(deep);
        ASSERT_TRUE(flat) << flat.message();

        OIIO::ImageBuf src(path);
        ASSERT_TRUE(src.read(0, 0, true)) << src.geterror();
        ASSERT_TRUE(src.deep());
        OIIO::ImageBuf ref = OIIO::ImageBufAlgo::flatten(src);
        ASSERT_FALSE(ref.has_error()) << ref.geterror();
        double zrel = 0;
        const Diff d = compare_to_oiio(*flat, ref, true, &zrel);
        std::cout << "[ measured ] " << name << ": flatten_deep vs OIIO flatten: max |diff| RGBA " << d.max_abs
                  << ", max relative " << d.max_rel << " over " << d.n << " values; Z max relative " << zrel << "\n";
        // Half samples: inputs are exact in both; only accumulation order and
        // OIIO's output rounding differ.
        EXPECT_LE(d.max_rel, 1e-3) << name;

        for (const char* split : {"auto", "6"}) {
            auto s = parse_layer_split(split);
            ASSERT_TRUE(s);
            auto layers = layers_from_deep(deep, *s);
            ASSERT_TRUE(layers) << layers.message();
            Image comp = composite_layers(pointers(*layers), deep.data_window()).value();
            double m = 0;
            for (std::size_t i = 0; i < comp.npixels(); ++i)
                for (int c = 0; c < 4; ++c) m = std::max(m, double(std::fabs(comp.plane(c)[i] - flat->plane(c)[i])));
            std::cout << "[ measured ] " << name << ": split " << split << ": " << layers->size()
                      << " layers; composite vs flatten max |diff| " << m << "\n";
            EXPECT_LE(m, 1e-5) << name << " split " << split;
        }
    }
}

TEST(layers_shared, CompositedIsTheFlattenedMergeOfTheThreeFiles) {
    GDOF_REQUIRE_SHARED(comp_path, "exr/deep_lowres_left/composited.exr");
    std::vector<ImageSet> sets;
    for (const char* name : {"Balls.exr", "Trunks.exr", "Leaves.exr"}) {
        GDOF_REQUIRE_SHARED(path, std::string("exr/deep_lowres_left/") + name);
        auto s = io::read_image(path);
        ASSERT_TRUE(s) << s.message();
        sets.push_back(std::move(s.value()));
    }
    auto comp = io::read_flat(comp_path);
    ASSERT_TRUE(comp) << comp.message();
    const DeepImage merged = merge({&sets[0].deep(0), &sets[1].deep(0), &sets[2].deep(0)});
    auto flat = flatten_deep(merged);
    ASSERT_TRUE(flat) << flat.message();
    // The same through layers of the merged samples.
    auto layers = layers_from_deep(merged, LayerSplit{});
    ASSERT_TRUE(layers) << layers.message();
    Image via_layers = composite_layers(pointers(*layers), comp->data_window()).value();

    // composited.exr was made from four deep files: these three and a ground
    // plane (Ground.exr, not in the shared data). So it equals the merge of
    // the three exactly where the ground adds nothing: where our merge is
    // opaque and nearer than the ground. Measured: the fraction of opaque
    // pixels that match to half precision, and alpha never decreasing.
    const RgbaIndices ix = find_rgba(*comp);
    const int idx[4] = {ix.r, ix.g, ix.b, ix.a};
    const Roi w = comp->data_window();
    std::size_t opaque = 0, opaque_match = 0, layers_match = 0, alpha_drop = 0;
    double worst_drop = 0;
    for (int y = w.y0; y < w.y1; ++y)
        for (int x = w.x0; x < w.x1; ++x) {
            const double ma = flat->at(3, x, y);
            const double ca = comp->at(ix.a, x, y);
            if (ca < ma - 2e-3) {
                ++alpha_drop;
                worst_drop = std::max(worst_drop, ma - ca);
            }
            if (ma < 0.999) continue;
            ++opaque;
            bool same = true, same_layers = true;
            for (int c = 0; c < 4; ++c) {
                const double ref = comp->at(idx[c], x, y);
                const double tol = 2e-3 * std::max(1.0, std::fabs(ref));
                same = same && std::fabs(flat->at(c, x, y) - ref) <= tol;
                same_layers = same_layers && std::fabs(via_layers.at(c, x, y) - ref) <= tol;
            }
            opaque_match += same;
            layers_match += same_layers;
        }
    const double frac = double(opaque_match) / double(std::max<std::size_t>(1, opaque));
    const double frac_layers = double(layers_match) / double(std::max<std::size_t>(1, opaque));
    std::cout << "[ measured ] composited.exr vs flatten of the merged samples of Balls+Trunks+Leaves: " << opaque
              << " opaque pixels, " << 100.0 * frac << " % equal to half precision (via " << layers->size()
              << " auto layers: " << 100.0 * frac_layers << " %); " << alpha_drop
              << " pixels where composited alpha is lower (worst " << worst_drop << ")\n";
    EXPECT_GE(frac, 0.99);
    EXPECT_EQ(alpha_drop, 0u);
    EXPECT_EQ(opaque_match, layers_match);
}

TEST(layers_shared, DeepWithIdSplitsById) {
    GDOF_REQUIRE_SHARED(path, "exr/deep_with_id_11.exr");
    auto set = io::read_image(path);
    ASSERT_TRUE(set) << set.message();
    const DeepImage& deep = set->deep(0);
    const int idc = deep.channel_index("id");
    ASSERT_GE(idc, 0);
    std::set<std::uint32_t> ids(deep.usamples(idc), deep.usamples(idc) + deep.total_samples());
    auto split = parse_layer_split("id");
    ASSERT_TRUE(split);
    auto layers = layers_from_deep(deep, *split);
    ASSERT_TRUE(layers) << layers.message();
    EXPECT_EQ(layers->size(), ids.size());
    std::set<std::string> names;
    for (const auto& l : *layers) names.insert(l.name);
    for (std::uint32_t id : ids) EXPECT_EQ(names.count("id " + std::to_string(id)), 1u) << id;
    // Front to back by median depth: depth_near of consecutive layers are not
    // required to be ordered, but the layers' covered ranges are consistent.
    for (const auto& l : *layers) EXPECT_LE(l.depth_near, l.depth_far) << l.name;
    auto by_particle = layers_from_deep(deep, *parse_layer_split("id:particleid"));
    ASSERT_TRUE(by_particle) << by_particle.message();
    std::set<std::uint32_t> pids(deep.usamples(deep.channel_index("particleid")),
                                 deep.usamples(deep.channel_index("particleid")) + deep.total_samples());
    EXPECT_EQ(by_particle->size(), pids.size());
    auto flat = flatten_deep(deep);
    ASSERT_TRUE(flat);
    Image comp = composite_layers(pointers(*layers), deep.data_window()).value();
    double m = 0;
    for (std::size_t i = 0; i < comp.npixels(); ++i)
        for (int c = 0; c < 4; ++c) m = std::max(m, double(std::fabs(comp.plane(c)[i] - flat->plane(c)[i])));
    std::cout << "[ measured ] deep_with_id_11.exr: " << ids.size() << " ids, " << pids.size()
              << " particle ids; composite of id layers vs flatten max |diff| " << m
              << " (ids may interleave in depth)\n";
}

TEST(layers_shared, TumRgbdDepthSlices) {
    GDOF_REQUIRE_SHARED(depth_path, "rgbd/tum/depth.png");
    GDOF_REQUIRE_SHARED(color_path, "rgbd/tum/color.png");
    auto colour = io::read_flat(color_path);
    ASSERT_TRUE(colour) << colour.message();
    auto depth = io::read_flat(depth_path);
    ASSERT_TRUE(depth) << depth.message();
    ASSERT_EQ(colour->data_window(), depth->data_window());
    // One image: R, G, B (opaque) + the raw depth as "depth".
    Image img = Image::with_channels({"R", "G", "B", "depth"}, colour->data_window());
    const RgbaIndices ix = find_rgba(*colour);
    const int src[3] = {ix.r, ix.g, ix.b};
    for (int c = 0; c < 3; ++c) std::copy_n(colour->plane(src[c]), img.npixels(), img.plane(c));
    std::copy_n(depth->plane(0), img.npixels(), img.plane(3));
    SliceOptions opt;
    opt.source.depth_decode.encoding = DepthEncoding::Scaled;
    opt.source.depth_decode.scale = 65535.0 / 5000.0;  // normalised 16-bit counts -> metres
    opt.extend_px = 8;
    for (const char* split : {"auto", "4"}) {
        opt.split = *parse_layer_split(split);
        auto r = layers_from_depth_map(img, opt);
        ASSERT_TRUE(r) << r.message();
        std::size_t holes = 0;
        for (std::size_t i = 0; i < img.npixels(); ++i) holes += img.plane(3)[i] == 0.0f;
        std::cout << "[ measured ] TUM depth map, split " << split << ": " << r->size() << " slices:";
        for (const auto& l : *r) std::cout << " [" << l.name << "]";
        std::cout << "; " << holes << " invalid depth pixels (in the farthest slice)\n";
        // Opaque input: the slices composite back to it exactly, and the
        // farthest slice is opaque everywhere (its own pixels + extension).
        Image comp = composite_layers(pointers(*r), img.data_window()).value();
        double m = 0;
        for (std::size_t i = 0; i < img.npixels(); ++i)
            for (int c = 0; c < 3; ++c) m = std::max(m, double(std::fabs(comp.plane(c)[i] - img.plane(c)[i])));
        EXPECT_EQ(m, 0.0) << split;
        const Layer* far = nullptr;
        for (const auto& l : *r)
            if (!l.image.data_window().empty()) far = &l;
        ASSERT_NE(far, nullptr);
        EXPECT_EQ(far->image.data_window(), img.data_window());
        for (std::size_t i = 0; i < far->image.npixels(); ++i) ASSERT_EQ(far->image.plane(3)[i], 1.0f) << i;
    }
}
