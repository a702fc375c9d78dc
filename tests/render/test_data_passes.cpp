// Cycles' data passes (film/data_passes.h): Mist of a plane at a known distance against the
// closed form of each falloff (orthographic view: every camera ray meets the plane at the
// same distance, so each pixel's mist is exact to float rounding); the world's mist is 1;
// a 30%-transparent card mixes in the mist behind it (z-test, |z| < 4.5); Object and
// Material Index exact on every pixel fully covered by one of two objects, 0 on the world,
// for every integrator; the alpha threshold picks the surface behind a thin card; bad pass
// indices and mist settings are refused naming the object; the Normal pass is a normal map's.
// Fixed seeds, 16x16 images.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_data_passes {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kSize = 16;

// A 4 x 4 plane at z = 0 (filling the view) seen from z = 3, under a point lamp of
// radius 0 (every integrator renders it, mlt included); optional cards in front.
json plane_scene(const json &camera, const json &mist, const json &settings, const json &extra_meshes = json::array(),
                 const json &extra_materials = json::array()) {
  json s = {{"width", kSize}, {"height", kSize}, {"samples", 16}, {"max_bounces", 4}, {"mlt_chains", 16}};
  s.update(settings);
  json materials = json::array({json{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.5, 0.5, 0.5}}}});
  for (const json &m : extra_materials) materials.push_back(m);
  json meshes =
      json::array({json{{"name", "plane"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}}});
  for (const json &m : extra_meshes) meshes.push_back(m);
  return {{"settings", s},
          {"camera", camera},
          {"world", {{"color", {0, 0, 0}}, {"strength", 0}, {"mist", mist}}},
          {"materials", materials},
          {"meshes", meshes},
          {"lights", {{{"type", "point"}, {"power", 200}, {"radius", 0}, {"transform", {{"translate", {0.5, 0.3, 2.5}}}}}}}};
}

json ortho_camera(double scale = 2.0) {
  return {{"type", "orthographic"}, {"ortho_scale", scale}, {"clip_start", 0.01},
          {"transform", {{"look_at", {{"from", {0, 0.001, 3}}, {"to", {0, 0, 0}}}}}}};
}

json perspective_camera(double distance = 3) {
  return {{"type", "perspective"}, {"focal_length", 50}, {"sensor_width", 36}, {"clip_start", 0.01},
          {"transform", {{"look_at", {{"from", {0, 0.001, distance}}, {"to", {0, 0, 0}}}}}}};
}

struct Vec3d {
  double x, y, z;
};
Vec3d normalized(Vec3d v) {
  const double l = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / l, v.y / l, v.z / l};
}

double falloff(const std::string &name, double x) {
  return name == "quadratic" ? x * x : name == "linear" ? x : std::sqrt(x);
}

}  // namespace

TEST(DataPasses, MistOfAPlaneMatchesEachFalloff) {
  // start 1, depth 4, plane at 3: x = 0.5.
  for (const char *fall : {"quadratic", "linear", "inverse_quadratic"}) {
    const double expected = falloff(fall, 0.5);
    for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt"}) {
      json mist = {{"start", 1}, {"depth", 4}, {"falloff", fall}};
      Image img = render_json(plane_scene(ortho_camera(), mist, {{"integrator", integrator}}).dump());
      ASSERT_EQ(img.mist.size(), size_t(kSize * kSize));
      for (size_t i = 0; i < img.mist.size(); ++i)
        // The view looks from (0, 0.001, 3): its axis tilts by 3.3e-4, so the plane's
        // distance along it varies by up to 3.3e-4 over the view (mist by < 1.7e-4).
        ASSERT_NEAR(img.mist[i], expected, 2e-4) << fall << " " << integrator << " pixel " << i;
    }
  }
}

TEST(DataPasses, MistThroughAPerspectiveCameraEveryIntegrator) {
  // Perspective: the mist's distance is from the camera's position. The middle 2 x 2
  // pixels' samples (within 2.5 px of the centre) meet the plane between 3 and 3.019 away:
  // linear mist from start 1, depth 4 is in [0.5, 0.5048].
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json mist = {{"start", 1}, {"depth", 4}, {"falloff", "linear"}};
    Image img = render_json(plane_scene(perspective_camera(), mist, {{"integrator", integrator}}).dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    for (int y = 7; y <= 8; ++y)
      for (int x = 7; x <= 8; ++x) {
        float m = img.mist[size_t(y) * kSize + size_t(x)];
        EXPECT_GE(m, 0.5f - 1e-5f) << integrator;
        EXPECT_LE(m, 0.5048f) << integrator;
      }
  }
}

