// Shadow catchers (integrators/path/shadow_catcher.h, film/shadow_catcher_passes.h): a ball
// over a floor that is a shadow catcher, under an area lamp or a sun.
//
// The path tracer's catcher pass is the floor's light with the ball over its light without
// it, and its copy of a path draws the main path's random numbers, so with one seed:
// - the Shadow Catcher pass equals, pixel by pixel, the ratio of a render of the scene with
//   the floor an ordinary object to a render without the ball (the same paths: 1e-4
//   relative, floating-point order only), wherever the camera sees the floor;
// - under a sun (a delta light) and a black world it is exactly 1 where the floor is lit
//   and exactly 0 in the umbra; the matte there is transparent black, and Combined holds
//   the shadow as alpha (film transparent) or over the world (film opaque);
// - a scene whose catcher is off renders bit-identically with catcher support, and BDPT
//   renders a catcher as an ordinary object (bit-identical to the flag off) and says so.
// All checks are deterministic (fixed seeds, same paths): no false alarms.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kSize = 40;
// Hidden from every kind of ray: as if absent, with the same bounds and light choices.
const json kHidden = {{"camera", false},       {"diffuse", false}, {"glossy", false},
                      {"transmission", false}, {"shadow", false},  {"volume_scatter", false}};

// The ball over the floor; floor_catcher: the floor is a shadow catcher; ball: seen (else
// hidden from every ray: the scene without it, with the same bounds, so the same light
// choices and ray offsets).
json catcher_scene(bool floor_catcher, bool ball, const json &lamp, const json &world = {{"color", {0.1, 0.12, 0.15}}},
                   const json &settings = json::object(), const json &ball_color = {0.8, 0.3, 0.2}) {
  json floor = {{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"floor"}}};
  if (floor_catcher) floor["shadow_catcher"] = true;
  json sphere = {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.5}, {"segments", 24}}},
                 {"materials", {"ball"}}, {"transform", {{"translate", {-0.3, 0.2, 0.8}}}}};
  if (!ball) sphere["visibility"] = kHidden;
  json meshes = {floor, sphere};
  json s = {{"width", kSize}, {"height", kSize}, {"samples", 16}, {"max_bounces", 4}, {"seed", 3}};
  s.update(settings);
  return {{"settings", s},
          {"camera", {{"focal_length", 30}, {"transform", {{"look_at", {{"from", {0, -4.0, 3.2}}, {"to", {0, 0, 0.3}}}}}}}},
          {"world", world},
          {"materials",
           {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.65, 0.6}}},
            {{"name", "ball"}, {"type", "diffuse"}, {"color", ball_color}}}},
          {"meshes", meshes},
          {"lights", {lamp}}};
}

// Lamps of the footage (Object > Visibility > Shadow Catcher on the light, the default):
// they light the catcher pass too.
const json kAreaLamp = {{"type", "area"},       {"size", 0.8},       {"power", 200},
                        {"position", {0.9, -0.4, 2.6}}, {"direction", {-0.3, 0.1, -1}}, {"shadow_catcher", true}};
const json kSun = {{"type", "sun"}, {"strength", 3}, {"angle", 0}, {"direction", {0.7, -0.5, -1}}, {"shadow_catcher", true}};

const float *px(const std::vector<float> &v, int channels, int x, int y) {
  return &v[(size_t(y) * kSize + x) * size_t(channels)];
}

}  // namespace

