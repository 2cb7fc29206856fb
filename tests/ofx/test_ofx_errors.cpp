// Bad input through the test host never crashes the host: missing clips,
// wrong components, integer bit depths, bad parameters and a host without the
// suites the plugin needs give a failed status and (for instances) a
// persistent error message naming the clip, parameter or key.
#include "ofx/ofx_test_support.h"

using namespace gdof::test;

namespace {

constexpr int W = 48, H = 32;

struct Fixture {
    Plate plate = make_plate(W, H);
    Session s{kDefocusId, W, H};
    Fixture() {
        if (!s.ok()) return;
        s.fx->connect("Source", plate_clip(plate, "rgba"));
        s.fx->connect("Depth", plate_clip(plate, "depth"));
        s.fx->set_choice("depth_channel", "A");
        s.fx->set_choice("kind", "focal_planes");
        s.fx->set("max_radius", 6);
    }
    // Renders; expects failure with an error message containing every `needle`.
    void expect_error(const std::vector<std::string>& needles) {
        const Rendered r = s.fx->render(0, {1, 1});
        EXPECT_EQ(r.status, kOfxStatFailed);
        const std::string m = s.fx->persistent_message();
        EXPECT_EQ(s.fx->persistent_type(), kOfxMessageError) << m;
        EXPECT_TRUE(contains(m, "gdof Defocus: ")) << m;
        if (std::getenv("GDOF_SHOW_MESSAGES")) std::printf("  message: %s\n", m.c_str());
        for (const std::string& n : needles) EXPECT_TRUE(contains(m, n)) << "'" << m << "' does not mention '" << n << "'";
        EXPECT_EQ(s.host.live_images(), 0) << "images are released on errors too";
    }
};

}  // namespace

TEST(ofx_errors, MissingDepthClipIsAPersistentErrorNotACrash) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->disconnect("Depth");
    f.expect_error({"Depth clip is not connected"});
    // Connecting it fixes the render and clears the message.
    f.s.fx->connect("Depth", plate_clip(f.plate, "depth"));
    const Rendered r = f.s.fx->render(0, {1, 1});
    EXPECT_EQ(r.status, kOfxStatOK) << f.s.fx->persistent_message();
    EXPECT_TRUE(f.s.fx->persistent_message().empty());
}

TEST(ofx_errors, AlphaOnlySourceIsRejectedNamingTheComponents) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->connect("Source", plate_clip(f.plate, "depth"));  // Alpha
    f.expect_error({"clip 'Source'", "Alpha", "RGBA or RGB"});
}

TEST(ofx_errors, ByteAndShortImagesAreRejectedNamingTheDepth) {
    for (const char* depth : {kOfxBitDepthByte, kOfxBitDepthShort}) {
        Fixture f;
        ASSERT_TRUE(f.s.ok());
        f.s.fx->effect().honour_clip_preferences = false;  // a host that sends integer images anyway
        ClipFrame src = plate_clip(f.plate, "rgba");
        src.depth = depth;
        f.s.fx->connect("Source", src);
        f.expect_error({"clip 'Source'", std::string(depth).substr(11), "32-bit float"});
    }
}

TEST(ofx_errors, ByteDepthPassIsRejectedToo) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->effect().honour_clip_preferences = false;
    ClipFrame d = plate_clip(f.plate, "depth");
    d.depth = kOfxBitDepthByte;
    f.s.fx->connect("Depth", d);
    f.expect_error({"clip 'Depth'", "Byte"});
}

TEST(ofx_errors, DepthChannelTheClipDoesNotHaveIsNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("depth_channel", "G");  // the Depth clip is Alpha
    f.expect_error({"clip 'Depth'", "depth_channel", "G"});
}

TEST(ofx_errors, PositionPassNeedsThreeChannels) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("depth_pass", "position");
    f.expect_error({"clip 'Depth'", "position pass"});
}