TEST(DataPasses, WorldMistIsOneAndTransparencyMixesWhatIsBehind) {
  // A card 0.5 x 0.5 at z = 1 (2 from the camera), 30% Transparent BSDF, over the plane at 3;
  // the orthographic view (scale 4) sees the plane's edge: the world beyond.
  json card_material = {{"name", "card"},
                        {"type", "mix"},
                        {"fac", 0.3},
                        {"shader1", {{"type", "diffuse"}}},
                        {"shader2", {{"type", "transparent"}}}};
  json card = {{"name", "card"},
               {"shape", {{"type", "quad"}, {"size", 1}}},
               {"transform", {{"translate", {0, 0, 1}}}},
               {"materials", {"card"}}};
  json mist = {{"start", 1}, {"depth", 4}, {"falloff", "linear"}};
  json camera = ortho_camera(6.0);  // 6 units across: the 4-unit plane leaves 1 unit of world each side
  for (const char *integrator : {"path", "bdpt"}) {
    Image img = render_json(plane_scene(camera, mist, {{"integrator", integrator}, {"samples", 64}}, json::array({card}),
                                        json::array({card_material}))
                                .dump());
    // Corners (at most 1.5 px from the edge, 2.7 px from the plane): the world, mist 1.
    for (int y : {0, 1, 14, 15})
      for (int x : {0, 1, 14, 15}) EXPECT_EQ(img.mist[size_t(y) * kSize + size_t(x)], 1.0f) << integrator;
    // The card covers pixels 6..9 (1 unit of 6 across 16 px): the middle 2 x 2 fully.
    // Cover = 0.7 (1 - mist(2)) + 0.3 (1 - mist(3)) = 0.7 x 0.75 + 0.3 x 0.5: mist 0.325.
    double s = 0, s2 = 0;
    int n = 0;
    for (int y = 7; y <= 8; ++y)
      for (int x = 7; x <= 8; ++x) {
        double v = img.mist[size_t(y) * kSize + size_t(x)];
        s += v;
        s2 += v * v;
        ++n;
      }
    const double mean = s / n;
    // Per sample the cover is 0.525 or 0.675 + ... : its spread is at most 0.25 per sample.
    const double standard_error = 0.25 / std::sqrt(double(n) * 64.0);
    EXPECT_LT(std::fabs(mean - 0.325) / standard_error, 4.5) << integrator << ": " << mean;
  }
}

