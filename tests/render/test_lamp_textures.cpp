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

namespace test_lamp_textures {

using namespace rdv::test;
using nlohmann::json;

TEST(LampTextures, PathAndBdptAgree) {
  expect_small_bdpt_matches_path(load_scene("lamp_textures.json"), "lamp textures");
}

}  // namespace test_lamp_textures
