// A light's node tree as the add-on lowers it (`emission`: its Emission's colour and strength):
// multiplied into the lamp's colour, a Blackbody evaluated by the engine's own table, a Light
// Falloff by the distance to the point lit (Cycles 3.4's formula), and bad values refused with
// the light named. Deterministic.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "lights/light.h"
#include "textures/texture_graph.h"

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
      EXPECT_NEAR(lamp_radiance(l, {0, 0, -1}, d).y, lamp_radiance(plain.light, {0, 0, -1}, d).y * 2.0f * d,
                  1e-5f * d * plain.light.radiance.y) << type << " at " << d;
  }
}
