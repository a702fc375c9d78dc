// Ray visibility (scene/ray_visibility.h): a ball over a floor under an area lamp, with one
// kind of ray hidden at a time. Checked against closed relations in the path tracer (an
// instance hidden from every ray renders as if absent; hiding an object from the camera
// changes no pixel whose camera rays never meet it, bit for bit; a ball hidden from
// diffuse rays still shadows the floor in direct light; a lamp hidden from diffuse rays
// lights a diffuse floor not at all), and BDPT against the path tracer on every case:
// K runs each, Welch's t-test on every 8x8 block (1% false alarms over the file,
// Sidak-corrected per block; fixed seeds, so each verdict is reproducible).
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_ray_visibility {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kRuns = 6;
constexpr int kSize = 32;
// Thirteen BDPT-vs-path and nine mlt-vs-path comparisons of 4x4 blocks.
constexpr int kBlockTestsInFile = 22 * 16;
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / kBlockTestsInFile);

// The ball's material and visibility, the lamp's extra parameters, the world's.
json ball_scene(const json &ball_visibility, const json &ball_material = {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}},
                const json &lamp_extra = json::object(), const json &world_extra = json::object(),
                const json &floor_material = {{"type", "diffuse"}, {"color", {0.7, 0.7, 0.7}}}) {
  json ball = {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.6}, {"segments", 24}}},
               {"materials", {"ball"}}, {"transform", {{"translate", {0, 0, 0.7}}}}};
  if (!ball_visibility.is_null()) ball["visibility"] = ball_visibility;
  json bm = ball_material, fm = floor_material;
  bm["name"] = "ball";
  fm["name"] = "floor";
  json lamp = {{"type", "area"}, {"size", 0.6}, {"power", 150}, {"position", {0.8, -0.3, 2.6}}, {"direction", {0, 0, -1}}};
  lamp.update(lamp_extra);
  json world = {{"color", {0.08, 0.09, 0.1}}};
  world.update(world_extra);
  return {{"settings", {{"width", kSize}, {"height", kSize}, {"samples", 32}, {"max_bounces", 4}, {"seed", 1}}},
          {"camera", {{"focal_length", 35}, {"transform", {{"look_at", {{"from", {0, -4.2, 2.8}}, {"to", {0, 0, 0.5}}}}}}}},
          {"world", world},
          {"materials", {bm, fm}},
          {"meshes", {ball, {{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 5}}}, {"materials", {"floor"}}}}},
          {"lights", {lamp}}};
}

json with(json scene, const json &settings) {
  scene["settings"].update(settings);
  return scene;
}

// `integrator` against the path tracer (Metropolis: 64 chains, a small bootstrap).
void expect_matches_path(const json &scene, const std::string &what, const char *integrator, int samples_pt,
                         int samples, bool brightness = false) {
  json s = {{"integrator", "path"}, {"samples", samples_pt}};
  auto pt = seeded_renders(scene.dump(), s.dump(), kRuns, 1);
  s = {{"integrator", integrator}, {"samples", samples}, {"mlt_chains", 64}, {"mlt_bootstrap", 4}};
  auto other = seeded_renders(scene.dump(), s.dump(), kRuns, 1001);
  BlockComparison c = compare_blocks(other, pt, kSize, kSize, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << what << " " << integrator << ": " << c.detail;
  // Brightness (Metropolis: the image's sum is b, the chains' own estimate): the runs'
  // mean within 3.3 standard errors of the path tracer's (1e-3).
  const BrightnessComparison b = compare_brightness(other, pt);
  if (brightness)
    EXPECT_LT(std::fabs(b.z), 3.3) << what << " " << integrator << ": mean " << b.mean_a << " vs path " << b.mean_b;
  std::printf("[ ray visibility ] %-4s %-34s mean ratio %.4f +- %.4f (z %.2f); %s\n", integrator, what.c_str(),
              b.mean_a / b.mean_b, b.error / b.mean_b, b.z, c.detail.substr(0, 60).c_str());
}

void expect_bdpt_matches_path(const json &scene, const std::string &what, int samples_pt = 48, int samples_bdpt = 32,
                              bool brightness = false) {
  expect_matches_path(scene, what, "bdpt", samples_pt, samples_bdpt, brightness);
}

double sum_of(const Image &img, int x0, int y0, int x1, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) s += img.rgba[(size_t(y) * img.width + x) * 4 + c];
  return s;
}

