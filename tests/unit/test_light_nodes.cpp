// A light's node tree as the add-on lowers it (`emission`: its Emission's colour and strength):
// multiplied into the lamp's colour, a Blackbody evaluated by the engine's own table, a Light
// Falloff by the distance to the point lit (Cycles 3.4's formula), and bad values refused with
// the light named. Deterministic.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "lights/lamp_emission.h"
#include "lights/light.h"
#include "textures/texture_graph.h"

namespace test_light_nodes {

using namespace rdv;
using nlohmann::json;

namespace {

Light light(const json &j) {
  Params p(j.dump(), "light 'Lamp'");
  return make_light(p).light;
}

}  // namespace

TEST(LightNodes, EmissionMultipliesTheLampsColour) {
  const json lamp = {{"type", "point"}, {"power", 100}, {"color", {1.0, 0.5, 0.25}}};
  const Color plain = light(lamp).radiance;
  json tinted = lamp;
  tinted["emission"] = {{"color", {{"node", "blackbody"}, {"temperature", 2800}}}, {"strength", 1.8}};
  TextureGraph g;
  std::vector<std::string> w;
  const Color blackbody = g.eval(g.parse(json{{"node", "blackbody"}, {"temperature", 2800}}, "test", w), ShadingPoint{});
  const Color expected = plain * blackbody * 1.8f, got = light(tinted).radiance;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], expected[i], 1e-6f * expected[i]) << i;
  EXPECT_GT(blackbody.x, blackbody.z) << "2800 K is warm";
}

