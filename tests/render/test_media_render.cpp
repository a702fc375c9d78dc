// Participating media rendered end to end, against closed forms. z-tests on the mean
// over pixels at |z| < 4.5 (false alarm < 1e-5 per check); fixed seeds.
#include <gtest/gtest.h>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "media_grids.h"
#include "render_helpers.h"
#include "statistics.h"

namespace test_media_render {

using namespace rdv::test;
using nlohmann::json;

namespace {

void expect_channels(const Image &img, std::array<double, 3> expected, const std::string &what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected[c]) / std::hypot(m.standard_error, 2e-5 * expected[c] + 1e-7);
    EXPECT_LT(std::fabs(z), 4.5) << what << " channel " << c << ": mean " << m.mean << " expected " << expected[c]
                                 << " (se " << m.standard_error << ")";
  }
}

}  // namespace

// Beer-Lambert: an orthographic camera looks through a purely absorbing, chromatic
// slab (an index-matched box) at a uniform world: L = L_world exp(-sigma_a d).
TEST(MediaRender, BeerLambertSlab) {
  const double d = 0.8;
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}}},
            {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.5}, {"transform", {{"look_at", {{"from", {0, -5, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {2.0, 2.0, 2.0}}}},
            {"materials", {{{"name", "smoke"}, {"type", "volume"},
                            {"volume", {{"sigma_a", {0.5, 1.0, 2.5}}, {"sigma_s", {0, 0, 0}}}}}}},
            {"meshes", {{{"name", "slab"}, {"shape", {{"type", "box"}, {"size", {3.0, d, 3.0}}}}, {"materials", {"smoke"}}}}}};
  expect_channels(render_json(j.dump()), {2 * std::exp(-0.5 * d), 2 * std::exp(-1.0 * d), 2 * std::exp(-2.5 * d)},
                  "absorbing slab");
}

// Kirchhoff's furnace: inside a black enclosure emitting Le, a medium that absorbs,
// scatters (anisotropically) and emits sigma_a Le is in equilibrium: radiance is Le in
// every direction. The camera sits inside the medium; the medium is chromatic.
TEST(MediaRender, VolumetricFurnaceInsideEnclosure) {
  const double Le = 0.6;
  json sa = {0.3, 0.9, 2.0}, ss = {1.5, 0.4, 0.2};
  json j = {{"settings", {{"width", 12}, {"height", 12}, {"samples", 128}, {"max_bounces", 1000}}},
            {"camera", {{"focal_length", 18}, {"transform", {{"look_at", {{"from", {0.1, -0.2, 0.05}}, {"to", {1, 0.3, 0.2}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "shell"}, {"type", "diffuse"}, {"color", {0, 0, 0}}, {"emission", {Le, Le, Le}},
                            {"volume", {{"sigma_a", sa}, {"sigma_s", ss}, {"anisotropy", 0.6},
                                        {"emission", {0.3 * Le, 0.9 * Le, 2.0 * Le}}}}}}},
            {"meshes", {{{"name", "sphere"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", 24}, {"smooth", false}}},
                         {"materials", {"shell"}}}}}};
  expect_channels(render_json(j.dump()), {Le, Le, Le}, "volumetric furnace");
}

// A conservative (albedo 1) world fog around a white emitter-filled... the classic:
// a uniform world seen through infinite non-absorbing fog stays the world's radiance.
TEST(MediaRender, AlbedoOneFogKeepsUniformWorld) {
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}, {"max_bounces", 1000}}},
            {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0.7, 0.7, 0.7}}}},
            {"materials", {{{"name", "fog"}, {"type", "volume"}, {"volume", {{"sigma_a", 0}, {"sigma_s", {0.9, 1.2, 0.5}}, {"anisotropy", -0.3}}}}}},
            {"meshes", {{{"name", "cloud"}, {"shape", {{"type", "sphere"}, {"radius", 1.5}, {"smooth", false}}}, {"materials", {"fog"}}}}}};
  expect_channels(render_json(j.dump()), {0.7, 0.7, 0.7}, "albedo-1 fog ball under a uniform world");
}

// Extremes stay finite: densities from 1e-6 to 1e5, albedo 0 and 1, g = +-0.99, a spot
// in world fog.
TEST(MediaRender, ExtremesStayFinite) {
  for (double density : {1e-6, 1.0, 1e5})
    for (double g : {-0.99, 0.99})
      for (double albedo : {0.0, 1.0}) {
        json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 4}, {"max_bounces", 64}}},
                  {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 1}}, {"to", {0, 0, 0.5}}}}}}}},
                  {"world", {{"color", {0.1, 0.1, 0.1}}, {"volume", {{"density", density * 1e-3}, {"color", albedo}, {"anisotropy", g}}}}},
                  {"materials", {{{"name", "grey"}, {"type", "diffuse"}},
                                 {{"name", "smoke"}, {"type", "volume"}, {"volume", {{"density", density}, {"color", albedo}, {"anisotropy", g}}}}}},
                  {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"grey"}}},
                              {{"name", "cloud"}, {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}}, {"materials", {"smoke"}},
                               {"transform", {{"translate", {0, 0, 0.6}}}}}}},
                  {"lights", {{{"type", "spot"}, {"position", {0, 0, 3}}, {"direction", {0, 0, -1}}, {"power", 500}}}}};
        Image img = render_json(j.dump());
        EXPECT_TRUE(img.all_finite()) << "density " << density << " g " << g << " albedo " << albedo;
        EXPECT_EQ(img.progress.samples_dropped, 0u) << "density " << density << " g " << g << " albedo " << albedo;
      }
}