// The Shadow Catcher pass of the scene with `lamp` against the ratio of renders with the
// floor an ordinary object and without the ball (and without the lamp: `lamp_in_pass` false).
void expect_lit_ratio(const json &lamp, bool lamp_in_pass) {
  Image caught = render_json(catcher_scene(true, true, lamp).dump(), R"({"shadow_catcher_pass": true})");
  Image with_ball = render_json(catcher_scene(false, true, lamp).dump());
  json hidden_lamp = lamp;
  if (!lamp_in_pass) hidden_lamp["visibility"] = kHidden;  // the same light choices, no light
  Image without_ball = render_json(catcher_scene(false, false, hidden_lamp).dump());
  ASSERT_TRUE(caught.all_finite());
  int floor_pixels = 0, shadowed = 0;
  double worst = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float *matte = px(caught.shadow_catcher_matte, 4, x, y);
      const float *f = px(caught.shadow_catcher, 3, x, y);
      if (matte[3] != 0.0f) {  // the camera sees some of the ball here: no pure floor
        for (int c = 0; c < 3; ++c) EXPECT_GT(matte[c], 0.0f) << x << "," << y;
        continue;
      }
      ++floor_pixels;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(matte[c], 0.0f) << "the matte of the bare floor, " << x << "," << y;
      // The matte is Combined with the Shadow Catcher pass on.
      EXPECT_EQ(caught.rgba[(size_t(y) * kSize + x) * 4 + 3], 0.0f);
      bool in_shadow = false;
      for (int c = 0; c < 3; ++c) {
        const double lit = with_ball.rgba[(size_t(y) * kSize + x) * 4 + c];
        const double bare = without_ball.rgba[(size_t(y) * kSize + x) * 4 + c];
        ASSERT_GT(bare, 0.0);
        const double ratio = lit / bare;
        worst = std::max(worst, std::fabs(f[c] - ratio) / std::max(ratio, 1e-3));
        EXPECT_NEAR(f[c], ratio, 1e-4 * std::max(ratio, 1.0)) << "pixel " << x << "," << y << " channel " << c;
        in_shadow = in_shadow || ratio < 0.8;
      }
      shadowed += in_shadow;
    }
  std::printf("lamp in the pass %d: floor pixels %d (ratio below 0.8: %d), worst relative difference %.2g\n",
              int(lamp_in_pass), floor_pixels, shadowed, worst);
  EXPECT_GT(floor_pixels, kSize * kSize / 2);
  if (lamp_in_pass) EXPECT_GT(shadowed, 10) << "the scene must show the ball's shadow on the floor";
}

TEST(ShadowCatcher, PassIsTheLitRatioOfRendersWithAndWithoutTheBall) { expect_lit_ratio(kAreaLamp, true); }

// A lamp that is not a shadow catcher (its object's Shadow Catcher turned off) is the
// synthetic objects' light: it lights the image but not the catcher pass, which then
// exceeds 1 where it lights the floor.
TEST(ShadowCatcher, LampsThatAreNotCatchersLightOnlyTheImage) {
  json lamp = kAreaLamp;
  lamp["shadow_catcher"] = false;
  expect_lit_ratio(lamp, false);
}

TEST(ShadowCatcher, SunLitFloorIsOneAndUmbraZero) {
  // A black ball and world: the floor has the sun's light only, or none.
  const json black = {{"color", {0, 0, 0}}};
  for (bool transparent : {true, false}) {
    Image img = render_json(
        catcher_scene(true, true, kSun, black, {{"film_transparent", transparent}, {"samples", 8}}, {0, 0, 0}).dump());
    ASSERT_TRUE(img.all_finite());
    int lit = 0, umbra = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        if (px(img.shadow_catcher_matte, 4, x, y)[3] != 0.0f) continue;  // the ball is seen here
        const float *f = px(img.shadow_catcher, 3, x, y);
        const float *combined = px(img.rgba, 4, x, y);
        if (f[0] == 1.0f && f[1] == 1.0f && f[2] == 1.0f) {
          ++lit;
          // Approximate shadow catcher: no shadow, so a transparent (or the world's black) pixel.
          for (int c = 0; c < 3; ++c) EXPECT_EQ(combined[c], 0.0f);
          EXPECT_EQ(combined[3], transparent ? 0.0f : 1.0f);
        } else if (f[0] == 0.0f && f[1] == 0.0f && f[2] == 0.0f) {
          ++umbra;
          for (int c = 0; c < 3; ++c) EXPECT_EQ(combined[c], 0.0f);
          EXPECT_EQ(combined[3], 1.0f) << "the umbra as black, opaque";
        } else {
          // The umbra's edge: pixels whose samples see both.
          EXPECT_GT(f[0], 0.0f);
          EXPECT_LT(f[0], 1.0f);
          if (transparent) {
            EXPECT_NEAR(combined[3], 1.0f - (f[0] + f[1] + f[2]) / 3.0f, 1e-6f);
          }
        }
      }
    std::printf("film transparent %d: lit floor pixels %d, umbra %d\n", int(transparent), lit, umbra);
    EXPECT_GT(lit, 100) << "transparent " << transparent;
    EXPECT_GT(umbra, 10) << "transparent " << transparent;
  }
}

