// Dense grids passed as binary buffers (rdv_scene_add_grid, {"buffer": name}) render
// exactly like the same grids given as JSON "values"; re-adding a name replaces its
// voxels; an unknown name warns naming the medium and renders without that grid.
// Deterministic comparisons (same seed, one thread): no false alarms.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "media_grids.h"
#include "render_helpers.h"

namespace test_grid_buffers {

using namespace rdv::test;
using nlohmann::json;

namespace {

const json kBounds = {{-1, -1, -1}, {1, 1, 1}};

// A smoke cloud with blackbody fire: `grid` is the density, emission and temperature grid.
json fire_scene(const json &grid) {
  return {{"settings", {{"width", 12}, {"height", 12}, {"samples", 8}, {"threads", 1}, {"seed", 7}}},
          {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
          {"world", {{"color", {0.3, 0.4, 0.5}}}},
          {"materials", {{{"name", "fire"}, {"type", "volume"},
                          {"volume", {{"density", 6.0}, {"color", {0.6, 0.5, 0.4}}, {"emission_strength", 2.0},
                                      {"blackbody_intensity", 1.0}, {"temperature", 1500.0}, {"grid", grid},
                                      {"emission_grid", grid}, {"temperature_grid", grid}}}}}},
          {"meshes", {{{"name", "domain"}, {"shape", {{"type", "box"}, {"size", {2, 2, 2}}}}, {"materials", {"fire"}}}}}};
}

void add_grid(rdv_scene *scene, const char *name, const std::vector<float> &values, uint32_t n) {
  uint32_t id = 99;
  ASSERT_EQ(RDV_OK, rdv_scene_add_grid(scene, name, values.data(), n, n, n, &id)) << rdv_last_error();
  EXPECT_EQ(id, 0u);  // the first name; re-adding it keeps its id
}

}  // namespace

TEST(GridBuffers, BufferRendersLikeJsonValues) {
  const int n = 20;
  json dense = puff_grid(n, kBounds);
  std::vector<float> values = dense["values"].get<std::vector<float>>();
  Image from_json = render_json(fire_scene(dense).dump());
  json ref = {{"buffer", "smoke"}, {"bounds", kBounds}};
  // Added once, and added first as an empty grid then replaced (a simulation step).
  for (bool replaced : {false, true}) {
    Image from_buffer = render_json_prepared(
        [&](rdv_scene *s) {
          if (replaced) add_grid(s, "smoke", std::vector<float>(values.size(), 0.0f), n);
          add_grid(s, "smoke", values, n);
        },
        fire_scene(ref).dump());
    EXPECT_EQ(from_buffer.warnings, from_json.warnings);
    ASSERT_EQ(from_buffer.rgba.size(), from_json.rgba.size());
    ASSERT_TRUE(from_buffer.all_finite());
    EXPECT_GT(from_json.channel_mean(0), 0.05f);
    size_t differing = 0;
    for (size_t i = 0; i < from_json.rgba.size(); ++i) differing += from_buffer.rgba[i] != from_json.rgba[i];
    EXPECT_EQ(differing, 0u) << (replaced ? "replaced buffer" : "buffer");
  }
}

TEST(GridBuffers, MissingBufferWarnsAndRendersWithoutIt) {
  json scene = fire_scene({{"buffer", "no_such_grid"}, {"bounds", kBounds}});
  Image img = render_json(scene.dump());
  EXPECT_NE(img.warnings.find("medium 'fire'"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("no grid buffer 'no_such_grid'"), std::string::npos) << img.warnings;
  ASSERT_TRUE(img.all_finite());
  // Without its density grid the medium is vacuum: the world shows through.
  const float world[3] = {0.3f, 0.4f, 0.5f};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.channel_mean(c), world[c], 1e-4);
}

TEST(GridBuffers, BadBuffersAreRejected) {
  rdv_scene *s = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_create(&s));
  std::vector<float> v = {0.5f, -1.0f};
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_grid(s, "g", v.data(), 2, 1, 1, nullptr));
  EXPECT_NE(std::string(rdv_last_error()).find("grid 'g'"), std::string::npos) << rdv_last_error();
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_grid(s, "g", v.data(), 0, 1, 1, nullptr));
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_grid(s, "g", nullptr, 1, 1, 1, nullptr));
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_grid(s, nullptr, v.data(), 1, 1, 1, nullptr));
  rdv_scene_destroy(s);
}

}  // namespace test_grid_buffers
