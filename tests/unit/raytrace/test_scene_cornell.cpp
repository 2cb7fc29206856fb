// The real Cornell box OBJ (shared data; skipped when absent).
#include "gdof/scene.h"
#include "test_support.h"

using namespace gdof;

TEST(scene_cornell, obj_counts_and_light) {
    GDOF_REQUIRE_SHARED(path, "meshes/CornellBox-Original.obj");
    auto r = load_obj(path);
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r->positions.size() / 3, 72u);  // 72 "v" lines (CR line ends, tabs)
    EXPECT_EQ(r->shapes.size(), 8u);          // 8 groups
    EXPECT_EQ(r->triangle_count(), 36u);      // 18 quads
    bool light = false;
    for (const Material& m : r->materials)
        if (m.name == "light") {
            light = true;
            EXPECT_TRUE(m.emissive());
        }
    EXPECT_TRUE(light);
}

TEST(scene_cornell, example_scene_loads) {
    GDOF_REQUIRE_SHARED(cornell, "meshes/CornellBox-Original.obj");
    GDOF_REQUIRE_SHARED(bunny, "meshes/bunny_small.obj");
    auto r = load_scene(std::string(GDOF_SOURCE_DIR) + "/examples/render/cornell.json");
    if (!r && r.message().find("not found") != std::string::npos)
        GDOF_SKIP_OR_FAIL("examples/render/cornell.json does not reach the shared data: " << r.message());
    ASSERT_TRUE(r) << r.message();
    EXPECT_GT(r->emissive_triangle_count(), 0u);
    EXPECT_EQ(r->meshes.size(), 2u);
    EXPECT_EQ(r->meshes[1].triangle_count(), 4968u);  // bunny_small: 4968 triangles
}
