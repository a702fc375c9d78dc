// A light's node tree as the add-on lowers it (`emission`: its Emission's colour and strength):
// multiplied into the lamp's colour, a Blackbody evaluated by the engine's own table, and bad
// values refused with the light named. Deterministic.
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
