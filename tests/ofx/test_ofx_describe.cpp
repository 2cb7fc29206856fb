// The bundle through the test host: loading, the plugins it lists, and what
// describe / describeInContext report (contexts, pixel depths, flags, clips,
// parameters), for both effects and both contexts; unload and reload.
#include <algorithm>

#include "gdof/diffusion.h"
#include "ofx/ofx_test_support.h"

using namespace gdof::test;
using gdof::ofxtest::ImageEffect;
using gdof::ofxtest::PropertySet;

namespace {

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

const PropertySet& clip(const ImageEffect& d, const std::string& name) {
    static const PropertySet none;
    auto it = d.clips.find(name);
    return it == d.clips.end() ? none : it->second->props;
}

const PropertySet* param(const ImageEffect& d, const std::string& name) {
    auto it = d.params.params.find(name);
    return it == d.params.params.end() ? nullptr : &it->second->props;
}

struct Described {
    Host host;
    Described() {
        std::string err;
        EXPECT_TRUE(host.load(bundle_binary(), &err)) << err;
        for (const char* id : {kDefocusId, kFocalStackId}) {
            EXPECT_EQ(host.describe(id), kOfxStatOK) << id;
            for (const char* ctx : {kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral})
                EXPECT_EQ(host.describe_in_context(id, ctx), kOfxStatOK) << id << " " << ctx;
        }
    }
    const ImageEffect& desc(const char* id) { return *host.plugin(id)->descriptor; }
    const ImageEffect& ctx(const char* id, const char* c) { return *host.plugin(id)->contexts.at(c); }
};

}  // namespace

TEST(ofx_describe, BundleListsTheTwoEffectsAsImageEffectPluginsV1) {
    Host host;
    std::string err;
    ASSERT_TRUE(host.load(bundle_binary(), &err)) << err;
    const auto ids = host.plugin_ids();
    EXPECT_EQ(ids, (std::vector<std::string>{kDefocusId, kFocalStackId}));
    for (const auto& id : ids) {
        const OfxPlugin* p = host.plugin(id)->ofx;
        EXPECT_STREQ(p->pluginApi, kOfxImageEffectPluginApi);
        EXPECT_EQ(p->apiVersion, 1);
        EXPECT_EQ(host.plugin(id)->load_status, kOfxStatOK);
    }
    // The suites it asked for at load: the three it needs, plus messages and threads.
    for (const char* s : {"OfxPropertySuite v1", "OfxParameterSuite v1", "OfxImageEffectSuite v1", "OfxMessageSuite v2",
                          "OfxMultiThreadSuite v1"})
        EXPECT_TRUE(has(host.suites_fetched, s)) << s;
}

TEST(ofx_describe, EffectsDeclareContextsFloatDepthTilesMultiResolutionAndThreading) {
    Described d;
    for (const char* id : {kDefocusId, kFocalStackId}) {
        const PropertySet& p = d.desc(id).props;
        EXPECT_EQ(p.strings(kOfxImageEffectPropSupportedContexts),
                  (std::vector<std::string>{kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral}))
            << id;
        EXPECT_EQ(p.strings(kOfxImageEffectPropSupportedPixelDepths), (std::vector<std::string>{kOfxBitDepthFloat})) << id;
        EXPECT_EQ(p.integer(kOfxImageEffectPropSupportsTiles), 1) << id;
        EXPECT_EQ(p.integer(kOfxImageEffectPropSupportsMultiResolution), 1) << id;
        EXPECT_EQ(p.integer(kOfxImageEffectPluginPropHostFrameThreading), 0) << id << ": the library threads itself";
        EXPECT_EQ(p.str(kOfxImageEffectPluginRenderThreadSafety), kOfxImageEffectRenderFullySafe) << id;
        EXPECT_EQ(p.integer(kOfxImageEffectPluginPropSingleInstance), 0) << id;
        EXPECT_EQ(p.integer(kOfxImageEffectPropSupportsMultipleClipDepths), 0) << id;
        EXPECT_EQ(p.str(kOfxImageEffectPluginPropGrouping), "gdof") << id;
        EXPECT_FALSE(p.str(kOfxPropPluginDescription).empty()) << id;
    }
    EXPECT_EQ(d.desc(kDefocusId).props.str(kOfxPropLabel), "gdof Defocus");
    EXPECT_EQ(d.desc(kFocalStackId).props.str(kOfxPropLabel), "gdof Focal Stack");
    EXPECT_EQ(d.desc(kDefocusId).props.integer(kOfxImageEffectPropTemporalClipAccess), 0);
    EXPECT_EQ(d.desc(kFocalStackId).props.integer(kOfxImageEffectPropTemporalClipAccess), 1)
        << "the focal stack reads other frames of Source";
}