TEST(DataPasses, IndicesExactOnCoveredPixelsEveryIntegrator) {
  // Two quads side by side on the plane's level (1.4 x 2 each, x in [-2.2, -0.8] and
  // [0.8, 2.2]), nothing behind them: the world elsewhere.
  json materials = {{{"name", "red"}, {"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}}, {"pass_index", 7}},
                    {{"name", "blue"}, {"type", "diffuse"}, {"color", {0.2, 0.2, 0.8}}, {"pass_index", 2}}};
  json left = {{"name", "left"},
               {"shape", {{"type", "quad"}, {"size", 1}}},
               {"transform", {{"translate", {-1.5, 0, 0}}, {"scale", {1.4, 2, 1}}}},
               {"materials", {"red"}},
               {"pass_index", 3}};
  json right = {{"name", "right"},
                {"shape", {{"type", "quad"}, {"size", 1}}},
                {"transform", {{"translate", {1.5, 0, 0}}, {"scale", {1.4, 2, 1}}}},
                {"materials", {"blue"}},
                {"pass_index", 5}};
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json scene =
        plane_scene(perspective_camera(6), json::object(), {{"integrator", integrator}}, json::array({left, right}), materials);
    scene["meshes"].erase(0);  // no plane: the world behind
    Image img = render_json(scene.dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    // 50 mm on 36 mm at 6 units: the view is 4.32 units across, 0.27 per pixel; a pixel's
    // samples reach 1.5 px (0.405) beyond its centre.
    int covered = 0, world = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        // Looking down -z with look_at's up, the image's right is -x.
        const double px = 0.27, cx = -(x + 0.5 - 8) * px, cy = (8 - y - 0.5) * px;
        const double lo_x = cx - 1.5 * px, hi_x = cx + 1.5 * px, lo_y = cy - 1.5 * px, hi_y = cy + 1.5 * px;
        const size_t i = size_t(y) * kSize + size_t(x);
        const bool in_y = lo_y > -1 && hi_y < 1;
        if (in_y && lo_x > -2.2 && hi_x < -0.8) {
          EXPECT_EQ(img.object_index[i], 3.0f) << integrator << " " << x << "," << y;
          EXPECT_EQ(img.material_index[i], 7.0f) << integrator << " " << x << "," << y;
          ++covered;
        } else if (in_y && lo_x > 0.8 && hi_x < 2.2) {
          EXPECT_EQ(img.object_index[i], 5.0f) << integrator << " " << x << "," << y;
          EXPECT_EQ(img.material_index[i], 2.0f) << integrator << " " << x << "," << y;
          ++covered;
        } else if ((hi_x < -2.2 || lo_x > 2.2 || (lo_x > -0.8 && hi_x < 0.8)) || hi_y < -1 || lo_y > 1) {
          EXPECT_EQ(img.object_index[i], 0.0f) << integrator << " " << x << "," << y;
          EXPECT_EQ(img.material_index[i], 0.0f) << integrator << " " << x << "," << y;
          ++world;
        }
        // Edge pixels: one of the values its sample 0 saw, never a blend.
        for (float v : {img.object_index[i]}) EXPECT_TRUE(v == 0 || v == 3 || v == 5) << integrator << " " << v;
      }
    EXPECT_GE(covered, 20) << integrator;
    EXPECT_GE(world, 20) << integrator;
  }
}

// Shader AOVs (film/shader_aovs.h): a colour AOV and a value AOV written by the left quad's
// material, the right quad's writing only the colour one; exact on the pixels one quad covers
// (colour, 1 in alpha), 0 on the world, for every integrator; a half-transparent card in front
// adds its own write (two writes: alpha 2) and lets the quad's through, as Cycles' chain does.
TEST(ShaderAovs, WrittenWhereTheCameraSeesTheMaterialEveryIntegrator) {
  json materials = {{{"name", "red"}, {"type", "diffuse"}, {"color", {0.8, 0.2, 0.2}},
                     {"aovs", {{"mask", {{"color", {0.25, 0.5, 1.0}}, {"value", 9}}}, {"depth_v", {{"value", 0.75}}}}}},
                    {{"name", "blue"}, {"type", "diffuse"}, {"color", {0.2, 0.2, 0.8}},
                     {"aovs", {{"mask", {{"color", {1.0, 0.0, 0.0}}}}, {"unknown", {{"value", 3}}}}}}};
  json left = {{"name", "left"}, {"shape", {{"type", "quad"}, {"size", 1}}},
               {"transform", {{"translate", {-1.5, 0, 0}}, {"scale", {1.4, 2, 1}}}}, {"materials", {"red"}}};
  json right = {{"name", "right"}, {"shape", {{"type", "quad"}, {"size", 1}}},
                {"transform", {{"translate", {1.5, 0, 0}}, {"scale", {1.4, 2, 1}}}}, {"materials", {"blue"}}};
  const json aovs = json::array({{{"name", "mask"}, {"type", "color"}}, {{"name", "depth_v"}, {"type", "value"}}});
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json scene = plane_scene(perspective_camera(6), json::object(), {{"integrator", integrator}, {"aovs", aovs}},
                             json::array({left, right}), materials);
    scene["meshes"].erase(0);
    Image img = render_json(scene.dump());
    ASSERT_EQ(img.shader_aovs.size(), 2u) << integrator;
    int covered = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const double px = 0.27, cx = -(x + 0.5 - 8) * px, cy = (8 - y - 0.5) * px;
        const double lo_x = cx - 1.5 * px, hi_x = cx + 1.5 * px, lo_y = cy - 1.5 * px, hi_y = cy + 1.5 * px;
        const size_t i = size_t(y) * kSize + size_t(x);
        const float *mask = &img.shader_aovs[0][i * 4];
        const float value = img.shader_aovs[1][i];
        const bool in_y = lo_y > -1 && hi_y < 1;
        if (in_y && lo_x > -2.2 && hi_x < -0.8) {
          EXPECT_NEAR(mask[0], 0.25f, 1e-6f) << integrator;
          EXPECT_NEAR(mask[2], 1.0f, 1e-6f) << integrator;
          EXPECT_NEAR(mask[3], 1.0f, 1e-6f) << integrator << ": every sample wrote it";
          EXPECT_NEAR(value, 0.75f, 1e-6f) << integrator;
          ++covered;
        } else if (in_y && lo_x > 0.8 && hi_x < 2.2) {
          EXPECT_NEAR(mask[0], 1.0f, 1e-6f) << integrator;
          EXPECT_EQ(value, 0.0f) << integrator << ": the blue material writes no depth_v";
          ++covered;
        } else if (hi_x < -2.2 || lo_x > 2.2 || hi_y < -1 || lo_y > 1) {
          for (int c = 0; c < 4; ++c) EXPECT_EQ(mask[c], 0.0f) << integrator << ": the world writes none";
          EXPECT_EQ(value, 0.0f) << integrator;
        }
      }
    EXPECT_GE(covered, 20) << integrator;
  }
  // A card in front of the left quad, 70% transparent, writing mask (0, 1, 0): every sample
  // writes the card's (its alpha 0.3 is below the threshold, 0.5) and those that pass through
  // it (about 70%: the transparent closure is picked by its weight, as in Cycles) the quad's
  // too; at 50% the card alone writes (its alpha reaches the threshold).
  materials.push_back({{"name", "card"}, {"type", "mix"}, {"fac", 0.7}, {"shader1", {{"type", "diffuse"}}},
                       {"shader2", {{"type", "transparent"}}}, {"aovs", {{"mask", {{"color", {0, 1, 0}}}}}}});
  json card = {{"name", "card"}, {"shape", {{"type", "quad"}, {"size", 1}}},
               {"transform", {{"translate", {-1.5, 0, 1}}, {"scale", {1.4, 2, 1}}}}, {"materials", {"card"}}};
  json scene = plane_scene(perspective_camera(6), json::object(), {{"aovs", aovs}}, json::array({left, right, card}), materials);
  scene["meshes"].erase(0);
  Image img = render_json(scene.dump());
  const size_t centre = size_t(8) * kSize + 12;  // x = 12 is left of the image's centre: the left quad (image right is -x)
  const float *mask = &img.shader_aovs[0][centre * 4];
  EXPECT_GT(mask[3], 1.5f);
  EXPECT_LT(mask[3], 1.9f);
  EXPECT_NEAR(mask[1], 1.0f + 0.5f * (mask[3] - 1.0f), 1e-5f) << "the quad's 0.5 for each sample through";
  EXPECT_NEAR(mask[0], 0.25f * (mask[3] - 1.0f), 1e-5f);
  scene["materials"].back()["fac"] = 0.5;
  img = render_json(scene.dump());
  EXPECT_NEAR(img.shader_aovs[0][centre * 4 + 1], 1.0f, 1e-5f);
  EXPECT_NEAR(img.shader_aovs[0][centre * 4 + 3], 1.0f, 1e-5f);
}