TEST(ofx_errors, BadBlurFieldValuesNameTheJsonKey) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_int("depths_count", 1);  // a single plane needs a slope
    f.s.fx->set("slope", 0);
    f.expect_error({"blur field", "slope"});
}

TEST(ofx_errors, BadLensNamesTheParameter) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set("focal_length_mm", -5);  // out of the declared range, a host may still send it
    f.expect_error({"focal_length_mm"});
}

TEST(ofx_errors, BadDepthEncodingValuesAreNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("depth_encoding", "near_far_linear");
    f.s.fx->set("depth_near", 10);
    f.s.fx->set("depth_far", 1);
    f.expect_error({"depth far"});
}

TEST(ofx_errors, BlurMapModeWithoutTheClipIsNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("kind", "image_map");
    f.expect_error({"Blur Map clip is not connected"});
}

TEST(ofx_errors, BlurMapChannelMissingIsNamed) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set_choice("kind", "image_map");
    f.s.fx->connect("BlurMap", plate_clip(f.plate, "depth"));  // Alpha
    f.s.fx->set_choice("map_channel", "R");
    f.expect_error({"blur field", "R"});
}

TEST(ofx_errors, HugeBlurIsAnErrorNamingTheRadius) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    f.s.fx->set("max_radius", 1e7);  // beyond the declared maximum
    f.s.fx->set("max_blur", 1e7);
    f.expect_error({"radius"});
}

TEST(ofx_errors, HostWithoutTheParameterSuiteIsRefusedAtLoad) {
    Host host;
    host.withheld_suites = {kOfxParameterSuite};
    std::string err;
    EXPECT_FALSE(host.load(bundle_binary(), &err));
    EXPECT_TRUE(contains(err, std::to_string(kOfxStatErrMissingHostFeature))) << err;
}

TEST(ofx_errors, HostWithoutMessagesOrThreadsStillRenders) {
    Host host;
    host.withheld_suites = {kOfxMessageSuite, kOfxMultiThreadSuite};
    std::string err;
    ASSERT_TRUE(host.load(bundle_binary(), &err)) << err;
    ASSERT_EQ(host.describe(kDefocusId), kOfxStatOK);
    ASSERT_EQ(host.describe_in_context(kDefocusId, kOfxImageEffectContextGeneral), kOfxStatOK);
    auto fx = host.create_instance(kDefocusId, kOfxImageEffectContextGeneral, W, H);
    ASSERT_TRUE(fx);
    const Plate plate = make_plate(W, H);
    fx->connect("Source", plate_clip(plate, "rgba"));
    fx->set_choice("kind", "focal_planes");
    EXPECT_EQ(fx->render(0, {1, 1}).status, kOfxStatFailed) << "no Depth: fails, with nowhere to say why";
    fx->connect("Depth", plate_clip(plate, "depth"));
    fx->set_choice("depth_channel", "A");
    EXPECT_EQ(fx->render(0, {1, 1}).status, kOfxStatOK);
}

TEST(ofx_errors, ActionsWithBadArgumentsFailCleanly) {
    Fixture f;
    ASSERT_TRUE(f.s.ok());
    gdof::ofxtest::Plugin& p = *f.s.host.plugin(kDefocusId);
    // A render without its arguments: the plugin reports, the host survives.
    gdof::ofxtest::PropertySet empty;
    EXPECT_EQ(f.s.host.call(p, kOfxImageEffectActionRender, &f.s.fx->effect(), &empty, nullptr), kOfxStatFailed);
    EXPECT_TRUE(contains(f.s.fx->persistent_message(), "kOfxImageEffectPropRenderWindow") ||
                contains(f.s.fx->persistent_message(), "OfxPropTime"))
        << f.s.fx->persistent_message();
    EXPECT_EQ(f.s.host.call(p, nullptr, &f.s.fx->effect(), nullptr, nullptr), kOfxStatErrBadHandle);
    EXPECT_EQ(f.s.host.call(p, "NoSuchAction", &f.s.fx->effect(), nullptr, nullptr), kOfxStatReplyDefault);
}
