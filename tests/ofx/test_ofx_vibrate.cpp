// "gdof Defocus" with filter vibrate (method 4, the generalized PSF field)
// through the test host against `gdof --vibrate` on the same plate, the same
// blur field, PSF-field file and sample count; and tiles against the whole
// render.
#include "ofx/ofx_defocus_fixture.h"

using namespace gdof::test;
using namespace gdof::test::defocus_fixture;

namespace {

// A swirl added to the defocus discs: a field whose look neither diffusion
// nor bokeh can give, so equal results cannot come from the wrong filter.
const char* kSwirlField = R"({"psf_field": {"kind": "sum", "children": [
    {"kind": "defocus"}, {"kind": "swirl", "strength": 2, "power": 1}]}})";

void set_vibrate(Instance& fx, const std::string& psf_file, int samples) {
    fx.set_choice("filter", "vibrate");
    fx.set_string("psf_field", psf_file);
    fx.set_int("psf_samples", samples);
}

}  // namespace

// The PSF-field file and sample count are read as the CLI reads
// --psf-field and --psf-samples: the same pixels. Without a file it is the
// defocus field, as --vibrate without --psf-field.
TEST(ofx_vibrate, VibrateFilterEqualsCliVibrate) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    f.s.fx->set_choice("filter", "bokeh");
    const Rendered bokeh = f.s.fx->render(0, kFull);
    ASSERT_EQ(bokeh.status, kOfxStatOK) << f.s.fx->persistent_message();

    const std::string psf = f.dir.file("swirl.json");
    write_text(psf, kSwirlField);
    set_vibrate(*f.s.fx, psf, 48);
    const Rendered swirl = f.s.fx->render(0, kFull);
    ASSERT_EQ(swirl.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double d = max_diff_to_file(swirl, f.cli(kPlanesJson, "--psf-field " + quote(psf) + " --psf-samples 48", false, "--vibrate"), 4, H);

    set_vibrate(*f.s.fx, "", 48);
    const Rendered disc = f.s.fx->render(0, kFull);
    ASSERT_EQ(disc.status, kOfxStatOK) << f.s.fx->persistent_message();
    const double dd = max_diff_to_file(disc, f.cli(kPlanesJson, "--psf-samples 48", false, "--vibrate"), 4, H);

    const double swirl_vs_disc = max_diff(swirl, disc), disc_vs_bokeh = max_diff(disc, bokeh);
    std::printf("OFX vibrate vs CLI --vibrate: swirl field max |diff| = %.3g, default field %.3g; swirl vs disc %.3g, "
                "vibrate disc vs bokeh disc %.3g\n", d, dd, swirl_vs_disc, disc_vs_bokeh);
    EXPECT_LE(d, 1e-5);
    EXPECT_LE(dd, 1e-5);
    EXPECT_GT(swirl_vs_disc, 1e-2) << "the file's swirl was applied";
    EXPECT_GT(disc_vs_bokeh, 1e-4) << "the vibrate filter ran, not bokeh";
    EXPECT_FALSE(swirl.wrote_outside);
    EXPECT_EQ(f.s.host.live_images(), 0) << "every image fetched is released";
}

// Tiles (one after the other and from several threads) equal the whole
// render bit for bit: with analysis = frame every tile sees the whole plate,
// the layers are moved over the whole frame (visibility after the move is
// global) and the tile is cropped from it; the samples sum in a fixed order.
TEST(ofx_vibrate, FourTilesEqualTheWholeRender) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    set_planes(*f.s.fx);
    const std::string psf = f.dir.file("swirl.json");
    write_text(psf, kSwirlField);
    set_vibrate(*f.s.fx, psf, 32);
    const auto [whole, tiled, concurrent] = render_tiled(*f.s.fx);
    ASSERT_EQ(whole.status, kOfxStatOK);
    std::printf("vibrate: 4 tiles vs whole: max |diff| = %.3g (concurrent tiles: %.3g)\n", max_diff(whole, tiled),
                max_diff(whole, concurrent));
    EXPECT_EQ(max_diff(whole, tiled), 0.0);
    EXPECT_EQ(max_diff(whole, concurrent), 0.0);
    EXPECT_FALSE(tiled.wrote_outside);
    EXPECT_EQ(f.s.host.live_images(), 0);
}
