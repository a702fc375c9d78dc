// Numerical stability at the extremes: millimetre- and kilometre-scale scenes (no
// self-shadowing "acne" from the ray offset), mirror-smooth and fully rough
// surfaces, tiny bright lamps. z-tests at |z| < 4.5 (false alarm < 1e-5 per check).
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_extremes {

using namespace rdv::test;
using nlohmann::json;

namespace {

// A white floor of size s centred at c, a sun at 60 degrees from the normal, an
// orthographic camera looking straight down: radiance = E cos(60) / pi everywhere.
json sunlit_floor(double s, const std::vector<double> &c) {
  double h = 3 * s;
  return {{"settings", {{"width", 12}, {"height", 12}, {"samples", 64}, {"max_bounces", 4}}},
          {"camera", {{"type", "orthographic"}, {"ortho_scale", s * 0.5}, {"clip_start", s * 0.01}, {"clip_end", h * 2},
                      {"transform", {{"look_at", {{"from", {c[0], c[1], c[2] + h}}, {"to", c}, {"up", {0, 1, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", s}}}, {"materials", {"white"}},
                       {"transform", {{"translate", c}, {"rotate", {0.0, 0.0, 13.0}}}}}}},
          {"lights", {{{"type", "sun"}, {"direction", {std::sin(M_PI / 3), 0, -std::cos(M_PI / 3)}}, {"angle", 0}, {"strength", 3}}}}};
}

void expect_uniform(const Image &img, double expected, const std::string &what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      ASSERT_NEAR(img.rgba[(size_t(y) * img.width + x) * 4], expected, 1e-3 * expected)
          << what << " pixel " << x << "," << y << " (self-shadowing from the ray offset?)";
}

}  // namespace

TEST(Extremes, NoShadowAcneFromMillimetreToKilometre) {
  const double expected = 3 * 0.5 / M_PI;
  expect_uniform(render_json(sunlit_floor(1e-4, {0, 0, 0}).dump()), expected, "0.1 mm floor at the origin");
  expect_uniform(render_json(sunlit_floor(1e-3, {2.5e-3, -1e-3, 7e-4}).dump()), expected, "1 mm floor");
  expect_uniform(render_json(sunlit_floor(1.0, {0, 0, 0}).dump()), expected, "1 m floor");
  expect_uniform(render_json(sunlit_floor(1e3, {1e4, -2e4, 3e3}).dump()), expected, "1 km floor far out");
  expect_uniform(render_json(sunlit_floor(1e5, {1e5, 1e5, 0}).dump()), expected, "100 km floor at 1e5");
}

// Glossy surfaces from mirror (delta) to fully rough under a uniform world stay
// finite and never reflect more than arrives (radiance <= the world's).
TEST(Extremes, RoughnessFromMirrorToRough) {
  for (double r : {0.0, 1e-4, 0.01, 0.05, 0.5, 1.0}) {
    json j = {{"settings", {{"width", 16}, {"height", 16}, {"samples", 16}}},
              {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 1}}, {"to", {0, 0, 0}}}}}}}},
              {"world", {{"color", {1, 1, 1}}}},
              {"materials", {{{"name", "metal"}, {"type", "glossy"}, {"color", {1, 1, 1}}, {"roughness", r}}}},
              {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}}}, {"materials", {"metal"}}}}}};
    Image img = render_json(j.dump());
    ASSERT_TRUE(img.all_finite()) << "roughness " << r;
    EXPECT_EQ(img.progress.samples_dropped, 0u) << "roughness " << r;
    MeanEstimate m = pixel_mean(img, 0);
    EXPECT_LT(m.mean, 1.0 + 4.5 * m.standard_error + 1e-4) << "roughness " << r;
  }
}

