// composite(), method 2 in one call: bit-identical to the step-by-step
// orchestration `gdof --composite` ran before it (desired focus, index,
// selection, tiles at the first used reference's origin, its windows and
// metadata) for every focus source, hard and soft, with AOVs; a region into
// strided memory (an OFX host's bottom-up rows, RGB or RGBA) equals the crop
// of the whole result; a render scale is its area-mean reduction; only the
// chosen references are prepared and read; errors name the input at fault.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "defocus_test_helpers.h"
#include "gdof/blur_field.h"
#include "gdof/compositing.h"
#include "gdof/focal_stack.h"
#include "gdof/focus_surfaces.h"

namespace gdof {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int W = 53, H = 37;             // not multiples of the tile size
const Roi kGrid{-4, 6, -4 + W, 6 + H};    // the references' data window, away from the origin
const Roi kDisplay{0, 0, 48, 44};

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string describe(const Metadata& m) {
    std::string s;
    for (const Attribute& a : m.attributes()) {
        s += a.name + ":" + a.type + "=" + a.text;
        for (double v : a.numbers) s += " " + std::to_string(v);
        s += ";";
    }
    return s;
}

// Reference i: distinct texture, alpha < 1 in places, lens and camera metadata.
Image make_ref(int i) {
    Image img = Image::with_channels({"R", "G", "B", "A"}, kGrid);
    img.set_display_window(kDisplay);
    for (int y = kGrid.y0; y < kGrid.y1; ++y)
        for (int x = kGrid.x0; x < kGrid.x1; ++x) {
            img.at(0, x, y) = float(i) + 0.01f * float(x);
            img.at(1, x, y) = 0.3f * float(i) + 0.007f * float((x * y) % 13);
            img.at(2, x, y) = std::sin(0.37f * float(x) + 0.11f * float(y) + float(i));
            img.at(3, x, y) = (x + y + i) % 5 == 0 ? 0.5f : 1.0f;
        }
    img.metadata.set_float("focusDistance", 1.0 + i);
    img.metadata.set_float("fNumber", 2.8);
    img.metadata.set_float("focalLength", 50.0);
    img.metadata.set_string("gdof:test", "reference " + std::to_string(i));
    return img;
}

struct Fixture {
    FocalStack stack;
    std::vector<Image> images;
    Fixture() {
        const std::vector<DepthInterval> limits = {{1.0, 1.5}, {1.4, 2.2}, {2.0, 3.5}, {3.0, 8.0}, {5.0, kInf}, {1.2, 1.9}};
        for (std::size_t i = 0; i < limits.size(); ++i) {
            StackReference r;
            r.file = r.path = "ref." + std::to_string(i) + ".exr";
            r.near = limits[i].near;
            r.far = limits[i].far;
            stack.references.push_back(r);
            images.push_back(make_ref(int(i)));
        }
    }
    std::vector<const Image*> ptrs() const {
        std::vector<const Image*> p;
        for (const Image& i : images) p.push_back(&i);
        return p;
    }
};

// Surfaces across the stack: near 1 .. 5, far 1.5 .. 9.
FocusSurfaces surfaces() {
    auto s = parse_focus_surfaces(R"({"gdof_surfaces": 1, "near": {"grid": [[1, 2, 5], [1.2, 3, 5]]},
                                      "far": {"grid": [[1.5, 3.5, 8], [1.9, 8, 9]]}})");
    EXPECT_TRUE(s) << s.message();
    return s.value();
}

// Near/far maps (W x H, at the grid's origin) with NaN holes.
struct Maps {
    Image near = Image::with_channels({"near"}, {0, 0, W, H});
    Image far = Image::with_channels({"far"}, {0, 0, W, H});
    Maps() {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const bool hole = (x * 7 + y * 3) % 31 == 0;
                near.at(0, x, y) = hole ? kNaN : 1.0f + 4.0f * float(x) / float(W);
                far.at(0, x, y) = hole ? kNaN : near.at(0, x, y) + 0.5f + 0.2f * float(y);
            }
    }
};