// The World's AOV Outputs (Cycles writes them where camera rays leave for the world): a
// constant value, and a colour from Texture Coordinate > Generated, which is the ray's
// direction there (an orthographic view: one direction for every pixel), every integrator.
TEST(ShaderAovs, TheWorldWritesItsOwnAlongTheCameraRays) {
  const json aovs = json::array({{{"name", "sky"}, {"type", "color"}}, {{"name", "far"}, {"type", "value"}}});
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json scene = plane_scene(ortho_camera(), json::object(), {{"integrator", integrator}, {"aovs", aovs}});
    scene["meshes"].erase(0);  // nothing but the world
    scene["meshes"].push_back({{"name", "speck"}, {"shape", {{"type", "quad"}, {"size", 0.01}}},
                               {"transform", {{"translate", {0, 0, -5}}}}, {"materials", {"floor"}}});
    scene["world"]["aovs"] = {{"sky", {{"color", {{"node", "texture_coordinate"}, {"output", "generated"}}}}},
                              {"far", {{"value", 5}}}};
    Image img = render_json(scene.dump());
    ASSERT_EQ(img.shader_aovs.size(), 2u) << integrator;
    // The view from (0, 0.001, 3) toward the origin: direction (0, -1/3000, -1), normalised.
    const double dy = -0.001 / std::sqrt(9.0 + 1e-6), dz = -3.0 / std::sqrt(9.0 + 1e-6);
    int world = 0;
    for (int i = 0; i < kSize * kSize; ++i) {
      const float *sky = &img.shader_aovs[0][size_t(i) * 4];
      if (sky[3] == 0) continue;  // the speck's pixels
      ++world;
      EXPECT_NEAR(sky[0], 0.0, 1e-5) << integrator << " pixel " << i;
      EXPECT_NEAR(sky[1], dy, 1e-5) << integrator << " pixel " << i;
      EXPECT_NEAR(sky[2], dz, 1e-5) << integrator << " pixel " << i;
      EXPECT_EQ(sky[3], 1.0f) << integrator << " pixel " << i;
      EXPECT_EQ(img.shader_aovs[1][size_t(i)], 5.0f) << integrator << " pixel " << i;
    }
    EXPECT_GE(world, kSize * kSize - 9) << integrator;
  }
}