// A tiny, very bright point lamp almost touching a wall: finite everywhere.
TEST(Extremes, TinyBrightLampTouchingAWall) {
  json j = {{"settings", {{"width", 24}, {"height", 24}, {"samples", 16}}},
            {"camera", {{"transform", {{"look_at", {{"from", {0, -3, 0.5}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "grey"}, {"type", "diffuse"}}, {{"name", "mirror"}, {"type", "glossy"}, {"roughness", 0}}}},
            {"meshes", {{{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"grey"}}},
                        {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.3}}}, {"materials", {"mirror"}},
                         {"transform", {{"translate", {0.6, 0, 0.3}}}}}}},
            {"lights", {{{"type", "point"}, {"position", {0, 0, 1e-5}}, {"radius", 1e-6}, {"power", 1e6}},
                        {{"type", "area"}, {"position", {-0.5, 0, 1e-4}}, {"direction", {0, 0, -1}}, {"size", 1e-3}, {"power", 1e3}}}}};
  Image img = render_json(j.dump());
  EXPECT_TRUE(img.all_finite());
  EXPECT_EQ(img.progress.samples_dropped, 0u);
}

// ---- Every integrator at the extremes ------------------------------------------------
namespace {

const char *const kIntegrators[] = {"path", "bdpt", "pssmlt", "mmlt"};

json settings_for(const std::string &integrator, int size, int samples, int max_bounces) {
  return {{"width", size}, {"height", size}, {"integrator", integrator}, {"samples", samples},
          {"max_bounces", max_bounces}, {"mlt_chains", 16}, {"seed", 3}};
}

// A grey room (floor and back wall) lit by one point lamp of `power` watts.
json lamp_room(double power) {
  return {{"camera", {{"transform", {{"look_at", {{"from", {0, -3, 1}}, {"to", {0, 0, 0.5}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "grey"}, {"type", "diffuse"}, {"color", {0.6, 0.6, 0.6}}},
                         {{"name", "shiny"}, {"type", "glossy"}, {"color", {0.9, 0.9, 0.9}}, {"roughness", 0.2}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"grey"}}},
                      {{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"grey"}},
                       {"transform", {{"translate", {0, 1, 1}}, {"rotate", {90.0, 0.0, 0.0}}}}},
                      {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.3}}}, {"materials", {"shiny"}},
                       {"transform", {{"translate", {0.4, 0, 0.3}}}}}}},
          {"lights", {{{"type", "point"}, {"position", {-0.3, -0.2, 1.5}}, {"radius", 0.05}, {"power", power}}}}};
}

double image_sum(const Image &img) {
  double s = 0;
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
    for (int c = 0; c < 3; ++c) s += img.rgba[4 * i + c];
  return s;
}

}  // namespace

// Light power from 1e-6 W to 1e9 W: the image scales with it and nothing else changes.
// Path tracing and BDPT make the same random decisions at every power (no decision
// depends on the absolute brightness), so each pixel scales exactly, to float rounding.
// Metropolis' acceptance ratios and relative target do not depend on it either; a ratio
// rounded the other way can still turn one chain, so its image sum is held to 1%.
TEST(Extremes, LightPowerFromMicrowattsToGigawattsScalesTheImage) {
  for (const char *integrator : kIntegrators) {
    const json s = settings_for(integrator, 16, 8, 8);
    const Image unit = render_json(lamp_room(1.0).dump(), s.dump());
    ASSERT_TRUE(unit.all_finite()) << integrator;
    ASSERT_GT(image_sum(unit), 0) << integrator;
    for (double power : {1e-6, 1e9}) {
      const Image img = render_json(lamp_room(power).dump(), s.dump());
      ASSERT_TRUE(img.all_finite()) << integrator << " at " << power << " W";
      EXPECT_EQ(img.progress.samples_dropped, 0u) << integrator << " at " << power << " W";
      const double ratio = image_sum(img) / (power * image_sum(unit));
      std::printf("[ extremes ] %-6s %7.0e W: image / (power x image at 1 W) = %.6f\n", integrator, power, ratio);
      const bool metropolis = std::string(integrator) == "pssmlt" || std::string(integrator) == "mmlt";
      EXPECT_NEAR(ratio, 1.0, metropolis ? 0.01 : 1e-4) << integrator << " at " << power << " W";
      if (metropolis) continue;
      for (size_t i = 0; i < img.rgba.size(); i += 4)
        ASSERT_NEAR(img.rgba[i], power * unit.rgba[i], 1e-4 * power * unit.rgba[i] + 1e-30)
            << integrator << " at " << power << " W, pixel " << i / 4;
    }
  }
}