// A depth image over the grid (1 .. 8) and sharp planes at 1.2, 2.5 and 6.
struct BlurSource {
    Image depth = Image::with_channels({"Z"}, kGrid);
    Camera camera = test::test_camera(kDisplay);
    BlurField field;
    BlurSource() {
        for (int y = kGrid.y0; y < kGrid.y1; ++y)
            for (int x = kGrid.x0; x < kGrid.x1; ++x) depth.at(0, x, y) = 1.0f + 0.1f * float(x - kGrid.x0) + 0.05f * float(y);
        auto f = BlurField::parse(
            R"({"blurfield": {"kind": "focal_planes", "depths": [1.2, 2.5, 6], "max_blur": 10, "slope": 4}})");
        EXPECT_TRUE(f) << f.message();
        field = f.value();
    }
};

// What run_composite did before composite() existed: the steps by hand.
Image step_by_step(const FocalStack& stack, const DesiredFocus& desired, StackPixels& pixels, const CompositeOptions& cs) {
    std::vector<DepthInterval> limits;
    for (const StackReference& r : stack.references) limits.push_back({r.near, r.far});
    const StackIndex index = StackIndex::build(limits).value();
    const StackSelection sel = select_references(index, desired, cs).value();
    const std::vector<int> used = sel.used_references();
    EXPECT_FALSE(used.empty());
    const ReferenceInfo info = pixels.info(used.front()).value();
    Image out = composite_stack(sel, pixels, cs, info.data_window.x0, info.data_window.y0).value();
    out.set_display_window(info.display_window);
    out.metadata = info.metadata;
    for (const char* a : {"focusDistance", "focus", "fNumber", "aperture"}) out.metadata.erase(a);
    return out;
}

void expect_same_image(const Image& a, const Image& b) {
    ASSERT_EQ(a.channels(), b.channels());
    ASSERT_EQ(a.data_window(), b.data_window());
    EXPECT_EQ(a.display_window(), b.display_window());
    EXPECT_EQ(describe(a.metadata), describe(b.metadata));
    long bad = 0;
    for (int c = 0; c < a.nchannels(); ++c)
        for (std::size_t i = 0; i < a.npixels(); ++i) bad += !same_bits(a.plane(c)[i], b.plane(c)[i]);
    EXPECT_EQ(bad, 0) << "samples differ";
}

std::vector<CompositeOptions> option_sets() {
    CompositeOptions hard, soft, aovs;
    soft.soft_k = 3;
    soft.tile_size = 16;
    aovs.aovs = true;
    aovs.soft_k = 2;
    return {hard, soft, aovs};
}

TEST(compositing_pipeline, composite_equals_the_step_by_step_orchestration_for_every_source) {
    Fixture fx;
    const Maps maps;
    const BlurSource blur;
    BlurFocusOptions bs;
    bs.coc_px = 1.0;
    struct Case {
        std::string name;
        FocusSource source;
        DesiredFocus desired;
    };
    std::vector<Case> cases;
    cases.push_back({"surfaces", surfaces(), desired_from_surfaces(surfaces(), W, H).value()});
    cases.push_back({"maps", FocusMaps{&maps.near, 0, &maps.far, 0}, desired_from_maps(maps.near, 0, maps.far, 0).value()});
    cases.push_back({"blur field", FocusFromBlurField{&blur.field, &blur.camera, &blur.depth, bs},
                     desired_from_blur_field(blur.field, blur.camera, blur.depth, bs).value()});
    for (const Case& c : cases)
        for (const CompositeOptions& cs : option_sets()) {
            SCOPED_TRACE(c.name + ", soft " + std::to_string(cs.soft_k) + (cs.aovs ? ", aovs" : ""));
            MemoryStackPixels old_px(fx.ptrs()), new_px(fx.ptrs());
            const Image expected = step_by_step(fx.stack, c.desired, old_px, cs);
            CompositeStats st;
            auto got = composite(fx.stack, c.source, new_px, cs, &st);
            ASSERT_TRUE(got) << got.message();
            expect_same_image(got.value(), expected);
            EXPECT_GE(st.references_used, 2) << "the case exercises the selection";
            EXPECT_EQ(int(st.used_references.size()), st.references_used);
            EXPECT_EQ(st.references, int(fx.images.size()));
            EXPECT_FALSE(got->metadata.has("focusDistance")) << "no single lens describes the result";
            EXPECT_TRUE(got->metadata.has("gdof:test"));
            for (int i = 0; i < int(fx.images.size()); ++i) EXPECT_EQ(old_px.reads(i), new_px.reads(i)) << "reference " << i;
        }
}