const json kHidden = {{"camera", false}, {"diffuse", false},      {"glossy", false},
                      {"transmission", false}, {"shadow", false}, {"volume_scatter", false}};

}  // namespace

// An instance no ray sees renders as if it were not there: every sample takes the same
// random numbers and meets the same surfaces, so the images are equal bit for bit.
TEST(RayVisibility, HiddenFromEveryRayIsAbsent) {
  for (const char *integrator : {"path", "bdpt"}) {
    json settings = {{"integrator", integrator}};
    // A black world: the ball would still widen the scene's bounds, which size the world light.
    json hidden = with(ball_scene(kHidden, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}}, json::object(),
                                  {{"color", {0, 0, 0}}}),
                       settings);
    json absent = hidden;
    absent["meshes"].erase(0);
    Image a = render_json(hidden.dump()), b = render_json(absent.dump());
    ASSERT_TRUE(a.all_finite());
    EXPECT_EQ(a.rgba, b.rgba) << integrator;
  }
}

// Hidden from the camera: pixels whose camera rays never come near the ball are the
// image with the ball seen, bit for bit (the path tracer; every later ray is the same);
// where the ball was, the floor behind it shows (grey: red and green alike).
TEST(RayVisibility, CameraHiddenBallStillShadowsAndIsNotSeen) {
  Image seen = render_json(ball_scene(nullptr).dump());
  Image hidden = render_json(ball_scene({{"camera", false}}).dump());
  ASSERT_TRUE(hidden.all_finite());
  // The top rows (the image is top-down) see the floor far behind the ball and the world
  // (the filter reaches 1.5 px).
  EXPECT_EQ(sum_of(seen, 0, 0, kSize, 6), sum_of(hidden, 0, 0, kSize, 6));
  // The middle: the red ball in one, the grey floor (with its shadow) in the other.
  auto redness = [](const Image &img) {
    double r = 0, g = 0;
    for (int y = 13; y < 19; ++y)
      for (int x = 13; x < 19; ++x) {
        r += img.rgba[(size_t(y) * kSize + x) * 4 + 0];
        g += img.rgba[(size_t(y) * kSize + x) * 4 + 1];
      }
    return r / g;
  };
  EXPECT_GT(redness(seen), 2.0);
  EXPECT_LT(redness(hidden), 1.3);
  expect_bdpt_matches_path(ball_scene({{"camera", false}}), "ball hidden from the camera");
}

// Direct light only (max_bounces 1) under a lamp: a ball hidden from diffuse rays still
// casts its shadow (shadow rays see it), so the floor is as with the ball seen.
TEST(RayVisibility, DiffuseHiddenBallShadowsInDirectLight) {
  json direct = {{"max_bounces", 1}, {"samples", 256}};
  Image seen = render_json(with(ball_scene(nullptr), direct).dump());
  Image hidden = render_json(with(ball_scene({{"diffuse", false}}), direct).dump());
  Image no_shadow = render_json(with(ball_scene({{"diffuse", false}, {"shadow", false}}), direct).dump());
  ASSERT_TRUE(hidden.all_finite());
  const double a = sum_of(seen, 0, 0, kSize, kSize), b = sum_of(hidden, 0, 0, kSize, kSize);
  EXPECT_NEAR(b / a, 1.0, 0.01);
  EXPECT_GT(sum_of(no_shadow, 0, 0, kSize, kSize) / a, 1.02);  // the shadow is gone
  expect_bdpt_matches_path(ball_scene({{"diffuse", false}}), "ball hidden from diffuse rays");
  expect_bdpt_matches_path(ball_scene({{"shadow", false}}), "ball casting no shadow");
}

// A mirror-like floor and a ball hidden from glossy rays: no reflection of it.
TEST(RayVisibility, GlossyHiddenBall) {
  json glossy_floor = {{"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.15}};
  expect_bdpt_matches_path(ball_scene({{"glossy", false}}, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}},
                                      json::object(), json::object(), glossy_floor),
                           "ball hidden from glossy rays");
}

// A glass ball hidden from transmission rays: refracted rays pass its far side.
TEST(RayVisibility, TransmissionHiddenGlassBall) {
  json glass = {{"type", "glass"}, {"ior", 1.45}, {"roughness", 0.2}};
  expect_bdpt_matches_path(ball_scene({{"transmission", false}}, glass), "glass ball hidden from transmission");
}