// ---- BDPT with media against path tracing -----------------------------------------
// K = 8 renders per integrator with independent seeds, 8x8-pixel blocks compared with
// Welch's t-test; false-alarm rate 1% over all blocks of these scenes (Sidak).

namespace {

json media_scene(const std::string &name) {
  std::ifstream f(source_path("scenes/" + name));
  std::stringstream ss;
  ss << f.rdbuf();
  return json::parse(ss.str());
}

// Blocks of 16x16 pixels: in-scattering near a lamp is heavy-tailed, and larger blocks
// keep the block means close enough to normal for the t-test.
// BDPT renders 8-16 spp where the path tracer's run means spread 5-10x more than its at 32
// (each side's error is printed): its share of the comparison's variance stays a few %.
constexpr int kMediaScenes = 8;
const double kMediaAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / (kMediaScenes * 4));

void expect_bdpt_matches_path(const json &scene, const std::string &what, int spp_path, int spp_bdpt) {
  auto runs = [&](const char *integrator, int spp, uint32_t seed0) {
    std::vector<std::vector<double>> out;
    for (int k = 0; k < 8; ++k) {
      json s = {{"width", 32}, {"height", 32}, {"integrator", integrator}, {"samples", spp}, {"seed", seed0 + k}, {"max_bounces", 8}};
      Image img = render_json(scene.dump(), s.dump());
      EXPECT_TRUE(img.all_finite()) << what;
      EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
      std::vector<double> v(size_t(img.width) * img.height);
      for (size_t i = 0; i < v.size(); ++i) v[i] = double(img.rgba[4 * i]) + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
      out.push_back(v);
    }
    return out;
  };
  auto pt = runs("path", spp_path, 1);
  auto bd = runs("bdpt", spp_bdpt, 2001);
  BlockComparison c = compare_blocks(bd, pt, 32, 32, 16, kMediaAlpha);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  const BrightnessComparison b = compare_brightness(bd, pt);  // each side's share of the noise
  std::printf("[ bdpt vs path ] %-16s errors of the run means: bdpt %.4f, path %.4f; %s\n", what.c_str(),
              b.error_a / b.mean_a, b.error_b / b.mean_b, c.detail.substr(0, 110).c_str());
}

}  // namespace

// Fog box lit by a spot with an occluder.
TEST(MediaBdptVsPath, FogLitBySpot) {
  json scene = media_scene("fog_spot.json");
  scene["lights"][0]["radius"] = 0.0;  // a delta spot: next-event estimation serves both integrators
  expect_bdpt_matches_path(scene, "fog + spot", 256, 8);
}

// The same with the camera standing inside the fog.
TEST(MediaBdptVsPath, CameraInsideFog) {
  json scene = media_scene("fog_spot.json");
  scene["lights"][0]["radius"] = 0.0;
  scene["camera"]["transform"] = {{"look_at", {{"from", {0, -3, 1.6}}, {"to", {0, 0, 1.2}}}}};
  expect_bdpt_matches_path(scene, "camera in fog", 256, 16);
}

// A glass ball in world fog: the volume caustic.
TEST(MediaBdptVsPath, GlassBallInFog) {
  json scene = media_scene("volume_caustic.json");
  scene["lights"][0]["radius"] = 0.4;
  expect_bdpt_matches_path(scene, "volume caustic", 256, 32);
}

// A chromatic medium (different extinction per channel) with backward scattering.
TEST(MediaBdptVsPath, ChromaticMedium) {
  json scene = media_scene("fog_spot.json");
  scene["lights"][0]["radius"] = 0.0;
  scene["materials"][3]["volume"] = {{"sigma_a", {0.02, 0.1, 0.3}}, {"sigma_s", {0.4, 0.2, 0.05}}, {"anisotropy", -0.4}};
  expect_bdpt_matches_path(scene, "chromatic", 128, 8);
}

// An emissive volume (a glowing ball of smoke) in fog, lighting the floor.
TEST(MediaBdptVsPath, EmissiveVolume) {
  json scene = media_scene("fog_spot.json");
  scene["lights"] = json::array();
  scene["materials"].push_back({{"name", "glow"}, {"type", "volume"},
                                {"volume", {{"density", 2.0}, {"color", 0.5}, {"emission_color", {1.0, 0.5, 0.2}}, {"emission_strength", 3.0}}}});
  scene["meshes"][2]["materials"] = {"glow"};
  expect_bdpt_matches_path(scene, "emissive volume", 64, 32);
}