TEST(ShaderAovs, BadSettingsAreRefused) {
  json scene = plane_scene(perspective_camera(6), json::object(), json::object());
  for (const json &bad : {json("mask"), json::array({{{"type", "color"}}}), json::array({{{"name", "m"}, {"type", "vector"}}}),
                          json::array({{{"name", "m"}}, {{"name", "m"}}})}) {
    scene["settings"]["aovs"] = bad;
    EXPECT_THROW(render_json(scene.dump()), std::runtime_error) << bad.dump();
  }
}

// Object Info: each instance emits its own values (the same material on both quads): its
// colour, its Blender random number (random_id / (2^32 - 1), as Cycles), its pass index, its
// location; read on the pixels the quads cover alone. Blender's values against Cycles':
// blender.brightness.object_info.
TEST(ObjectInfo, EachInstanceEmitsItsOwnValues) {
  struct Case { const char *output; Vec3d left, right; };
  const double r_left = 123456789.0 / 4294967295.0, r_right = 4000000000.0 / 4294967295.0;
  const Case cases[] = {{"color", {0.2, 0.4, 0.6}, {0.9, 0.1, 0.3}},
                        {"random", {r_left, r_left, r_left}, {r_right, r_right, r_right}},
                        {"object_index", {3, 3, 3}, {5, 5, 5}},
                        {"location", {0, 0, 0}, {1.5, 0, 0}}};  // clamped: -1.5 emits 0
  for (const Case &c : cases) {
    json glow = {{"name", "glow"}, {"type", "emission"}, {"strength", 1},
                 {"color", {{"node", "object_info"}, {"output", c.output}}}};
    auto quad = [](const char *name, double x, int index, uint32_t random, json color) {
      return json{{"name", name},
                  {"shape", {{"type", "quad"}, {"size", 1}}},
                  {"transform", {{"translate", {x, 0, 0}}, {"scale", {1.4, 2, 1}}}},
                  {"materials", {"glow"}},
                  {"pass_index", index},
                  {"random_id", random},
                  {"color", color}};
    };
    json scene = plane_scene(perspective_camera(6), json::object(), {{"integrator", "path"}},
                             json::array({quad("left", -1.5, 3, 123456789u, {0.2, 0.4, 0.6, 1}),
                                          quad("right", 1.5, 5, 4000000000u, {0.9, 0.1, 0.3, 1})}),
                             json::array({glow}));
    scene["meshes"].erase(0);
    Image img = render_json(scene.dump());
    ASSERT_TRUE(img.all_finite()) << c.output;
    // The view as in IndicesExactOnCoveredPixelsEveryIntegrator: 0.27 units a pixel, +x to the left.
    int checked = 0;
    for (int y = 5; y < 11; ++y)
      for (int x = 0; x < kSize; ++x) {
        const double cx = -(x + 0.5 - 8) * 0.27;
        const bool left = cx - 0.41 > -2.2 && cx + 0.41 < -0.8, right = cx - 0.41 > 0.8 && cx + 0.41 < 2.2;
        if (!left && !right) continue;
        const Vec3d w = left ? c.left : c.right;
        const double want[3] = {w.x, w.y, w.z};
        const float *px = &img.rgba[(size_t(y) * kSize + size_t(x)) * 4];
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], want[k], 1e-5 * std::max(1.0, want[k])) << c.output << " " << x;
        ++checked;
      }
    EXPECT_GE(checked, 12) << c.output;
  }
}