TEST(ShadowCatcher, OpaqueFilmShowsTheWorldBehindTheCatcherDarkenedByTheShadow) {
  // A floor the camera sees against a bright world: approximate Combined = the world's
  // colour behind the floor times the shadow factor's average, alpha 1.
  const json sky = {{"color", {0.2, 0.3, 0.5}}};
  Image img = render_json(catcher_scene(true, true, kSun, sky, {{"samples", 8}}).dump());
  int checked = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      if (px(img.shadow_catcher_matte, 4, x, y)[3] != 0.0f) continue;
      const float *f = px(img.shadow_catcher, 3, x, y);
      const float shade = std::clamp((f[0] + f[1] + f[2]) / 3.0f, 0.0f, 1.0f);
      const float *combined = px(img.rgba, 4, x, y);
      const float world[3] = {0.2f, 0.3f, 0.5f};
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(combined[c], world[c] * shade, 1e-5f) << x << "," << y;
      EXPECT_EQ(combined[3], 1.0f);
      ++checked;
    }
  EXPECT_GT(checked, kSize * kSize / 2);
}

TEST(ShadowCatcher, OtherIntegratorsRenderItAsAnOrdinaryObjectAndSaySo) {
  for (const char *integrator : {"bdpt", "pssmlt"}) {
    const json settings = {{"integrator", integrator}, {"samples", 4}, {"mlt_chains", 64}, {"mlt_bootstrap", 4}};
    Image caught = render_json(catcher_scene(true, true, kAreaLamp).dump(), settings.dump());
    Image plain = render_json(catcher_scene(false, true, kAreaLamp).dump(), settings.dump());
    EXPECT_NE(caught.warnings.find("object 'floor' (instance 1) is a shadow catcher"), std::string::npos)
        << integrator << ": " << caught.warnings;
    EXPECT_EQ(caught.rgba, plain.rgba) << integrator;
    for (float f : caught.shadow_catcher) ASSERT_EQ(f, 1.0f);
  }
}

// Integrator auto renders a scene with a shadow catcher with the path tracer when path is
// among its candidates (the others would render the catcher as an ordinary object), and
// says so; the pass shows the ball's shadow (below 1 under it).
TEST(ShadowCatcher, AutoPicksThePathTracer) {
  const json settings = {{"integrator", "auto"}, {"time_limit", 1.0}, {"samples", 8}, {"shadow_catcher_pass", true}};
  Image img = render_json(catcher_scene(true, true, kAreaLamp).dump(), settings.dump());
  EXPECT_NE(img.warnings.find("integrator auto renders with path"), std::string::npos) << img.warnings;
  EXPECT_EQ(json::parse(img.stats)["auto"]["integrator"], "path") << img.stats;
  float darkest = 1;
  for (float f : img.shadow_catcher) darkest = std::min(darkest, f);
  EXPECT_LT(darkest, 0.5f) << "no shadow in the Shadow Catcher pass";
}

TEST(ShadowCatcher, SceneSettingIsCheckedAndResetable) {
  SceneHandle s;
  uint32_t material = 0, mesh = 0, inst = 0;
  ASSERT_EQ(rdv_scene_add_material(s.s, "m", R"({"type":"diffuse"})", &material), RDV_OK);
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  ASSERT_EQ(rdv_scene_add_mesh(s.s, "tri", positions, 3, nullptr, nullptr, indices, 1, nullptr, material, &mesh), RDV_OK);
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(rdv_scene_add_instance(s.s, mesh, identity, &inst), RDV_OK);
  EXPECT_NE(rdv_scene_set_instance_params(s.s, inst, R"({"shadow_catcher": "yes"})"), RDV_OK);
  EXPECT_EQ(rdv_scene_set_instance_params(s.s, inst, R"({"shadow_catcher": true})"), RDV_OK);
  EXPECT_EQ(rdv_scene_set_instance_params(s.s, inst, R"({})"), RDV_OK);  // back to an ordinary object
}