// Interleaved memory with `n` channels over `window`, rows stored bottom-up
// with padding (as an OFX host does), guard values everywhere first.
struct HostBuffer {
    static constexpr float kGuard = -777.0f;
    Roi window;
    int n = 4, row = 0;
    std::vector<float> px;
    HostBuffer(const Roi& w, int nch) : window(w), n(nch), row(w.width() * nch + 3) {
        px.assign(std::size_t(row) * std::size_t(std::max(1, w.height())), kGuard);
    }
    // gdof row y is stored at index (window.y1 - 1 - y): the top row last.
    ImageView view() {
        if (window.empty()) return {nullptr, n, window, 1, n, 0};
        return ImageView::interleaved(&px[std::size_t(window.height() - 1) * std::size_t(row)], n, window, -row);
    }
    float at(int c, int x, int y) const {
        return px[std::size_t(window.y1 - 1 - y) * std::size_t(row) + std::size_t(x - window.x0) * std::size_t(n) + std::size_t(c)];
    }
    bool padding_untouched() const {
        for (int r = 0; r < window.height(); ++r)
            for (int i = window.width() * n; i < row; ++i)
                if (px[std::size_t(r) * std::size_t(row) + std::size_t(i)] != kGuard) return false;
        return true;
    }
};

TEST(compositing_pipeline, a_region_into_bottom_up_host_memory_equals_the_crop_of_the_whole) {
    Fixture fx;
    const FocusSource focus = surfaces();
    const std::vector<Roi> regions = {
        {3, 10, 30, 29},                                        // inside
        {kGrid.x0 - 5, kGrid.y0 - 2, kGrid.x0 + 9, kGrid.y0 + 11},  // over the top-left corner
        kGrid.grown(4),                                         // all of it and a border
        {100, 100, 120, 110},                                   // outside
        {10, 20, 11, 21},                                       // one pixel
    };
    for (const CompositeOptions& cs : option_sets()) {
        MemoryStackPixels whole_px(fx.ptrs());
        const Image whole = composite(fx.stack, focus, whole_px, cs).value();
        const Roi& dw = whole.data_window();
        for (const Roi& region : regions)
            for (int n : cs.aovs ? std::vector<int>{6} : std::vector<int>{3, 4}) {
                SCOPED_TRACE("region " + to_string(region) + ", " + std::to_string(n) + " channels, soft " +
                             std::to_string(cs.soft_k));
                HostBuffer host(region, n);
                MemoryStackPixels px(fx.ptrs());
                CompositeStats st;
                ASSERT_TRUE(composite(fx.stack, focus, px, CompositeTarget{host.view()}, cs, &st));
                long bad = 0;
                for (int y = region.y0; y < region.y1; ++y)
                    for (int x = region.x0; x < region.x1; ++x)
                        for (int c = 0; c < n; ++c) {
                            const float want = dw.contains(x, y) ? whole.at(c, x, y) : 0.0f;
                            bad += !same_bits(host.at(c, x, y), want);
                        }
                EXPECT_EQ(bad, 0);
                EXPECT_TRUE(host.padding_untouched());
                if (intersect(region, dw).empty()) {
                    EXPECT_EQ(st.tile_reads, 0) << "nothing to read";
                }
            }
    }
}

TEST(compositing_pipeline, a_render_scale_is_the_area_mean_of_the_full_result) {
    Fixture fx;
    const FocusSource focus = surfaces();
    MemoryStackPixels whole_px(fx.ptrs());
    CompositeOptions cs;
    cs.soft_k = 2;
    const Image whole = composite(fx.stack, focus, whole_px, cs).value();
    const Roi& dw = whole.data_window();
    for (double s : {0.5, 0.25}) {
        SCOPED_TRACE("scale " + std::to_string(s));
        const Roi region{int(std::floor(dw.x0 * s)) - 1, int(std::floor(dw.y0 * s)), int(std::ceil(dw.x1 * s)),
                         int(std::ceil(dw.y1 * s)) + 1};
        HostBuffer host(region, 4);
        MemoryStackPixels px(fx.ptrs());
        ASSERT_TRUE(composite(fx.stack, focus, px, CompositeTarget{host.view(), s, s}, cs));
        const int k = int(std::lround(1.0 / s));
        double worst = 0;
        for (int y = region.y0; y < region.y1; ++y)
            for (int x = region.x0; x < region.x1; ++x)
                for (int c = 0; c < 4; ++c) {
                    double sum = 0;
                    int count = 0;
                    for (int v = y * k; v < (y + 1) * k; ++v)
                        for (int u = x * k; u < (x + 1) * k; ++u)
                            if (dw.contains(u, v)) sum += whole.at(c, u, v), ++count;
                    const double want = count ? sum / count : 0.0;
                    worst = std::max(worst, std::abs(double(host.at(c, x, y)) - want));
                }
        EXPECT_LE(worst, 1e-6);
        EXPECT_TRUE(host.padding_untouched());
    }
}

