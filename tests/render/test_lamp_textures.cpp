// Lamps whose node tree varies over them (lights/lamp_emission.h; Cycles shades the point light
// leaves the lamp from): scenes/lamp_textures.json has an area lamp with a checker of its
// Parametric coordinates, seen in a glossy floor; a spot whose colour is a gradient of its
// Parametric (the spherical map of the direction); a sphere lamp whose strength is a noise of the
// point's position. Next-event estimation, rays that meet the lamps and BDPT's light subpaths
// each evaluate the tree at their own point: path tracing and BDPT give the same image (Welch's
// t-test per 8x8 block, 1% false-alarm rate for the file, Sidak-corrected per block) and the
// same mean (|z| < 3.3: 1e-3). The Metropolis integrators: MltVsBdpt.LampTextures
// (test_mlt.cpp); Cycles: blender.brightness.lamp_textures; the values at points and
// directions: LampTextures.* (unit/test_light_nodes.cpp).
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>
#include "render_helpers.h"
#include "statistics.h"

using namespace rdv::test;
using nlohmann::json;

TEST(LampTextures, PathAndBdptAgree) {
  const json scene = load_scene("lamp_textures.json");
  const double alpha_per_block = 1.0 - std::pow(1.0 - 0.01, 1.0 / 16);
  auto runs = [&](const char *integrator, int samples, uint32_t seed) {
    return seeded_renders(scene.dump(), json({{"integrator", integrator}, {"samples", samples}, {"width", 32},
                                              {"height", 32}}).dump(), 6, seed);
  };
  const std::vector<std::vector<double>> bdpt = runs("bdpt", 16, 100), path = runs("path", 32, 200);
  BlockComparison c = compare_blocks(bdpt, path, 32, 32, 8, alpha_per_block);
  EXPECT_EQ(c.failed, 0) << c.detail;
  const BrightnessComparison b = compare_brightness(bdpt, path);
  EXPECT_LT(std::fabs(b.z), 3.3) << "bdpt " << b.mean_a << " path " << b.mean_b;
  std::printf("[ lamp textures ] bdpt / path mean %.4f +- %.4f; %s\n", b.mean_a / b.mean_b, b.error / b.mean_b,
              c.detail.substr(0, 100).c_str());
}
