// Whole scenes at every scale and far from the origin render as the unit scene does.
// The Cornell box (walls meeting at corners, boxes standing on the floor) with its lamp
// 1% of the box height below the ceiling is scaled from 0.1 mm to 100 km and moved up
// to 1e5 units from the origin; each image is compared with the unit box's block by
// block, with the path tracer and BDPT. Ray offsets that do not follow the rounding
// error of each point fail here: a fixed 1.5e-5 offset near the origin sent rays from
// the lamp of the millimetre box through the ceiling (image mean 0.85 of the unit
// box's), 256 ulps at 3e4 from the origin moved origins through the walls (0.98).
//
// Each check renders K = 8 images per side with independent seeds and compares 8x8
// blocks of a 32 x 32 image with Welch's t-test (tests/support/statistics.h); the image
// means must also agree within 1% (the standard error of such a mean, measured: about
// 0.2%). False-alarm rate: 1% over all blocks of this file (Sidak).
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_scene_scales {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kSize = 32, kBlock = 8, kRuns = 8;
constexpr int kComparisons = 2 * 8;  // every compare() call in this file
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / (kComparisons * (kSize / kBlock) * (kSize / kBlock)));

// scenes/cornell_box.json (2 units tall) with its lamp 0.02 below the ceiling, scaled by
// `scale` about the origin and then moved by `offset`. Emission is radiance, so the
// image does not change with scale.
json cornell_box(double scale, const std::vector<double> &offset) {
  std::ifstream f(source_path("scenes/cornell_box.json"));
  std::stringstream text;
  text << f.rdbuf();
  json scene = json::parse(text.str());
  auto place = [&](const json &p) {
    return json::array({double(p[0]) * scale + offset[0], double(p[1]) * scale + offset[1],
                        double(p[2]) * scale + offset[2]});
  };
  json &look_at = scene["camera"]["transform"]["look_at"];
  look_at["from"] = place(look_at["from"]);
  look_at["to"] = place(look_at["to"]);
  scene["camera"]["clip_start"] = 0.1 * scale;
  scene["camera"]["clip_end"] = 100 * scale;
  for (json &mesh : scene["meshes"]) {
    json &t = mesh["transform"];
    json translate = t.contains("translate") ? t["translate"] : json::array({0.0, 0.0, 0.0});
    if (mesh["name"] == "lamp") translate[2] = double(translate[2]) - 0.02;
    t["translate"] = place(translate);
    t["scale"] = {scale, scale, scale};
  }
  return scene;
}

std::vector<std::vector<double>> renders(const json &scene, const std::string &integrator, uint32_t seed0) {
  json s = {{"width", kSize}, {"height", kSize}, {"integrator", integrator},
            {"samples", integrator == "path" ? 64 : 24}, {"max_bounces", 8}};
  return seeded_renders(scene.dump(), s.dump(), kRuns, seed0);
}

// The unit box at the origin, rendered once per integrator for the whole file.
const std::vector<std::vector<double>> &unit_box(const std::string &integrator) {
  static std::map<std::string, std::vector<std::vector<double>>> cache;
  auto it = cache.find(integrator);
  if (it == cache.end()) it = cache.emplace(integrator, renders(cornell_box(1, {0, 0, 0}), integrator, 1)).first;
  return it->second;
}

void expect_like_unit_box(double scale, const std::vector<double> &offset, const std::string &what) {
  for (const std::string integrator : {"path", "bdpt"}) {
    BlockComparison c =
        compare_blocks(renders(cornell_box(scale, offset), integrator, 101), unit_box(integrator), kSize, kSize, kBlock, kAlpha);
    EXPECT_EQ(c.failed, 0) << what << ", " << integrator << ": " << c.detail;
    EXPECT_NEAR(c.mean_ratio, 1.0, 0.01) << what << ", " << integrator;
    std::printf("[ scales ] %-26s %-4s %s\n", what.c_str(), integrator.c_str(), c.detail.substr(0, 90).c_str());
  }
}

}  // namespace

TEST(SceneScales, TenthOfAMillimetre) { expect_like_unit_box(1e-4, {0, 0, 0}, "0.1 mm box"); }
TEST(SceneScales, Millimetre) { expect_like_unit_box(1e-3, {0, 0, 0}, "1 mm box"); }
TEST(SceneScales, Kilometre) { expect_like_unit_box(1e3, {0, 0, 0}, "1 km box"); }
TEST(SceneScales, HundredKilometres) { expect_like_unit_box(1e5, {0, 0, 0}, "100 km box"); }
TEST(SceneScales, UnitBox3e4FromTheOrigin) { expect_like_unit_box(1, {3e4, 0, 0}, "unit box at x = 3e4"); }
TEST(SceneScales, UnitBox1e4FromTheOriginOnEveryAxis) { expect_like_unit_box(1, {1e4, -1e4, 1e4}, "unit box at 1e4 (x, y, z)"); }
// A 200 m block 1e5 from the origin. (A 2 m box there is no longer the same box:
// float32 spaces coordinates 7.8 mm apart at 1e5, and the lamp's area alone changes by
// 2-3%; Blender stores its vertices in float32 too.)
TEST(SceneScales, Block1e5FromTheOrigin) { expect_like_unit_box(100, {1e5, -1e5, 0}, "200 m block at 1e5 (x, y)"); }
TEST(SceneScales, MillimetreBoxOneUnitFromTheOrigin) { expect_like_unit_box(1e-3, {1, 0, 1}, "mm box at 1 (x, z)"); }

}  // namespace test_scene_scales