// Records what composite() asks of a source.
class Recording final : public StackPixels {
public:
    explicit Recording(StackPixels& inner) : inner_(inner) {}
    int size() const override { return inner_.size(); }
    Result<ReferenceInfo> info(int ref) override { return inner_.info(ref); }
    Status prepare(const std::vector<int>& refs, const Roi& region) override {
        ++prepares;
        prepared = refs;
        prepared_region = region;
        return inner_.prepare(refs, region);
    }
    Status read_tile(int ref, const Roi& tile, float* rgba) override {
        std::lock_guard<std::mutex> lock(mu_);
        read_refs.push_back(ref);
        read_bounds = unite(read_bounds, tile);
        if (fail_reads) return Status::error("reference " + std::to_string(ref) + ": the disk is on fire");
        return inner_.read_tile(ref, tile, rgba);
    }
    int prepares = 0;
    std::vector<int> prepared, read_refs;
    Roi prepared_region, read_bounds;
    bool fail_reads = false;

private:
    StackPixels& inner_;
    std::mutex mu_;
};

TEST(compositing_pipeline, only_the_chosen_references_are_prepared_and_read_over_the_region) {
    Fixture fx;
    const Roi region{10, 12, 40, 30};  // absolute
    for (const CompositeOptions& cs : option_sets()) {
        MemoryStackPixels mem(fx.ptrs());
        Recording rec(mem);
        HostBuffer host(region, cs.aovs ? 6 : 4);
        CompositeStats st;
        ASSERT_TRUE(composite(fx.stack, FocusSource{surfaces()}, rec, CompositeTarget{host.view()}, cs, &st));
        EXPECT_EQ(rec.prepares, 1);
        EXPECT_EQ(rec.prepared, st.used_references);
        const Roi local{region.x0 - kGrid.x0, region.y0 - kGrid.y0, region.x1 - kGrid.x0, region.y1 - kGrid.y0};
        EXPECT_EQ(rec.prepared_region, local) << "the region in the stack's local coordinates";
        EXPECT_EQ(rec.read_bounds, local);
        for (int r : rec.read_refs)
            EXPECT_NE(std::find(rec.prepared.begin(), rec.prepared.end(), r), rec.prepared.end()) << "read " << r;
        EXPECT_LT(int(rec.prepared.size()), int(fx.images.size())) << "some reference is left out";
    }
}