// Lamp and world: a lamp hidden from diffuse rays lights a diffuse scene not at all (the
// world still does); a lamp without shadows; the world hidden from the camera.
TEST(RayVisibility, LampAndWorld) {
  json dark = {{"color", {0, 0, 0}}};
  Image img = render_json(ball_scene(nullptr, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}},
                                     {{"visibility", {{"diffuse", false}}}}, dark).dump());
  ASSERT_TRUE(img.all_finite());
  EXPECT_EQ(sum_of(img, 0, 0, kSize, kSize), 0.0);
  json diffuse_off = {{"visibility", {{"diffuse", false}}}};
  json glossy_floor = {{"type", "principled"}, {"base_color", {0.5, 0.5, 0.5}}, {"roughness", 0.2}};
  expect_bdpt_matches_path(ball_scene(nullptr, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}}, diffuse_off,
                                      json::object(), glossy_floor),
                           "lamp hidden from diffuse rays");
  expect_bdpt_matches_path(ball_scene(nullptr, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}},
                                      {{"visibility", {{"shadow", false}}}}),
                           "lamp casting no shadows");
  json world_hidden = {{"color", {0.5, 0.6, 0.8}}, {"visibility", {{"camera", false}}}};
  json scene = ball_scene(nullptr, {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}}, json::object(), world_hidden);
  Image w = render_json(scene.dump());
  EXPECT_EQ(sum_of(w, 0, 0, kSize, 2), 0.0);  // the top rows (the image is top-down) see only the world
  expect_bdpt_matches_path(scene, "world hidden from the camera");
}

// A world of its own for camera rays (Light Path > Is Camera Ray in the World's nodes):
// camera rays that escape see the "camera" look, every other ray the world that lights.
// Against the world hidden from the camera, every sample of the path tracer takes the same
// random numbers (the camera look is a light no sampling chooses), so the difference of
// the two images is, in each pixel, the camera look times the share of its camera rays
// that escaped: a multiple of that colour between 0 and 1, 0 where the camera sees no sky.
TEST(RayVisibility, CameraWorldIsWhatCameraRaysSee) {
  const json red = {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}};
  const double look[3] = {0.1, 0.2, 0.9};
  json camera_world = {{"color", {0.5, 0.6, 0.8}}, {"camera", {{"color", {look[0], look[1], look[2]}}}}};
  json hidden_world = {{"color", {0.5, 0.6, 0.8}}, {"visibility", {{"camera", false}}}};
  json scene = ball_scene(nullptr, red, json::object(), camera_world);
  Image a = render_json(scene.dump()), b = render_json(ball_scene(nullptr, red, json::object(), hidden_world).dump());
  ASSERT_TRUE(a.all_finite());
  int sky = 0, ground = 0;
  for (int i = 0; i < kSize * kSize; ++i) {
    const double share = (a.rgba[4 * i + 2] - b.rgba[4 * i + 2]) / look[2];
    ASSERT_GE(share, -1e-5) << "pixel " << i;
    ASSERT_LE(share, 1 + 1e-5) << "pixel " << i;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(a.rgba[4 * i + c] - b.rgba[4 * i + c], share * look[c], 1e-5) << "pixel " << i << " channel " << c;
    sky += share > 1 - 1e-5;
    ground += share == 0;
  }
  EXPECT_GE(sky, 2 * kSize);  // the top rows see only the world
  EXPECT_GE(ground, kSize * kSize / 2);
  expect_bdpt_matches_path(scene, "world with a camera look");
  expect_matches_path(with(scene, {{"max_bounces", 4}}), "world with a camera look", "mlt", 64, 128, true);
  // Bad input names the world.
  SceneHandle s;
  EXPECT_NE(rdv_scene_set_world(s.s, R"({"camera": {"color": [1, -1, 0]}})"), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("world camera"), std::string::npos) << rdv_last_error();
  EXPECT_NE(rdv_scene_set_world(s.s, R"({"camera": {"colour": [1, 1, 0]}})"), RDV_OK);
}

