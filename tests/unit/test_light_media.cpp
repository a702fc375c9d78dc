// Scene::light_media: the media each light sits in, found once per commit, are the
// media the per-sample walk (Scene::media_along from each emitted ray) finds for every
// point the light emits from; a light a medium boundary passes through is left to the
// walk.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "committed_scene.h"
#include "core/hash.h"
#include "core/ray_offset.h"
#include "render_helpers.h"

namespace test_light_media {

using namespace rdv;
using nlohmann::json;

namespace {

// For every light with media found at commit: 4096 emitted rays (as BDPT's light
// subpaths leave the light) whose walk must find the same media. Returns how many
// lights had fixed media.
int check_fixed_media(const Scene &scene) {
  int fixed = 0;
  for (uint32_t i = 0; i < scene.lights().size(); ++i) {
    const std::vector<int> *media = scene.light_media(i);
    if (!media) continue;
    ++fixed;
    const Light &light = scene.lights()[i];
    Pcg32 rng(7, i);
    for (int k = 0; k < 4096; ++k) {
      EmissionSample es;
      Vec2 u_pos{rng.next_float(), rng.next_float()}, u_dir{rng.next_float(), rng.next_float()};
      if (!scene.sample_emission(i, u_pos, u_dir, Vec3(0.5f), es)) continue;
      Ray ray = es.ray;
      if (light.type == LightType::Triangle) ray.o = spawn_origin(ray.o, light.axis, light.error, ray.d);
      if (scene.media_along(ray.o, ray.d) != *media) {
        ADD_FAILURE() << "light " << i << ", ray " << k << ": the walk finds other media";
        return -1;
      }
    }
  }
  return fixed;
}

json box_mesh(const std::string &name, Vec3 size, Vec3 at, const std::string &material) {
  return {{"name", name}, {"shape", {{"type", "box"}, {"size", {size.x, size.y, size.z}}}},
          {"materials", {material}}, {"transform", {{"translate", {at.x, at.y, at.z}}}}};
}

// A 4 m box of fog standing on a floor; inside it a spot with a radius, an emissive
// cube and a smaller emissive box of glowing smoke (its triangles are a boundary);
// an area lamp straddling the fog's wall; a point lamp outside.
json lamps_and_fog() {
  json fog = {{"name", "fog"}, {"type", "volume"}, {"volume", {{"density", 0.2}}}};
  json glow = {{"name", "glow"}, {"type", "emission"}, {"strength", 3.0}};
  json glowing_smoke = {{"name", "glowing smoke"}, {"type", "emission"}, {"strength", 2.0},
                        {"volume", {{"density", 1.0}}}};
  return {{"camera", {{"transform", {{"look_at", {{"from", {0, -8, 2}}, {"to", {0, 0, 1}}}}}}}},
          {"materials", {{{"name", "floor"}, {"type", "diffuse"}}, fog, glow, glowing_smoke}},
          {"meshes",
           {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 20}}}, {"materials", {"floor"}}},
            box_mesh("fog box", Vec3(4, 4, 4), Vec3(0, 0, 2.001f), "fog"),
            box_mesh("glowing cube", Vec3(0.3f, 0.3f, 0.3f), Vec3(-1, 1, 1), "glow"),
            box_mesh("smoke", Vec3(0.5f, 0.5f, 0.5f), Vec3(1, 1, 1), "glowing smoke")}},
          {"lights",
           {{{"name", "spot"}, {"type", "spot"}, {"position", {0.5, -0.5, 3}}, {"direction", {0, 0, -1}},
             {"power", 100}, {"radius", 0.1}, {"spot_size", 1.0}},
            {{"name", "straddling"}, {"type", "area"}, {"size", 1.0}, {"position", {2, 0, 3.5}},
             {"direction", {0, 0, -1}}, {"power", 100}},
            {{"name", "outside"}, {"type", "point"}, {"position", {0, -6, 3}}, {"power", 100}}}}};
}

}  // namespace

TEST(LightMedia, FixedMediaMatchTheWalkFromEveryPoint) {
  for (const char *name : {"fog_door.json", "fog_spot.json", "volume_caustic.json"}) {
    SCOPED_TRACE(name);
    test::CommittedScene l(test::load_scene(name));
    EXPECT_EQ(check_fixed_media(l.scene()), 1);  // each has one lamp, away from boundaries
  }
}

TEST(LightMedia, LampsInAndAcrossAFogBox) {
  test::CommittedScene l(lamps_and_fog());
  const Scene &scene = l.scene();
  int spot = -1, straddling = -1, outside = -1, cube = -1, smoke = -1;
  for (uint32_t i = 0; i < scene.lights().size(); ++i) {
    const Light &light = scene.lights()[i];
    if (light.type == LightType::Spot) spot = int(i);
    if (light.type == LightType::Area) straddling = int(i);
    if (light.type == LightType::Point) outside = int(i);
    if (light.type == LightType::Triangle) {
      Vec3 c = light.p0 + (light.edge_u + light.edge_v) * (1.0f / 3.0f);
      (c.x < 0 ? cube : smoke) = int(i);
    }
  }
  ASSERT_TRUE(spot >= 0 && straddling >= 0 && outside >= 0 && cube >= 0 && smoke >= 0);
  // The spot and the glowing cube are in the fog, the fog box's medium alone.
  ASSERT_NE(scene.light_media(uint32_t(spot)), nullptr);
  ASSERT_EQ(scene.light_media(uint32_t(spot))->size(), 1u);
  EXPECT_NE(scene.light_media(uint32_t(spot))->front(), scene.world_medium());
  ASSERT_NE(scene.light_media(uint32_t(cube)), nullptr);
  EXPECT_EQ(*scene.light_media(uint32_t(cube)), *scene.light_media(uint32_t(spot)));
  ASSERT_NE(scene.light_media(uint32_t(outside)), nullptr);
  EXPECT_TRUE(scene.light_media(uint32_t(outside))->empty());
  // A boundary passes through these: the media depend on the point (and the side).
  EXPECT_EQ(scene.light_media(uint32_t(straddling)), nullptr);
  EXPECT_EQ(scene.light_media(uint32_t(smoke)), nullptr);
  EXPECT_EQ(check_fixed_media(scene), 2 + 12);  // spot, outside and the cube's 12 triangles
}

}  // namespace test_light_media
