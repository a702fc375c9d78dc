// Index-matched medium boundaries that coincide with real surfaces: a fog or fire box
// whose bottom face lies in the floor plane. Which of two coplanar faces a ray meets
// first is up to rounding; paths must neither pass through the floor nor lose the
// medium they are in, whatever the order, for every integrator and for shadow rays,
// at millimetre, metre and kilometre scale.
//
// Each check renders K = 8 images per side with independent seeds and compares 8x8
// blocks of a 32 x 32 image with Welch's t-test (tests/support/statistics.h); false-alarm
// rate 1% over all blocks of this file (Sidak).
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_media_boundaries {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kSize = 32, kBlock = 8;
constexpr int kComparisons = 10;  // every compare() call in this file
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / (kComparisons * (kSize / kBlock) * (kSize / kBlock)));

// A 1 m box of fog lit by a lamp above it (or glowing on its own: fire) standing on a
// 6 m floor at height `ground`, its bottom face `bottom` above the floor (0: in the
// floor's plane; below 0: sunk into the floor, where no path reaches its hidden part, so
// it renders as the coplanar box should). The whole scene is scaled by `scale` (lamp
// power by scale^2 and densities by 1 / scale keep the image the same); off the origin
// (ground != 0) the ray offsets grow with the coordinates.
json box_on_floor(bool glow, double bottom, double scale, double ground) {
  auto at = [&](double x, double y, double z) { return json::array({x * scale, y * scale, (z + ground) * scale}); };
  json volume = glow ? json{{"density", 1.5 / scale}, {"color", 0.5}, {"emission_color", {1.0, 0.5, 0.2}},
                            {"emission_strength", 2.0}}
                     : json{{"density", 1.5 / scale}, {"color", 0.8}, {"anisotropy", 0.3}};
  json scene = {
      {"camera", {{"type", "perspective"}, {"focal_length", 30}, {"clip_start", 0.01 * scale}, {"clip_end", 100 * scale},
                  {"transform", {{"look_at", {{"from", at(0.4, -2.2, 1.4)}, {"to", at(0, 0, 0.25)}}}}}}},
      {"world", {{"color", {0, 0, 0}}}},
      {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.7, 0.7}}},
                     {{"name", "box"}, {"type", "volume"}, {"volume", volume}}}},
      {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6 * scale}}}, {"materials", {"floor"}},
                   {"transform", {{"translate", at(0, 0, 0)}}}},
                  {{"name", "box"}, {"shape", {{"type", "box"}, {"size", {scale, scale, (1 - bottom) * scale}}}},
                   {"materials", {"box"}}, {"transform", {{"translate", at(0, 0, (1 + bottom) / 2)}}}}}},
      {"lights", json::array()}};
  if (!glow)
    scene["lights"].push_back({{"name", "lamp"}, {"type", "point"}, {"position", at(0.6, -0.9, 2.2)},
                               {"radius", 0.05 * scale}, {"power", 400 * scale * scale}});
  return scene;
}

std::vector<std::vector<double>> renders(const json &scene, const char *integrator, int spp, uint32_t seed0) {
  json s = {{"width", kSize}, {"height", kSize}, {"integrator", integrator}, {"samples", spp}, {"max_bounces", 8}};
  return seeded_renders(scene.dump(), s.dump(), 8, seed0);
}

void compare(const std::vector<std::vector<double>> &a, const std::vector<std::vector<double>> &b,
             const std::string &what) {
  BlockComparison c = compare_blocks(a, b, kSize, kSize, kBlock, kAlpha);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  std::printf("[ boundaries ] %-34s %s\n", what.c_str(), c.detail.substr(0, 100).c_str());
}

// The coplanar box against the sunk one (its bottom 10% below the floor, far beyond any
// ray offset), with both integrators.
void expect_coplanar_matches_sunk(bool glow, double scale, double ground, const std::string &what) {
  const int spp_path = glow ? 64 : 128, spp_bdpt = 32;
  auto sunk = renders(box_on_floor(glow, -0.1, scale, ground), "path", spp_path, 1);
  json coplanar = box_on_floor(glow, 0, scale, ground);
  compare(renders(coplanar, "path", spp_path, 101), sunk, what + ": path, coplanar vs sunk");
  compare(renders(coplanar, "bdpt", spp_bdpt, 201), sunk, what + ": bdpt, coplanar vs sunk");
}

}  // namespace

TEST(MediaBoundaries, FogBoxOnTheFloor) { expect_coplanar_matches_sunk(false, 1, 0, "fog box"); }
TEST(MediaBoundaries, GlowingBoxOnTheFloor) { expect_coplanar_matches_sunk(true, 1, 0, "glowing box"); }
TEST(MediaBoundaries, MillimetreScale) { expect_coplanar_matches_sunk(false, 1e-3, 5, "fog box, mm"); }
TEST(MediaBoundaries, KilometreScale) { expect_coplanar_matches_sunk(false, 1e3, 0.37, "fog box, km"); }

// scenes/fire.json: a fire whose domain box stands on the floor, its only light, seen
// close to its foot, against the same fire in a box reaching below the floor (the
// grids keep their bounds: the box's hidden part is empty), with both integrators.
TEST(MediaBoundaries, FireSceneStandsOnTheFloor) {
  std::ifstream f(source_path("scenes/fire.json"));
  std::stringstream text;
  text << f.rdbuf();
  json scene = json::parse(text.str());
  scene["camera"]["transform"] = {{"look_at", {{"from", {0.1, -1.2, 0.35}}, {"to", {0.0, 0.0, 0.05}}}}};
  json sunk = scene;
  json &box = sunk["meshes"][2];
  ASSERT_EQ(box["name"], "fire_box");
  ASSERT_NEAR(double(box["transform"]["translate"][2]) - double(box["shape"]["size"][2]) / 2, 0.0, 1e-9);
  box["shape"]["size"][2] = double(box["shape"]["size"][2]) + 0.1;
  box["transform"]["translate"][2] = double(box["transform"]["translate"][2]) - 0.05;
  auto reference = renders(sunk, "path", 64, 1);
  compare(renders(scene, "path", 64, 101), reference, "fire scene: path, on the floor vs sunk");
  compare(renders(scene, "bdpt", 32, 201), reference, "fire scene: bdpt, on the floor vs sunk");
}

}  // namespace test_media_boundaries