// Bad input is an error naming the object; the scene file reports it and renders on.
TEST(RayVisibility, BadValuesNameTheObject) {
  SceneHandle s;
  float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t indices[3] = {0, 1, 2}, mat = 0, mesh = 0, inst = 0;
  ASSERT_EQ(rdv_scene_add_material(s.s, "m", R"({"type":"diffuse"})", &mat), RDV_OK);
  ASSERT_EQ(rdv_scene_add_mesh(s.s, "Ball", positions, 3, nullptr, nullptr, indices, 1, nullptr, mat, &mesh), RDV_OK);
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(rdv_scene_add_instance(s.s, mesh, identity, &inst), RDV_OK);
  EXPECT_NE(rdv_scene_set_instance_params(s.s, inst, R"({"visibility": {"camera": 0}})"), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("object 'Ball'"), std::string::npos) << rdv_last_error();
  EXPECT_NE(rdv_scene_set_instance_params(s.s, inst, R"({"visibility": {"reflection": false}})"), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("unknown key 'reflection'"), std::string::npos) << rdv_last_error();
  EXPECT_NE(rdv_scene_set_instance_params(s.s, inst, R"({"visibility": false})"), RDV_OK);
  EXPECT_NE(rdv_scene_add_light(s.s, "Lamp", R"({"type":"point","visibility":{"shadow":"no"}})", nullptr), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("Lamp"), std::string::npos) << rdv_last_error();
  EXPECT_NE(rdv_scene_set_world(s.s, R"({"visibility": []})"), RDV_OK);
}