TEST(ofx_describe, DefocusClipsInBothContexts) {
    Described d;
    for (const char* c : {kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral}) {
        const ImageEffect& e = d.ctx(kDefocusId, c);
        EXPECT_EQ(e.clip_order, (std::vector<std::string>{"Source", "Depth", "BlurMap", "Mask", "Aperture", "Output"})) << c;
        EXPECT_EQ(clip(e, "Source").strings(kOfxImageEffectPropSupportedComponents),
                  (std::vector<std::string>{kOfxImageComponentRGBA, kOfxImageComponentRGB}));
        EXPECT_EQ(clip(e, "Source").integer(kOfxImageClipPropOptional), 0);
        EXPECT_EQ(clip(e, "Depth").integer(kOfxImageClipPropOptional), 1) << "checked at render, with a message";
        EXPECT_TRUE(has(clip(e, "Depth").strings(kOfxImageEffectPropSupportedComponents), kOfxImageComponentAlpha));
        EXPECT_EQ(clip(e, "BlurMap").str(kOfxPropLabel), "Blur Map");
        EXPECT_EQ(clip(e, "Mask").integer(kOfxImageClipPropIsMask), 1);
        EXPECT_EQ(clip(e, "Mask").integer(kOfxImageClipPropOptional), 1);
        EXPECT_EQ(clip(e, "Output").strings(kOfxImageEffectPropSupportedComponents),
                  (std::vector<std::string>{kOfxImageComponentRGBA, kOfxImageComponentRGB}));
        for (const char* n : {"Source", "Depth", "BlurMap", "Mask", "Output"})
            EXPECT_EQ(clip(e, n).integer(kOfxImageEffectPropSupportsTiles), 1) << n;
    }
}

TEST(ofx_describe, DefocusParametersMirrorTheBlurFieldWithJsonAndCliNames) {
    Described d;
    const ImageEffect& e = d.ctx(kDefocusId, kOfxImageEffectContextGeneral);
    struct Expect {
        const char* name;
        const char* type;
    };
    const Expect expected[] = {
        {"kind", kOfxParamTypeChoice},          {"max_radius", kOfxParamTypeDouble},
        {"focal_length_mm", kOfxParamTypeDouble}, {"sensor_width_mm", kOfxParamTypeDouble},
        {"f_number", kOfxParamTypeDouble},      {"focus_distance", kOfxParamTypeDouble},
        {"scene_unit_mm", kOfxParamTypeDouble}, {"depths_count", kOfxParamTypeInteger},
        {"depths_1", kOfxParamTypeDouble},      {"depths_6", kOfxParamTypeDouble},
        {"max_blur", kOfxParamTypeDouble},      {"slope", kOfxParamTypeDouble},
        {"interpolation", kOfxParamTypeChoice}, {"shape", kOfxParamTypeChoice},
        {"mode", kOfxParamTypeChoice},          {"center", kOfxParamTypeDouble3D},
        {"radius", kOfxParamTypeDouble},        {"size", kOfxParamTypeDouble3D},
        {"normal", kOfxParamTypeDouble3D},      {"thickness", kOfxParamTypeDouble},
        {"blur", kOfxParamTypeDouble},          {"falloff", kOfxParamTypeDouble},
        {"map_channel", kOfxParamTypeChoice},   {"map_scale", kOfxParamTypeDouble},
        {"depth_pass", kOfxParamTypeChoice},    {"depth_channel", kOfxParamTypeChoice},
        {"depth_encoding", kOfxParamTypeChoice}, {"depth_scale", kOfxParamTypeDouble},
        {"depth_near", kOfxParamTypeDouble},    {"depth_far", kOfxParamTypeDouble},
        {"solver", kOfxParamTypeChoice},        {"adi_steps", kOfxParamTypeInteger},
        {"layers", kOfxParamTypeInteger},       {"analysis", kOfxParamTypeChoice},
        {"cut_by_blur", kOfxParamTypeBoolean},  {"filter", kOfxParamTypeChoice},
        {"psf_field", kOfxParamTypeString},     {"psf_samples", kOfxParamTypeInteger},
    };
    for (const Expect& x : expected) {
        const PropertySet* p = param(e, x.name);
        ASSERT_TRUE(p) << "parameter " << x.name << " missing";
        EXPECT_EQ(p->str(kOfxParamPropType), x.type) << x.name;
        EXPECT_EQ(p->str(kOfxParamPropScriptName), x.name) << x.name;
        EXPECT_FALSE(p->str(kOfxParamPropHint).empty()) << x.name << " has no hint";
    }
    EXPECT_EQ(param(e, "kind")->strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"thin_lens", "focal_planes", "region", "image_map"}));
    EXPECT_EQ(param(e, "solver")->strings(kOfxParamPropChoiceOption), (std::vector<std::string>{"adi", "explicit", "auto"}));
    // The solver's default is the library's (DiffusionOptions: auto), as `gdof --diffuse` without --solver.
    const std::vector<std::string> solvers = param(e, "solver")->strings(kOfxParamPropChoiceOption);
    const int solver_default = param(e, "solver")->integer(kOfxParamPropDefault);
    ASSERT_GE(solver_default, 0);
    ASSERT_LT(solver_default, int(solvers.size()));
    EXPECT_EQ(solvers[std::size_t(solver_default)], gdof::to_string(gdof::DiffusionOptions{}.solver));
    EXPECT_EQ(solvers[std::size_t(solver_default)], "auto");
    EXPECT_EQ(param(e, "depth_encoding")->strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"metric", "inverse", "scaled", "near_far_linear", "near_far_inverse"}));
    EXPECT_EQ(param(e, "analysis")->strings(kOfxParamPropChoiceOption), (std::vector<std::string>{"frame", "region"}));
    // The three filters, as the CLI's --diffuse, --bokeh and --vibrate (saved by index: new ones last).
    EXPECT_EQ(param(e, "filter")->strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"diffusion", "bokeh", "vibrate"}));
    EXPECT_EQ(param(e, "psf_field")->str(kOfxParamPropStringMode), kOfxParamStringIsFilePath);
    EXPECT_EQ(param(e, "psf_samples")->integer(kOfxParamPropDefault), 0) << "0: automatic, as --psf-samples";
    EXPECT_EQ(param(e, "focal_length_mm")->dbl(kOfxParamPropDefault), 50.0);
    EXPECT_EQ(param(e, "sensor_width_mm")->dbl(kOfxParamPropDefault), 36.0);
    EXPECT_EQ(param(e, "scene_unit_mm")->dbl(kOfxParamPropDefault), 1000.0);
    // Parameters sit in groups that exist.
    for (const auto& [name, p] : e.params.params) {
        const std::string parent = p->props.str(kOfxParamPropParent);
        if (!parent.empty()) {
            EXPECT_TRUE(param(e, parent)) << name << " has parent " << parent;
        }
    }
}

