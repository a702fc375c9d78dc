// An area lamp's Spread (Cycles 3.4's soft-box slats): the emission's fall-off with the angle
// off the axis, the lamp's power kept whatever the spread, and the same emission in next-event
// estimation, rays that hit the lamp and emission sampling. Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "core/params.h"
#include "lights/light.h"

namespace test_area_spread {

using namespace rdv;
using nlohmann::json;

namespace {

Light area_lamp(double spread_degrees) {
  json j = {{"type", "area"}, {"power", 50}, {"size", 0.5}, {"position", {0, 0, 2}}, {"direction", {0, 0, -1}}};
  if (spread_degrees >= 0) j["spread"] = spread_degrees * kPi / 180.0;
  Params p(j.dump(), "light 'Softbox'");
  return make_light(p).light;
}

// The radiance a direction at angle `a` off the axis carries (in the x-z plane).
float along(const Light &l, float a) { return lamp_radiance(l, l.position, {std::sin(a), 0.0f, -std::cos(a)}, 1.0f).y; }

}  // namespace

TEST(AreaSpread, FallsOffAsTheSlatsHideTheLamp) {
  const Light wide = area_lamp(-1), slats = area_lamp(60);
  const float L0 = wide.radiance.y;
  // 180 degrees (the default): Lambertian, every direction of the front side alike.
  for (float a : {0.0f, 0.5f, 1.2f, 1.5f}) EXPECT_FLOAT_EQ(along(wide, a), L0) << a;
  EXPECT_EQ(along(wide, 2.0f), 0.0f) << "one-sided";
  // 60 degrees: tan_spread = tan(60 degrees), nothing beyond 30 degrees off the axis.
  const float t = std::tan(kPi / 3.0f), norm = 2.0f / (2.0f + (2.0f * kPi / 3.0f - kPi) * t);
  for (float deg : {0.0f, 10.0f, 20.0f, 29.0f, 31.0f, 60.0f}) {
    const float a = deg * kPi / 180.0f;
    EXPECT_NEAR(along(slats, a), L0 * std::max(0.0f, (1.0f - t * std::tan(a)) * norm), 1e-5f * L0) << deg;
  }
  EXPECT_GT(along(slats, 0.0f), 2.0f * L0) << "brighter along the axis, as the power is kept";
}

TEST(AreaSpread, KeepsTheLampsPower) {
  // The radiant exitance: the integral of L cos over the hemisphere, at every spread down to
  // Cycles' smallest, 1 degree (narrower is clamped to it).
  for (double spread : {180.0, 120.0, 60.0, 15.0, 1.0, 0.0}) {
    const Light l = area_lamp(spread);
    double exitance = 0;
    constexpr int n = 400000;  // midpoints in cos^2, where L cos dw = L d(cos^2) pi
    for (int i = 0; i < n; ++i) {
      const double c = std::sqrt((i + 0.5) / n);
      exitance += along(l, float(std::acos(c)));
    }
    exitance *= kPi / n;
    EXPECT_NEAR(exitance / (kPi * area_lamp(-1).radiance.y), 1.0, spread >= 15 ? 1e-3 : 2e-2) << spread;
  }
}

TEST(AreaSpread, EveryRoutineSeesTheSameEmission) {
  const Light l = area_lamp(45);
  const Vec3 ref(0.3f, 0.2f, 0.5f);
  for (float u : {0.2f, 0.5f, 0.8f}) {
    LightSample s;
    if (!sample_light(l, ref, {u, 1.0f - u}, Vec3(0.5f), s)) continue;
    EXPECT_FLOAT_EQ(s.L.y, lamp_radiance(l, s.p, -s.wi, s.dist).y);
    // The ray back toward that point hits the lamp with the same radiance.
    float t;
    Color L;
    ASSERT_TRUE(intersect_light(l, Ray{ref, s.wi, kInf}, kInf, t, L));
    EXPECT_NEAR(L.y, s.L.y, 1e-5f * s.L.y + 1e-9f);
  }
  // Emission sampling draws directions within the cone only, cosine-distributed: its density
  // integrates to 1 over the cone, matches emission_pdf, and no sample is wasted outside.
  for (float u : {0.05f, 0.3f, 0.55f, 0.8f, 0.95f})
    for (float v : {0.1f, 0.6f, 0.97f}) {
      EmissionSample e;
      ASSERT_TRUE(sample_emission(l, {0.5f, 0.5f}, {u, v}, Vec3(0.5f), Vec3(0.0f), 10.0f, e)) << u << " " << v;
      EXPECT_FLOAT_EQ(e.Le.y, lamp_radiance(l, e.ray.o, e.ray.d, 1.0f).y);
      float pdf_pos, pdf_dir;
      emission_pdf(l, e.ray.o, e.n, e.ray.d, 10.0f, pdf_pos, pdf_dir);
      EXPECT_NEAR(pdf_dir, e.pdf_dir, 1e-4f * e.pdf_dir);
    }
  const float sin_max = std::sin(0.5f * 45.0f * kPi / 180.0f);
  double total = 0;
  constexpr int n = 2000;
  for (int i = 0; i < n; ++i) {  // over the cap in cos, times 2 pi
    const float c = 1.0f - (1.0f - std::sqrt(1.0f - sin_max * sin_max)) * (i + 0.5f) / n;
    float pdf_pos, pdf_dir;
    emission_pdf(l, l.position, l.axis, Vec3(std::sqrt(1 - c * c), 0, -c), 10.0f, pdf_pos, pdf_dir);
    total += pdf_dir * 2 * kPi * (1.0f - std::sqrt(1.0f - sin_max * sin_max)) / n;
  }
  EXPECT_NEAR(total, 1.0, 1e-3);
}

}  // namespace test_area_spread