// Path-space Metropolis (integrators/mlt/path_space.h): ray visibility is part of f (each
// edge blocked by what its kind of ray meets, each vertex visible to the ray that reaches
// it, the last segment to the light blocked by the light's shadow casters) and of the
// walks' densities (camera-side walks trace each kind, light-side walks what any ray but
// the camera's meets). Against the path tracer on the cases above, lit by the lamp alone
// (mlt samples no world light): hidden from the camera, from diffuse rays (mixed: its
// shadow stays), from shadow rays, from glossy rays over a glossy floor, a glass ball hidden
// from transmission, and the lamp hidden from diffuse rays and casting no shadows.
TEST(RayVisibility, PathSpaceMltMatchesPath) {
  const json dark = {{"color", {0, 0, 0}}}, red = {{"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}};
  // Rougher than the BDPT cases' floor: the lamp's glint in a 0.15 floor holds most of the
  // image, and 64 mutations per pixel leave the rest of it (1e-4 of the light) unvisited.
  const json glossy_floor = {{"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.4}};
  const json glass = {{"type", "glass"}, {"ior", 1.45}, {"roughness", 0.2}};
  auto check = [&](const json &scene, const std::string &what) { expect_matches_path(scene, what, "mlt", 64, 128, true); };
  // A dark ball: hidden from the camera, the bright floor behind it shows.
  check(ball_scene({{"camera", false}}, {{"type", "diffuse"}, {"color", {0.1, 0.02, 0.02}}}, json::object(), dark),
        "ball hidden from the camera");
  check(ball_scene({{"diffuse", false}}, red, json::object(), dark), "ball hidden from diffuse rays");
  check(ball_scene({{"shadow", false}}, red, json::object(), dark), "ball casting no shadow");
  check(ball_scene({{"glossy", false}}, red, json::object(), dark, glossy_floor), "ball hidden from glossy rays");
  check(ball_scene({{"transmission", false}}, glass, json::object(), dark), "glass hidden from transmission");
  check(ball_scene(nullptr, red, {{"visibility", {{"diffuse", false}}}}, dark, glossy_floor),
        "lamp hidden from diffuse rays");
  check(ball_scene(nullptr, red, {{"visibility", {{"shadow", false}}}}, dark), "lamp casting no shadows");
  // Without any ray visibility the flags change nothing: every key true is the plain image.
  json plain = ball_scene(nullptr, red, json::object(), dark);
  json all_true = ball_scene({{"camera", true}, {"diffuse", true}, {"glossy", true}, {"transmission", true},
                              {"shadow", true}, {"volume_scatter", true}},
                             red, json::object(), dark);
  json s = {{"integrator", "mlt"}, {"samples", 8}, {"mlt_chains", 16}};
  EXPECT_EQ(render_json(plain.dump(), s.dump()).rgba, render_json(all_true.dump(), s.dump()).rgba);
}

// Mixed visibility in BDPT's light strategies (integrators/bdpt/bdpt.h): scenes where light
// subpaths carry much of the image, against the path tracer (blocks, and the image's mean
// within 3.3 standard errors). A point lamp (the camera path cannot find it) over a white
// ball hidden from diffuse rays, a diffuse floor and a wall behind: the floor must not get
// the light the ball reflects (light walks reach the floor from the ball: the segment must
// be checked against the kind of the floor's scattering), and connections must trace that
// kind (through the ball, between floor and wall). A rough glass ball that casts no shadow
// under a small lamp: its caustic is mostly the light walks', the light straight through it
// next-event estimation's alone. A point lamp that casts no shadows: only next-event
// estimation lights the floor through the ball. Power (each part of bdpt.h's scheme
// switched off alone, 2026-11-29): without the check of the vertex before a light vertex,
// the first case's mean is 1.0063 (z 10.2); without the check that a connection's light
// vertex is seen by its kind, 1.0049 (z 7.8); with connections traced as any kind after a
// scattering, 0.9880 (z -17.7, 7/16 blocks); without leaving out the strategies no light
// walk can make a connection's segment for, the other two fail (0.9234, z -10.8; 0.9877,
// z -9.5). The cut of camera segments shows in
// BdptMisWeights.MixedVisibilityCornellBoxMatchesBruteForce (373 weights wrong without it).
TEST(RayVisibility, MixedVisibilityInBdptLightStrategies) {
  const json white = {{"type", "diffuse"}, {"color", {0.9, 0.9, 0.9}}}, dark = {{"color", {0, 0, 0}}};
  const json glass = {{"type", "glass"}, {"ior", 1.45}, {"roughness", 0.3}};
  // The scene lit by a point lamp of this radius (and visibility) instead of the area lamp.
  auto lit_by_point = [](json scene, float radius, const json &visibility = nullptr) {
    json lamp = {{"type", "point"}, {"radius", radius}, {"power", 200}, {"position", {0.8, -0.3, 2.6}}};
    if (!visibility.is_null()) lamp["visibility"] = visibility;
    scene["lights"] = {lamp};
    return scene;
  };
  json walled = lit_by_point(ball_scene({{"diffuse", false}}, white, json::object(), dark), 0);
  walled["materials"].push_back({{"name", "wall"}, {"type", "diffuse"}, {"color", {0.7, 0.7, 0.7}}});
  walled["meshes"].push_back({{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 5}}}, {"materials", {"wall"}},
                              {"transform", {{"translate", {0, 1.4, 0}}, {"rotate", {90, 0, 0}}}}});
  expect_bdpt_matches_path(walled, "point lamp, ball hidden from diffuse", 96, 32, true);
  expect_bdpt_matches_path(lit_by_point(ball_scene({{"shadow", false}}, glass, json::object(), dark), 0.3f),
                           "glass ball casting no shadow", 256, 32, true);
  expect_bdpt_matches_path(lit_by_point(ball_scene(nullptr, white, json::object(), dark), 0, {{"shadow", false}}),
                           "point lamp casting no shadows", 96, 32, true);
}

// A material's look per kind of ray (Light Path's ray types, shaders_map/ray_kinds.py) is a
// copy of its object on the same spot for each group of kinds: here a white ball seen by
// camera, glossy and transmission rays, and its copy seen by the other kinds, over a glossy
// floor under a point lamp (light walks carry the ball's light to the camera). Which copy a
// light walk's ray meets is the BVH's choice between coincident triangles, so light walks
// end there (bdpt.h): with a vertex on whichever copy was reported, BDPT's mean was 0.9665
// of the path tracer's (z -4.9, 2/16 blocks; 2026-11-30). Path-space mlt against the path
// tracer too.
TEST(RayVisibility, LookCopiesOnOneSpot) {
  const json white = {{"type", "diffuse"}, {"color", {0.9, 0.9, 0.9}}};
  const json glossy_floor = {{"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.2}};
  json scene = ball_scene({{"diffuse", false}, {"shadow", false}, {"volume_scatter", false}}, white, json::object(),
                          {{"color", {0, 0, 0}}}, glossy_floor);
  scene["meshes"][0]["look_copy"] = true;
  json copy = scene["meshes"][0];
  copy["name"] = "ball_for_other_rays";
  copy["visibility"] = {{"camera", false}, {"glossy", false}, {"transmission", false}};
  scene["meshes"].push_back(copy);
  scene["lights"] = {{{"type", "point"}, {"power", 200}, {"position", {0.8, -0.3, 2.6}}}};
  expect_bdpt_matches_path(scene, "a ball in two looks on one spot", 96, 32, true);
  expect_matches_path(scene, "a ball in two looks on one spot", "mlt", 96, 128, true);
}

}  // namespace test_ray_visibility