// The Normal pass is the normal the surface shades with, a normal map's (as Cycles' pass,
// the closures' normal): a world-space normal map of one tilted normal over the whole plane
// (before 2026-11-29 the pass showed the mesh's normal, +z, under any map).
TEST(DataPasses, NormalIsTheMappedNormalEveryIntegrator) {
  const Vec3d n = normalized({0.3, -0.2, 0.9});
  json floor = {{"name", "mapped"}, {"type", "diffuse"}, {"color", {0.5, 0.5, 0.5}},
                {"normal", {{"node", "normal_map"}, {"space", "WORLD"},
                            {"color", {0.5 + 0.5 * n.x, 0.5 + 0.5 * n.y, 0.5 + 0.5 * n.z}}}}};
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json scene = plane_scene(perspective_camera(3), json::object(), {{"integrator", integrator}}, json::array(),
                             json::array({floor}));
    scene["meshes"][0]["materials"] = {"mapped"};
    Image img = render_json(scene.dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    for (int i = 0; i < kSize * kSize; ++i) {
      const float *p = &img.normal[size_t(i) * 3];
      EXPECT_NEAR(p[0], n.x, 1e-4) << integrator << " pixel " << i;
      EXPECT_NEAR(p[1], n.y, 1e-4) << integrator << " pixel " << i;
      EXPECT_NEAR(p[2], n.z, 1e-4) << integrator << " pixel " << i;
    }
  }
}

TEST(DataPasses, AlphaThresholdPicksTheSurfaceBehindAThinCard) {
  // A card 30% opaque (70% Transparent BSDF) over the plane. With threshold 0.2 the indices
  // are the card's. Below the default threshold 0.5 they are what the pixel's sample 0
  // sees after it: the plane where it passed through (70%), else still the card's (it
  // scattered there: the chain ended), as Cycles.
  json materials = json::array({json{{"name", "card"},
                                     {"type", "mix"},
                                     {"fac", 0.7},
                                     {"pass_index", 9},
                                     {"shader1", {{"type", "diffuse"}}},
                                     {"shader2", {{"type", "transparent"}}}}});
  json card = {{"name", "card"}, {"shape", {{"type", "quad"}, {"size", 4}}},
               {"transform", {{"translate", {0, 0, 1}}}}, {"materials", {"card"}}, {"pass_index", 4}};
  for (float threshold : {0.5f, 0.2f}) {
    json scene = plane_scene(ortho_camera(), json::object(), {{"integrator", "path"}, {"pass_alpha_threshold", threshold}},
                             json::array({card}), materials);
    scene["meshes"][0]["pass_index"] = 1;
    Image img = render_json(scene.dump());
    int plane = 0;
    for (size_t i = 0; i < img.object_index.size(); ++i) {
      const bool is_plane = img.object_index[i] == 1.0f && img.material_index[i] == 0.0f;
      const bool is_card = img.object_index[i] == 4.0f && img.material_index[i] == 9.0f;
      EXPECT_TRUE(is_plane || is_card) << img.object_index[i] << " " << img.material_index[i];
      plane += is_plane;
    }
    // 256 pixels, 70% plane: 179 +- 7.3 (binomial); the bounds are 8 standard deviations out.
    if (threshold > 0.3f) {
      EXPECT_GT(plane, 120);
      EXPECT_LT(plane, 238);
    } else {
      EXPECT_EQ(plane, 0);
    }
  }
}

TEST(DataPasses, BadPassIndexOrMistNamesTheObject) {
  SceneHandle sc;
  const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t idx[] = {0, 1, 2};
  uint32_t mat = 0, mesh = 0, inst = 0;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "m", R"({"type": "diffuse"})", &mat));
  ASSERT_EQ(RDV_OK, rdv_scene_add_mesh(sc.s, "Suzanne", p, 3, nullptr, nullptr, idx, 1, nullptr, mat, &mesh));
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(RDV_OK, rdv_scene_add_instance(sc.s, mesh, identity, &inst));
  for (const char *bad : {R"({"pass_index": -1})", R"({"pass_index": 40000})", R"({"pass_index": 1.5})"}) {
    EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_set_instance_params(sc.s, inst, bad)) << bad;
    EXPECT_NE(std::string(rdv_last_error()).find("Suzanne"), std::string::npos) << rdv_last_error();
  }
  EXPECT_EQ(RDV_OK, rdv_scene_set_instance_params(sc.s, inst, R"({"pass_index": 12})"));
  EXPECT_NE(RDV_OK, rdv_scene_add_material(sc.s, "Rust", R"({"type": "diffuse", "pass_index": -3})", &mat));
  EXPECT_NE(std::string(rdv_last_error()).find("Rust"), std::string::npos) << rdv_last_error();
  for (const char *bad : {R"({"mist": {"falloff": "cubic"}})", R"({"mist": {"depth": -1}})",
                          R"({"mist": {"start": 1, "height": 2}})"}) {
    EXPECT_NE(RDV_OK, rdv_scene_set_world(sc.s, bad)) << bad;
    EXPECT_NE(std::string(rdv_last_error()).find("mist"), std::string::npos) << rdv_last_error();
  }
}

}  // namespace test_data_passes
