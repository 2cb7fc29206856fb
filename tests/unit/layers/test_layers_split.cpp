// parse_layer_split: the accepted forms and errors that name the value.
#include <gtest/gtest.h>

#include "gdof/layers.h"

using namespace gdof;

TEST(layers_split, AcceptedForms) {
    auto a = parse_layer_split("auto");
    ASSERT_TRUE(a) << a.message();
    EXPECT_EQ(a->mode, LayerSplit::Mode::Auto);

    auto am = parse_layer_split("auto:6");
    ASSERT_TRUE(am) << am.message();
    EXPECT_EQ(am->mode, LayerSplit::Mode::Auto);
    EXPECT_EQ(am->max_layers, 6);

    EXPECT_EQ(am->blur_cuts, LayerSplit::BlurCuts::Default);

    auto ab = parse_layer_split("auto:8:blur=2.5");
    ASSERT_TRUE(ab) << ab.message();
    EXPECT_EQ(ab->max_layers, 8);
    EXPECT_EQ(ab->blur_cuts, LayerSplit::BlurCuts::On);
    EXPECT_DOUBLE_EQ(ab->blur_step, 2.5);
    EXPECT_EQ(parse_layer_split("auto:blur")->blur_cuts, LayerSplit::BlurCuts::On);
    EXPECT_DOUBLE_EQ(parse_layer_split("auto:blur")->blur_step, 0.0);
    EXPECT_EQ(parse_layer_split("auto:gaps")->blur_cuts, LayerSplit::BlurCuts::Off);

    auto n = parse_layer_split("5");
    ASSERT_TRUE(n) << n.message();
    EXPECT_EQ(n->mode, LayerSplit::Mode::Count);
    EXPECT_EQ(n->count, 5);

    auto id = parse_layer_split("id");
    ASSERT_TRUE(id) << id.message();
    EXPECT_EQ(id->mode, LayerSplit::Mode::ById);
    EXPECT_EQ(id->id_channel, "id");

    auto idc = parse_layer_split("id:objid");
    ASSERT_TRUE(idc) << idc.message();
    EXPECT_EQ(idc->mode, LayerSplit::Mode::ById);
    EXPECT_EQ(idc->id_channel, "objid");
}

TEST(layers_split, ErrorsNameTheValue) {
    for (const char* bad : {"0", "-2", "abc", "", "5x", "1.5", "id:", "auto:0", "auto:x", "100000", "auto:", "auto::4",
                            "auto:blur=0", "auto:blur=x", "auto:blur=", "auto:blur=nan", "auto:gap"}) {
        auto r = parse_layer_split(bad);
        ASSERT_FALSE(r) << "'" << bad << "' was accepted";
        EXPECT_NE(r.message().find(std::string("'") + bad + "'"), std::string::npos) << r.message();
    }
}