// Fire: a volume light whose emission follows grids (an emission grid scaling the
// emission colour, blackbody from a temperature grid) inside thin smoke, lighting the
// floor through fog. Light subpaths and next-event estimation start from the flame.
TEST(MediaBdptVsPath, GridFireLightsTheFloor) {
  json scene = media_scene("fog_spot.json");
  scene["lights"] = json::array();
  json bounds = {{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}};
  json temperature = puff_grid(16, bounds);
  for (auto &v : temperature["values"]) v = float(v) * 1500.0f;
  scene["materials"].push_back({{"name", "fire"}, {"type", "volume"},
                                {"volume", {{"density", 0.8}, {"color", 0.6}, {"emission_color", {1.0, 0.4, 0.1}},
                                            {"emission_strength", 0.5}, {"emission_grid", puff_grid(16, bounds)},
                                            {"blackbody_intensity", 1.0}, {"temperature", 1.0},
                                            {"temperature_grid", temperature}, {"grid", puff_grid(16, bounds)}}}});
  scene["meshes"][2]["shape"] = {{"type", "box"}, {"size", {1, 1, 1}}};
  scene["meshes"][2]["materials"] = {"fire"};
  for (auto &g : {"emission_grid", "temperature_grid", "grid"})
    scene["materials"].back()["volume"][g]["transform"] = {{"translate", {0.2, 0.5, 1.4}}};
  scene["meshes"][2]["transform"] = {{"translate", {0.2, 0.5, 1.4}}};
  expect_bdpt_matches_path(scene, "grid fire", 128, 32);
}

// A heterogeneous cloud (a grid, delta and ratio tracking) filling the fog box.
TEST(MediaBdptVsPath, GridCloudLitBySpot) {
  json scene = media_scene("fog_spot.json");
  scene["lights"][0]["radius"] = 0.0;
  scene["materials"][3]["volume"] = {{"density", 3.0}, {"color", {0.9, 0.8, 0.7}}, {"anisotropy", 0.3},
                                     {"grid", puff_grid(32, {{-4, -4, -0.5}, {4, 4, 4}})}};
  expect_bdpt_matches_path(scene, "grid cloud", 256, 8);
}

// Nested media: smoke inside a glass ball inside the fog.
TEST(MediaBdptVsPath, SmokeInGlassInFog) {
  json scene = media_scene("volume_caustic.json");
  scene["lights"][0]["radius"] = 0.4;
  scene["materials"][0]["volume"] = {{"density", 1.5}, {"color", 0.8}, {"anisotropy", 0.2}};
  expect_bdpt_matches_path(scene, "smoke in glass", 256, 32);
}

TEST(MediaBdpt, VolumetricFurnaceInsideEnclosure) {
  const double Le = 0.6;
  json j = {{"camera", {{"focal_length", 18}, {"transform", {{"look_at", {{"from", {0.1, -0.2, 0.05}}, {"to", {1, 0.3, 0.2}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "shell"}, {"type", "diffuse"}, {"color", {0, 0, 0}}, {"emission", {Le, Le, Le}},
                            {"volume", {{"sigma_a", {0.3, 0.9, 2.0}}, {"sigma_s", {1.5, 0.4, 0.2}}, {"anisotropy", 0.6},
                                        {"emission", {0.3 * Le, 0.9 * Le, 2.0 * Le}}}}}}},
            {"meshes", {{{"name", "sphere"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", 24}, {"smooth", false}}},
                         {"materials", {"shell"}}}}}};
  expect_channels(render_json(j.dump(), R"({"integrator":"bdpt","width":12,"height":12,"samples":64,"max_bounces":1000})"),
                  {Le, Le, Le}, "volumetric furnace, bdpt");
}

// Replacing a material in place (the viewport's edit path) replaces its medium too.
TEST(MediaRender, SetMaterialReplacesTheMedium) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  auto loaded = rdv_tools::load_scene_json(R"({
    "camera": {"type": "orthographic", "ortho_scale": 0.5, "transform": {"look_at": {"from": [0, -5, 0], "to": [0, 0, 0]}}},
    "world": {"color": [1, 1, 1]},
    "materials": [{"name": "smoke", "type": "volume", "volume": {"sigma_a": 1.0, "sigma_s": 0}}],
    "meshes": [{"name": "slab", "shape": {"type": "box", "size": [3, 1, 3]}, "materials": ["smoke"]}]})", ".", scene);
  ASSERT_TRUE(loaded.problems.empty());
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(scene, 0, R"({"type": "volume", "volume": {"sigma_a": 2.0, "sigma_s": 0}})"));
  rdv_session *session = nullptr;
  ASSERT_EQ(RDV_OK, rdv_session_create(scene, R"({"width":4,"height":4,"samples":4})", &session));
  rdv_session_start(session);
  rdv_session_wait(session);
  float px[4 * 4 * 4];
  rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 4, 4, 1, px);
  EXPECT_NEAR(px[0], std::exp(-2.0), 1e-4);  // the new absorption, not exp(-1)
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
}

}  // namespace test_media_render
