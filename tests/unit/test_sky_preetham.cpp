// Blender's Preetham sky (lights/sky_preetham.h): finite and not negative everywhere, the ground
// included, brighter toward the sun, a blue zenith that whitens with turbidity, and bad
// settings named.
// Its image against Cycles is blender.brightness.preetham_sky. Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include "core/error.h"
#include "lights/sky_preetham.h"

namespace test_sky_preetham {

using namespace rdv;

namespace {

PreethamSky::Settings parse(const std::string &json) {
  Params p(json, "world sky");
  PreethamSky::Settings s = PreethamSky::from_params(p);
  p.check_all_used();
  return s;
}

Vec3 from_angles(float elevation, float azimuth) {
  return Vec3(std::cos(elevation) * std::sin(azimuth), std::cos(elevation) * std::cos(azimuth), std::sin(elevation));
}

}  // namespace

TEST(PreethamSky, LooksLikeASky) {
  const Vec3 sun = from_angles(0.5f, 1.0f);
  PreethamSky sky(parse(R"({"sun_direction":[)" + std::to_string(sun.x) + "," + std::to_string(sun.y) + "," +
                        std::to_string(sun.z) + R"(],"turbidity":3})"));
  for (float e = -1.5f; e <= 1.5f; e += 0.25f)
    for (float a = -3.0f; a <= 3.0f; a += 0.5f) {
      const Color c = sky.radiance(from_angles(e, a));
      ASSERT_TRUE(is_finite(c) && c.x >= 0 && c.y >= 0 && c.z >= 0) << e << " " << a;
    }
  // Brighter toward the sun than away from it, at the same height; the zenith bluer than red.
  EXPECT_GT(luminance(sky.radiance(from_angles(0.5f, 1.2f))), 2 * luminance(sky.radiance(from_angles(0.5f, 1.0f + kPi))));
  const Color zenith = sky.radiance(Vec3(0, 0, 1));
  EXPECT_GT(zenith.z, zenith.x);
  // Below the horizon Cycles clamps the zenith angle (not the angle to the sun): the ground is
  // lit, as the horizon is.
  EXPECT_GT(luminance(sky.radiance(from_angles(-0.8f, 1.0f + kPi))), 0.2f * luminance(sky.radiance(from_angles(0.0f, 1.0f + kPi))));
  // Hazier skies are whiter at the zenith.
  PreethamSky hazy(parse(R"({"sun_direction":[)" + std::to_string(sun.x) + "," + std::to_string(sun.y) + "," +
                         std::to_string(sun.z) + R"(],"turbidity":10})"));
  const Color z10 = hazy.radiance(Vec3(0, 0, 1));
  EXPECT_GT(z10.x / z10.z, zenith.x / zenith.z);
}

TEST(PreethamSky, BadSettingsAreNamed) {
  EXPECT_NO_THROW(parse(R"({"type":"preetham","sun_direction":[0,1,1],"turbidity":2})"));
  for (const char *json : {R"({"sun_direction":[0,0,0]})", R"({"turbidity":0.5})", R"({"turbidity":1e9})",
                           R"({"sun_direction":[1,2]})"}) {
    try {
      parse(json);
      ADD_FAILURE() << json << " was accepted";
    } catch (const Error &e) {
      EXPECT_NE(std::string(e.what()).find("world sky"), std::string::npos) << e.what();
    }
  }
}

}  // namespace test_sky_preetham