TEST(ofx_describe, FocalStackClipsAndParameters) {
    Described d;
    for (const char* c : {kOfxImageEffectContextFilter, kOfxImageEffectContextGeneral}) {
        const ImageEffect& e = d.ctx(kFocalStackId, c);
        EXPECT_EQ(e.clip_order, (std::vector<std::string>{"Source", "Near", "Far", "Output"})) << c;
        EXPECT_EQ(clip(e, "Source").integer(kOfxImageEffectPropTemporalClipAccess), 1);
        EXPECT_EQ(clip(e, "Near").integer(kOfxImageClipPropOptional), 1);
        EXPECT_EQ(clip(e, "Far").integer(kOfxImageClipPropOptional), 1);
    }
    const ImageEffect& e = d.ctx(kFocalStackId, kOfxImageEffectContextGeneral);
    for (const char* n : {"stack_source", "manifest", "lens_table", "first_frame", "coc_px", "focal_length_mm",
                          "sensor_width_mm", "scene_unit_mm", "soft", "focus_source", "surfaces", "grid", "interpolate",
                          "far_infinite", "map_channel", "near_00", "near_33", "far_00", "far_33"})
        EXPECT_TRUE(param(e, n)) << "parameter " << n << " missing";
    EXPECT_EQ(param(e, "manifest")->str(kOfxParamPropStringMode), kOfxParamStringIsFilePath);
    EXPECT_EQ(param(e, "lens_table")->str(kOfxParamPropStringMode), kOfxParamStringIsMultiLine);
    EXPECT_EQ(param(e, "stack_source")->strings(kOfxParamPropChoiceOption), (std::vector<std::string>{"frames", "files"}));
    EXPECT_EQ(param(e, "focus_source")->strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"surfaces", "surfaces_file", "maps"}));
}

TEST(ofx_describe, UnloadAndReloadGiveTheSameDescription) {
    Host host;
    std::string err;
    ASSERT_TRUE(host.load(bundle_binary(), &err)) << err;
    ASSERT_EQ(host.describe(kDefocusId), kOfxStatOK);
    const auto first = host.plugin(kDefocusId)->descriptor->props.strings(kOfxImageEffectPropSupportedContexts);
    host.unload();
    EXPECT_FALSE(host.loaded());
    ASSERT_TRUE(host.load(bundle_binary(), &err)) << err;
    ASSERT_EQ(host.describe(kDefocusId), kOfxStatOK);
    EXPECT_EQ(host.plugin(kDefocusId)->descriptor->props.strings(kOfxImageEffectPropSupportedContexts), first);
}

TEST(ofx_describe, UnknownContextIsRefused) {
    Host host;
    std::string err;
    ASSERT_TRUE(host.load(bundle_binary(), &err)) << err;
    ASSERT_EQ(host.describe(kDefocusId), kOfxStatOK);
    EXPECT_EQ(host.describe_in_context(kDefocusId, kOfxImageEffectContextTransition), kOfxStatErrMissingHostFeature);
}
