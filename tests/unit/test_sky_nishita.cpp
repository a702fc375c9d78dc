// Blender's Nishita sky (lights/sky_nishita.h): the sky a user expects (finite, blue above,
// reddened and brighter toward a low sun, black ground below the fade), the sun's disc where
// its settings put it with its power kept by the baked map, and bad settings named. Its
// brightness against Cycles is blender.brightness.nishita_sky. Deterministic.
#include <gtest/gtest.h>
#include "core/error.h"
#include "lights/sky_nishita.h"

namespace test_sky_nishita {

using namespace rdv;

namespace {

Vec3 from_angles(float elevation, float azimuth) {  // azimuth from +X toward +Y
  return Vec3(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

NishitaSky::Settings parse(const std::string &json) {
  Params p(json, "world sky");
  NishitaSky::Settings s = NishitaSky::from_params(p);
  p.check_all_used();
  return s;
}

}  // namespace

TEST(NishitaSky, LooksLikeASky) {
  const NishitaSky sky(NishitaSky::Settings{});  // Blender's defaults: sun 15 degrees up
  const Vec3 sun = sky.sun_direction();
  EXPECT_NEAR(std::asin(sun.z), 0.261799f, 1e-5f);
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j < 36; ++j) {
      const Color c = sky.radiance(from_angles(kPi * (i / 40.0f - 0.5f), 2 * kPi * j / 36.0f));
      EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && min_component(c) >= 0)
          << i << " " << j;
    }
  const Color zenith = sky.radiance(Vec3(0, 0, 1));
  EXPECT_GT(zenith.z, zenith.x) << "the zenith is blue";
  EXPECT_GT(luminance(zenith), 0.0f);
  // Toward the sun (just outside its disc) brighter than away from it, at the same height.
  const float azimuth = std::atan2(sun.y, sun.x);
  const Color near_sun = sky.radiance(from_angles(0.30f, azimuth)), away = sky.radiance(from_angles(0.30f, azimuth + kPi));
  EXPECT_GT(luminance(near_sun), 3 * luminance(away));
  // Mirror symmetric about the sun's meridian.
  for (float d : {0.4f, 1.3f, 2.5f}) {
    const Color a = sky.radiance(from_angles(0.5f, azimuth + d)), b = sky.radiance(from_angles(0.5f, azimuth - d));
    EXPECT_NEAR(luminance(a), luminance(b), 1e-3f * luminance(a)) << d;
  }
  // Below the horizon the sky's lowest row fades to black ground at 0.4 below.
  EXPECT_EQ(luminance(sky.radiance(Vec3(0, 0, -1))), 0.0f);
  EXPECT_GT(luminance(sky.radiance(normalize(Vec3(1, 0, -0.1f)))), 0.0f);
  // The disc: far brighter than the sky beside it.
  EXPECT_GT(luminance(sky.radiance(sun)), 1000 * luminance(near_sun));
}

// The settings move the sun where Blender puts it: elevation up from the horizon, rotation
// turning it about Z (Cycles' direction for rotation r: azimuth pi / 2 - r from +X).
TEST(NishitaSky, SunWhereTheSettingsPutIt) {
  NishitaSky::Settings s;
  s.sun_elevation = 0.6f;
  s.sun_rotation = 1.1f;
  const NishitaSky sky(s);
  const Vec3 expected = from_angles(0.6f, kPi / 2 - 1.1f);
  EXPECT_NEAR(dot(sky.sun_direction(), expected), 1.0f, 1e-6f);
  const float half = s.sun_size / 2;
  const Color centre = sky.radiance(expected);
  const Color rim = sky.radiance(from_angles(0.6f + 0.9f * half, kPi / 2 - 1.1f));
  EXPECT_LT(luminance(rim), luminance(centre)) << "limb darkening";
  EXPECT_GT(luminance(rim), 0.3f * luminance(centre));
  const Color outside = sky.radiance(from_angles(0.6f + 1.5f * half, kPi / 2 - 1.1f));
  EXPECT_LT(luminance(outside), 1e-3f * luminance(centre));
  // Without the disc: the sky there.
  s.sun_disc = false;
  EXPECT_LT(luminance(NishitaSky(s).radiance(expected)), 1e-3f * luminance(centre));
}

// The baked map keeps the disc's power: its pixels (supersampled) sum to the disc's
// radiance integrated over its cap, within 1%.
TEST(NishitaSky, BakedMapKeepsTheSunsPower) {
  NishitaSky::Settings s;
  s.sun_elevation = 0.4f;
  s.sun_rotation = 0.3f;
  const NishitaSky sky(s), no_disc([&] {
    NishitaSky::Settings t = s;
    t.sun_disc = false;
    return t;
  }());
  const int width = 2048, height = width / 2;
  const std::vector<float> with = sky.bake(width), without = no_disc.bake(width);
  double baked = 0;
  for (int j = 0; j < height; ++j) {
    const double theta0 = kPi * j / height, theta1 = kPi * (j + 1) / height;
    const double pixel_solid_angle = (std::cos(theta0) - std::cos(theta1)) * 2 * kPi / width;
    for (int i = 0; i < width; ++i) {
      const size_t k = (size_t(j) * width + size_t(i)) * 3 + 1;  // green
      baked += (with[k] - without[k]) * pixel_solid_angle;
    }
  }
  // The disc alone, integrated on a fine polar grid about its centre.
  const Vec3 c = sky.sun_direction(), u = normalize(cross(c, Vec3(0, 0, 1))), v = cross(c, u);
  const float half = s.sun_size / 2;
  const int n = 400;
  double direct = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double r = half * (a + 0.5) / n, phi = 2 * kPi * (b + 0.5) / n;
      const Vec3 d = normalize(c * float(std::cos(r)) + (u * float(std::cos(phi)) + v * float(std::sin(phi))) * float(std::sin(r)));
      direct += (sky.radiance(d).y - no_disc.radiance(d).y) * std::sin(r) * (half / n) * (2 * kPi / n);
    }
  EXPECT_GT(direct, 0);
  EXPECT_NEAR(baked / direct, 1.0, 0.01) << baked << " vs " << direct;
}

TEST(NishitaSky, BadSettingsAreNamed) {
  EXPECT_NO_THROW(parse(R"({"type":"nishita","sun_elevation":0.5,"sun_disc":false,"altitude":1e5})"));
  for (const char *json : {R"({"type":"hosek_wilkie"})", R"({"sun_elevation":2})", R"({"air_density":-1})",
                           R"({"sun_size":1e9})", R"({"sun_intensity":-0.5})"}) {
    try {
      parse(json);
      ADD_FAILURE() << json << " was accepted";
    } catch (const Error &e) {
      EXPECT_NE(std::string(e.what()).find("world sky"), std::string::npos) << e.what();
    }
  }
}

}  // namespace test_sky_nishita