TEST(LightNodes, BadEmissionNamesTheLight) {
  json lamp = {{"type", "point"}, {"power", 100}};
  for (const json &emission : {json{{"strength", -1}}, json{{"colour", 1}}, json(3)}) {
    lamp["emission"] = emission;
    try {
      light(lamp);
      ADD_FAILURE() << emission.dump();
    } catch (const Error &e) {
      EXPECT_NE(std::string(e.what()).find("light 'Lamp'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("emission"), std::string::npos) << e.what();
    }
  }
}

TEST(LightNodes, LightFalloffIsCyclesFormulaAtTheRayLength) {
  TextureGraph g;
  std::vector<std::string> w;
  auto falloff = [&](const char *output, float smooth) {
    return g.parse(json{{"node", "light_falloff"}, {"output", output}, {"strength", 3.0}, {"smooth", smooth}}, "test", w);
  };
  const int linear = falloff("LINEAR", 0), constant = falloff("CONSTANT", 0), quadratic = falloff("QUADRATIC", 0),
            smooth = falloff("QUADRATIC", 2);
  ShadingPoint sp;
  for (float d : {0.0f, 0.001f, 0.5f, 2.0f, 1000.0f}) {
    sp.ray_length = d;
    EXPECT_FLOAT_EQ(g.eval_float(linear, sp), 3.0f * d) << d;
    EXPECT_FLOAT_EQ(g.eval_float(constant, sp), 3.0f * d * d) << d;
    EXPECT_FLOAT_EQ(g.eval_float(quadratic, sp), 3.0f) << d;
    EXPECT_FLOAT_EQ(g.eval_float(smooth, sp), 3.0f * d * d / (2.0f + d * d)) << d;
  }
  sp.ray_length = INFINITY;  // a sun: Strength (Cycles 3.4 overflows there)
  for (int node : {linear, constant, quadratic, smooth}) EXPECT_FLOAT_EQ(g.eval_float(node, sp), 3.0f);
  EXPECT_TRUE(w.empty());
}

TEST(LightNodes, LightFalloffMakesEveryLampDependOnTheDistanceButTheSun) {
  const json falloff = {{"node", "light_falloff"}, {"output", "LINEAR"}, {"strength", 2.0}, {"smooth", 0}};
  for (const char *type : {"point", "spot", "area", "sun"}) {
    const bool sun = std::string(type) == "sun";
    const json lamp = {{"type", type}, {sun ? "strength" : "power", sun ? 3 : 100}, {"direction", {0, 0, -1}}};
    Params plain_params(lamp.dump(), "light 'Plain'");
    const UserLight plain = make_light(plain_params);
    json with = lamp;
    with["emission"] = {{"strength", falloff}};
    Params p(with.dump(), "light 'Lamp'");
    const UserLight user = make_light(p);
    const Light &l = user.light;
    if (sun) {  // an infinite ray: its Strength
      EXPECT_FALSE(l.by_distance);
      EXPECT_FLOAT_EQ(l.radiance.y, plain.light.radiance.y * 2.0f);
      continue;
    }
    EXPECT_TRUE(l.by_distance) << type;
    for (float d : {0.01f, 1.0f, 7.5f})
      EXPECT_NEAR(lamp_radiance(l, l.position, {0, 0, -1}, d).y, lamp_radiance(plain.light, l.position, {0, 0, -1}, d).y * 2.0f * d,
                  1e-5f * d * plain.light.radiance.y) << type << " at " << d;
  }
}

// A tree that varies over the lamp (Cycles 3.4 shades the point light leaves from, a lamp with
// no object): Geometry > Parametric runs over an area lamp as (0.5 + x, 0.5 + y) along its X
// and Y axes; Position is the point in the world; every routine (next-event estimation, a ray
// that meets the lamp, emission sampling) sees the same value at the same point, and the
// lamp's share of light samples is its mean over the area.
TEST(LampTextures, AnAreaLampsTreeIsEvaluatedWhereLightLeavesIt) {
  // A 2 x 1 m lamp at (3, 4, 5), turned 90 degrees about z (its X axis along world +y) and
  // facing down.
  const json parametric = {{"node", "texture_coordinate"}, {"output", "parametric"}};
  json lamp = {{"type", "area"}, {"shape", "rectangle"}, {"size", 2}, {"size_y", 1}, {"power", 100},
               {"transform", {{"rotate", {0, 0, 90}}, {"translate", {3, 4, 5}}}}};
  Params plain_params(lamp.dump(), "light 'Plain'");
  const UserLight plain = make_light(plain_params);
  lamp["emission"] = {{"color", parametric}};
  Params params(lamp.dump(), "light 'Cells'");
  const UserLight user = make_light(params);
  const Light &l = user.light;
  ASSERT_NE(l.emission, nullptr);
  EXPECT_FALSE(l.by_distance);
  EXPECT_NEAR(l.edge_u.y, 2.0f, 1e-5f);  // the lamp's X axis along world +y
  auto expected_at = [&](Vec3 p) {
    const float x = (p.y - 4.0f) / 2.0f, y = -(p.x - 3.0f) / 1.0f;  // lamp X = world y, lamp Y = world -x
    return plain.light.radiance * Color(0.5f + x, 0.5f + y, 0.0f);
  };
  const Vec3 ref(3.2f, 3.7f, 1.0f);
  for (Vec2 u : {Vec2(0.1f, 0.2f), Vec2(0.5f, 0.5f), Vec2(0.93f, 0.35f), Vec2(0.3f, 0.97f)}) {
    LightSample s;
    ASSERT_TRUE(sample_light(l, ref, u, Vec3(0.5f), s));
    const Color e = expected_at(s.p);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.L[c], e[c], 1e-4f * plain.light.radiance.y) << c;
    float t;
    Color hit;
    ASSERT_TRUE(intersect_light(l, Ray{ref, s.wi, kInf}, kInf, t, hit));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(hit[c], s.L[c], 1e-4f * plain.light.radiance.y) << c;
    EmissionSample em;
    ASSERT_TRUE(sample_emission(l, u, {0.4f, 0.6f}, Vec3(0.5f), Vec3(0.0f), 10.0f, em));
    const Color ee = expected_at(em.ray.o);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(em.Le[c], ee[c], 1e-4f * plain.light.radiance.y) << c;
  }
  // The mean luminance over the lamp: (0.5 R + 0.5 G) weighted by Rec.709.
  EXPECT_NEAR(l.emission->mean_luminance(), 0.5f * (0.2126f + 0.7152f), 1e-3f);

  // Position: the point in the world (a lamp has no object, so Object and Generated too).
  for (const char *output : {"position", "object", "generated"}) {
    lamp["emission"] = {{"color", {{"node", "texture_coordinate"}, {"output", output}}}};
    Params pp(lamp.dump(), "light 'Cells'");
    const UserLight at = make_light(pp);
    LightSample s;
    ASSERT_TRUE(sample_light(at.light, ref, {0.25f, 0.75f}, Vec3(0.5f), s)) << output;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(s.L[c], plain.light.radiance[c] * s.p[c], 1e-4f * plain.light.radiance.y * 5) << output << " " << c;
  }
}

// A point lamp's Parametric: Cycles' (u, v) of the spherical map of the direction light leaves
// by, (1 - u - v, u, 0) with u = 0.5 - atan2(x, y) / 2 pi, v = 1 - acos(z) / pi (negative parts
// emit nothing).
TEST(LampTextures, APointLampsParametricIsTheSphericalMapOfTheDirection) {
  json lamp = {{"type", "point"}, {"power", 100}, {"radius", 0},
               {"emission", {{"color", {{"node", "texture_coordinate"}, {"output", "parametric"}}}}}};
  Params params(lamp.dump(), "light 'Swirl'");
  const UserLight user = make_light(params);
  ASSERT_NE(user.light.emission, nullptr);
  const float intensity = 100.0f / (4 * kPi);
  struct Case { Vec3 dir; Color parametric; };
  for (const Case &c : {Case{{0, 1, 0}, {0.0f, 0.5f, 0}}, Case{{1, 0, 0}, {0.25f, 0.25f, 0}},
                        Case{{-1, 0, 0}, {0.0f, 0.75f, 0}}, Case{{0, 0, -1}, {1.0f, 0.0f, 0}}}) {
    const Color got = lamp_radiance(user.light, user.light.position, c.dir, 1.0f);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], intensity * c.parametric[k], 1e-5f * intensity) << c.dir.x << c.dir.y << c.dir.z << " " << k;
  }
}

}  // namespace test_light_nodes