// Scenes at the edges of every parameter, through every integrator: never a NaN or Inf
// pixel, never a dropped (non-finite) sample. Roughness 1e-5 (a near-delta lobe that is
// not flagged specular), IOR 1.0001 (a surface that nearly vanishes) and 4 (diamond is
// 2.4), media of density 1e-6 and 1e5, an emissive sliver triangle 1e-7 wide (its area
// pdf ~1e7), the camera inside glass and inside fog, 1000 bounces in a white box (mmlt
// too: its pilot and bootstrap share their samples among the depths beyond 16, so its
// start-up no longer grows as depths^2: 31.6 s for this 8x8 image before, measured).
TEST(Extremes, EveryIntegratorStaysFiniteAtTheEdges) {
  auto furnace = [](const json &material, double radius, const std::vector<double> &eye) {
    return json{{"camera", {{"transform", {{"look_at", {{"from", eye}, {"to", {0, 0, 0}}}}}}}},
                {"world", {{"color", {0.8, 0.8, 0.8}}}},
                {"materials", {material}},
                {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", radius}, {"segments", 24}}},
                             {"materials", {material["name"]}}}}}};
  };
  const json glossy = {{"name", "m"}, {"type", "glossy"}, {"color", {1, 1, 1}}, {"roughness", 1e-5}};
  const json glass_low = {{"name", "m"}, {"type", "glass"}, {"ior", 1.0001}, {"roughness", 0}};
  const json glass_high = {{"name", "m"}, {"type", "glass"}, {"ior", 4.0}, {"roughness", 1e-5}};
  const json thin = {{"name", "m"}, {"type", "volume"}, {"volume", {{"density", 1e-6}, {"color", 1.0}}}};
  const json dense = {{"name", "m"}, {"type", "volume"}, {"volume", {{"density", 1e5}, {"color", 0.5}}}};
  json sliver = lamp_room(0);
  sliver["lights"] = json::array();
  sliver["materials"].push_back({{"name", "glow"}, {"type", "emission"}, {"strength", 1e6}});
  sliver["meshes"].push_back({{"name", "sliver"}, {"positions", {-1, 0.5, 1.2, 1, 0.5, 1.2, 0, 0.5, 1.2000001}},
                              {"indices", {0, 1, 2}}, {"materials", {"glow"}}});
  json white_box = furnace({{"name", "m"}, {"type", "diffuse"}, {"color", {0.99, 0.99, 0.99}}}, 2, {0, -1, 0});
  white_box["meshes"].push_back({{"name", "lamp"}, {"shape", {{"type", "sphere"}, {"radius", 0.1}}},
                                 {"materials", {"glow"}}, {"transform", {{"translate", {0, 1, 0}}}}});
  white_box["materials"].push_back({{"name", "glow"}, {"type", "emission"}, {"strength", 10}});
  const std::pair<const char *, json> scenes[] = {
      {"roughness 1e-5", furnace(glossy, 1, {0, -4, 0})},
      {"ior 1.0001", furnace(glass_low, 1, {0, -4, 0})},
      {"ior 4", furnace(glass_high, 1, {0, -4, 0})},
      {"density 1e-6", furnace(thin, 1, {0, -4, 0})},
      {"density 1e5", furnace(dense, 1, {0, -4, 0})},
      {"camera inside glass", furnace(glass_high, 3, {0, -1, 0})},
      {"camera inside fog", furnace(dense, 3, {0, -1e-3, 0})},
      {"emissive sliver 1e-7 wide", sliver},
      {"1000 bounces in a white box", white_box},
  };
  for (const auto &[what, scene] : scenes)
    for (const char *integrator : kIntegrators) {
      const bool deep = std::string(what).find("1000") != std::string::npos;
      const int bounces = deep ? 1000 : 64;
      const Image img = render_json(scene.dump(), settings_for(integrator, 8, 4, bounces).dump());
      std::printf("[ extremes ] %-28s %-6s %.2f s\n", what, integrator, img.progress.elapsed_seconds);
      EXPECT_TRUE(img.all_finite()) << what << ", " << integrator;
      EXPECT_EQ(img.progress.samples_dropped, 0u) << what << ", " << integrator;
    }
}

