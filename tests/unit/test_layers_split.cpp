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
    for (const char* bad : {"0", "-2", "abc", "", "5x", "1.5", "id:", "auto:0", "auto:x", "100000"}) {
        auto r = parse_layer_split(bad);
        ASSERT_FALSE(r) << "'" << bad << "' was accepted";
        EXPECT_NE(r.message().find(std::string("'") + bad + "'"), std::string::npos) << r.message();
    }
}