TEST(compositing_pipeline, errors_name_the_input_at_fault) {
    Fixture fx;
    MemoryStackPixels px(fx.ptrs());
    // The desired focus is not the stack's size.
    FocalStack sized = fx.stack;
    sized.width = W + 1;
    sized.height = H;
    auto r = composite(sized, FocusSource{surfaces()}, px);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().subject(), "focus");
    EXPECT_NE(r.message().find("54x37"), std::string::npos) << r.message();
    const Maps maps;
    Image small = Image::with_channels({"far"}, {0, 0, W - 1, H});
    r = composite(fx.stack, FocusMaps{&maps.near, 0, &small, 0}, px);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().subject(), "focus") << r.message();
    // The references' near/far.
    FocalStack bad = fx.stack;
    bad.references[2].near = -1;
    r = composite(bad, FocusSource{surfaces()}, px);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().subject(), "stack");
    EXPECT_NE(r.message().find("reference 2"), std::string::npos) << r.message();
    // Their pixels.
    Recording failing(px);
    failing.fail_reads = true;
    r = composite(fx.stack, FocusSource{surfaces()}, failing);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().subject(), "pixels");
    EXPECT_NE(r.message().find("on fire"), std::string::npos) << r.message();
    // Nothing selected: no reference to take the whole result's windows from; a region is 0.
    Image nan_map = Image::with_channels({"near"}, {0, 0, W, H});
    for (std::size_t i = 0; i < nan_map.npixels(); ++i) nan_map.plane(0)[i] = kNaN;
    r = composite(fx.stack, FocusMaps{&nan_map, 0, &nan_map, 0}, px);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.status().subject().empty());
    EXPECT_NE(r.message().find("no pixel selected"), std::string::npos) << r.message();
    HostBuffer host({0, 10, 8, 14}, 4);
    ASSERT_TRUE(composite(fx.stack, FocusMaps{&nan_map, 0, &nan_map, 0}, px, CompositeTarget{host.view()}));
    for (int y = 10; y < 14; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_EQ(host.at(3, x, y), 0.0f);
    // A target without the channels asked for, or a bad scale.
    HostBuffer five({0, 10, 8, 14}, 5);
    Status st = composite(fx.stack, FocusSource{surfaces()}, px, CompositeTarget{five.view()});
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument) << st.message();
    CompositeOptions aovs;
    aovs.aovs = true;
    st = composite(fx.stack, FocusSource{surfaces()}, px, CompositeTarget{host.view()}, aovs);
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument) << st.message();
    st = composite(fx.stack, FocusSource{surfaces()}, px, CompositeTarget{host.view(), 0.0, 1.0});
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument) << st.message();
}

TEST(compositing_pipeline, view_references_read_host_memory_in_place) {
    // Reference 0: RGB over part of the grid (alpha 1 there); reference 1:
    // RGBA, rows bottom-up; both 0 (alpha too) where they have no pixel.
    const Roi grid{2, 3, 12, 9};
    HostBuffer rgb({4, 3, 10, 7}, 3), rgba(grid, 4);
    for (int y = 3; y < 7; ++y)
        for (int x = 4; x < 10; ++x)
            for (int c = 0; c < 3; ++c) rgb.view().at(c, x, y) = float(100 * c + 10 * y + x);
    for (int y = grid.y0; y < grid.y1; ++y)
        for (int x = grid.x0; x < grid.x1; ++x)
            for (int c = 0; c < 4; ++c) rgba.view().at(c, x, y) = float(1000 * c + 10 * y + x) * 0.5f;
    auto as_const = [](const ImageView& v) { return ConstImageView{v.base, v.nchannels, v.window, v.cstride, v.xstride, v.ystride}; };
    ViewStackPixels px({as_const(rgb.view()), ConstImageView{}}, grid);
    px.set_view(1, as_const(rgba.view()));
    EXPECT_EQ(px.size(), 2);
    EXPECT_EQ(px.info(1)->data_window, grid);
    const Roi tile{0, 0, 10, 6};  // local: the whole grid
    std::vector<float> buf(tile.npixels() * 4);
    ASSERT_TRUE(px.read_tile(0, tile, buf.data()));
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 10; ++x) {
            const int ax = grid.x0 + x, ay = grid.y0 + y;
            const bool in = rgb.window.contains(ax, ay);
            const float* p = &buf[(std::size_t(y) * 10 + std::size_t(x)) * 4];
            for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], in ? float(100 * c + 10 * ay + ax) : 0.0f);
            EXPECT_EQ(p[3], in ? 1.0f : 0.0f);
        }
    ASSERT_TRUE(px.read_tile(1, {1, 2, 4, 5}, buf.data()));
    for (int y = 2; y < 5; ++y)
        for (int x = 1; x < 4; ++x)
            for (int c = 0; c < 4; ++c)
                EXPECT_EQ(buf[(std::size_t(y - 2) * 3 + std::size_t(x - 1)) * 4 + std::size_t(c)],
                          float(1000 * c + 10 * (grid.y0 + y) + grid.x0 + x) * 0.5f);
    EXPECT_FALSE(px.read_tile(1, {0, 0, 11, 1}, buf.data())) << "outside the grid";
    EXPECT_FALSE(px.read_tile(2, tile, buf.data()));
}

}  // namespace
}  // namespace gdof