// A uniform world seen from inside a lossless glass ball (IOR 1.5) is the world, as in
// Cycles (Blender 3.4, this scene: mean 0.80005): refraction does not scale radiance in
// Radiance mode (bsdfs/dielectric.cpp; physically the radiance inside glass is n^2 times
// the world's, 1.8, which this engine showed before), for path tracing and for BDPT,
// whose light subpaths start outside the glass and enter it. z-test at |z| < 4.5.
TEST(Extremes, CameraInsideGlassSeesTheWorld) {
  const json scene = {{"camera", {{"transform", {{"look_at", {{"from", {0, -0.5, 0}}, {"to", {0, 0, 0}}}}}}}},
                      {"world", {{"color", {0.8, 0.8, 0.8}}}},
                      {"materials", {{{"name", "glass"}, {"type", "glass"}, {"ior", 1.5}, {"roughness", 0}}}},
                      {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 2}, {"segments", 32}}},
                                   {"materials", {"glass"}}}}}};
  for (const char *integrator : {"path", "bdpt"}) {
    const Image img = render_json(scene.dump(), settings_for(integrator, 12, 64, 1000).dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    const MeanEstimate m = pixel_mean(img, 1);
    std::printf("[ extremes ] camera inside glass, %-4s: mean %.4f +- %.4f (world 0.8)\n", integrator, m.mean,
                m.standard_error);
    EXPECT_LT(std::fabs(m.mean - 0.8) / std::hypot(m.standard_error, 1e-4 * 0.8), 4.5) << integrator;
  }
}

// A floor cut into 200 slivers (wedges of 1/100 radian from one corner) is lit like the
// same floor as two triangles: path tracing, same seed; image means within 4.5 standard
// errors of their difference.
TEST(Extremes, SliverTrianglesShadeLikeTheSurfaceTheyTile) {
  json positions = json::array(), indices = json::array();
  // A fan from one corner to 201 points along the opposite edges: thin wedges.
  positions.insert(positions.end(), {-1.0, -1.0, 0.0});
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 200.0;
    const double x = t < 0.5 ? 1.0 : 1.0 - (t - 0.5) * 4.0, y = t < 0.5 ? -1.0 + t * 4.0 : 1.0;
    positions.insert(positions.end(), {x, y, 0.0});
    if (k > 0) indices.insert(indices.end(), {0, k, k + 1});
  }
  auto floor_scene = [&](bool slivers) {
    json j = lamp_room(100);
    j["meshes"] = json::array();
    if (slivers)
      j["meshes"].push_back({{"name", "floor"}, {"positions", positions}, {"indices", indices}, {"materials", {"grey"}}});
    else
      j["meshes"].push_back({{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 2}}}, {"materials", {"grey"}}});
    j["camera"] = {{"type", "orthographic"}, {"ortho_scale", 1.6},
                   {"transform", {{"look_at", {{"from", {0, 0, 3}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}}};
    return j;
  };
  const json s = settings_for("path", 16, 16, 4);
  const Image quad = render_json(floor_scene(false).dump(), s.dump()), fan = render_json(floor_scene(true).dump(), s.dump());
  ASSERT_TRUE(quad.all_finite() && fan.all_finite());
  const MeanEstimate a = pixel_mean(quad, 0), b = pixel_mean(fan, 0);
  std::printf("[ extremes ] floor of 2 triangles %.5f +- %.5f, of 200 slivers %.5f +- %.5f\n", a.mean,
              a.standard_error, b.mean, b.standard_error);
  EXPECT_LT(std::fabs(a.mean - b.mean) / std::hypot(a.standard_error, b.standard_error), 4.5);
}

}  // namespace test_extremes
