// IES LM-63 profiles (lights/ies_profile.h) as Cycles 3.4 reads them: the table's values at its
// own angles, the mirrored quadrants and halves, the orientation of a direction, the unit, and
// malformed files refused with a reason; and lamps whose node tree holds one (lights/
// lamp_emission.h): their emission by direction in every sampling routine. Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include "core/error.h"
#include "lights/ies_profile.h"
#include "lights/lamp_emission.h"
#include "lights/light.h"

namespace test_ies_profile {

using namespace rdv;
using nlohmann::json;

namespace {

constexpr float kUnit = 0.0706650768394f;  // candela to the lamp's units (4 pi / 177.83)

std::string join(const std::vector<float> &v) {
  std::ostringstream s;
  for (float x : v) s << x << ' ';
  return s.str();
}

// A type C (1) or B (2) file: intensity(v, h) in candela at each pair of angles (degrees).
std::string ies_file(int type, const std::vector<float> &v, const std::vector<float> &h,
                     const std::function<float(float, float)> &intensity, float multiplier = 1,
                     const std::string &tilt = "TILT=NONE") {
  std::ostringstream s;
  s << "IESNA:LM-63-2002\n[TEST] a profile of the unit tests\n" << tilt << "\n";
  s << "1 -1 " << multiplier << ' ' << v.size() << ' ' << h.size() << ' ' << type << " 2 0 0 0\n1.0 1.0 100\n";
  s << join(v) << "\n" << join(h) << "\n";
  for (float hh : h) {
    for (float vv : v) s << intensity(vv, hh) << ' ';
    s << "\n";
  }
  return s.str();
}

float deg(float d) { return d * kPi / 180.0f; }

// The unit direction at vertical angle v from straight down and horizontal angle h, in
// Cycles' convention h = atan2(x, y) + pi.
Vec3 direction(float v_deg, float h_deg) {
  const float v = deg(v_deg), h = deg(h_deg) - kPi;
  return {std::sin(v) * std::sin(h), std::sin(v) * std::cos(h), -std::cos(v)};
}

IesProfile parsed(const std::string &text) {
  IesProfile p;
  std::string error;
  EXPECT_TRUE(p.parse(text, error)) << error;
  return p;
}

}  // namespace

TEST(IesProfile, ValuesAtItsOwnAnglesInTheLampsUnit) {
  // Four quadrants' worth given in full: the table comes back at each of its angles.
  const std::vector<float> v = {0, 20, 40, 60, 80, 100, 120, 140, 160, 180}, h = {0, 60, 120, 180, 240, 300, 360};
  auto I = [](float vv, float hh) { return 100.0f + 10.0f * vv + 3.0f * hh; };
  const IesProfile p = parsed(ies_file(1, v, h, I, 2.0f));
  for (float vv : {0.0f, 40.0f, 100.0f, 160.0f})
    for (float hh : {60.0f, 120.0f, 300.0f}) {
      EXPECT_NEAR(p.eval_angles(deg(vv), deg(hh)), 2.0f * kUnit * I(vv, hh), 1e-3f) << vv << " " << hh;
      if (vv > 0)  // straight down has no horizontal angle of its own (atan2(0, 0): 180)
        EXPECT_NEAR(p.eval(direction(vv, hh)), 2.0f * kUnit * I(vv, hh), 1e-4f * I(vv, hh)) << vv << " " << hh;
    }
  EXPECT_EQ(p.eval_angles(deg(180.0f), 0.0f), 0.0f) << "nothing at or beyond the last vertical angle";
}

TEST(IesProfile, CatmullRomBetweenAngles) {
  // Linear data is reproduced exactly by Catmull-Rom away from the ends.
  const std::vector<float> v = {0, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  const IesProfile p = parsed(ies_file(1, v, {0}, [](float vv, float) { return 500.0f - 4.0f * vv; }));
  for (float vv : {25.0f, 33.0f, 47.5f, 61.0f})
    EXPECT_NEAR(p.eval_angles(deg(vv), deg(123.0f)), kUnit * (500.0f - 4.0f * vv), 1e-3f) << vv;
  // A step: the cubic overshoots below 0 on its low side, which is clamped.
  const IesProfile step = parsed(ies_file(1, v, {0}, [](float vv, float) { return vv < 45 ? 1000.0f : 0.0f; }));
  EXPECT_EQ(step.eval_angles(deg(58.0f), 0.0f), 0.0f);
  EXPECT_GT(step.eval_angles(deg(32.0f), 0.0f), kUnit * 1000.0f) << "overshoots above";
}

TEST(IesProfile, SymmetricFilesAreMirroredAroundTheCircle) {
  const std::vector<float> v = {0, 30, 60, 90};
  auto I = [](float vv, float hh) { return 200.0f + vv + 5.0f * hh; };
  // One quadrant (0..90): h, 180 - h, 180 + h and 360 - h see the same.
  const IesProfile quadrant = parsed(ies_file(1, v, {0, 30, 60, 90}, I));
  EXPECT_EQ(quadrant.num_horizontal(), 13u);
  for (float hh : {30.0f, 60.0f})
    for (float mirrored : {180.0f - hh, 180.0f + hh, 360.0f - hh})
      EXPECT_NEAR(quadrant.eval_angles(deg(30), deg(mirrored)), kUnit * I(30, hh), 1e-3f) << hh << " " << mirrored;
  // Half (0..180): h and 360 - h.
  const IesProfile half = parsed(ies_file(1, v, {0, 45, 90, 135, 180}, I));
  EXPECT_NEAR(half.eval_angles(deg(60), deg(315)), kUnit * I(60, 45), 1e-3f);
  // 90..270 is shifted to 0..180; a full circle without its 360 entry gets it.
  const IesProfile shifted = parsed(ies_file(1, v, {90, 135, 180, 225, 270}, I));
  EXPECT_NEAR(shifted.eval_angles(deg(60), deg(45)), kUnit * I(60, 135), 1e-3f);
  const IesProfile no_360 = parsed(ies_file(1, v, {0, 90, 180, 270}, I));
  EXPECT_NEAR(no_360.eval_angles(deg(30), deg(270)), kUnit * I(30, 270), 1e-3f);
  EXPECT_NEAR(no_360.eval_angles(deg(30), deg(360)), kUnit * I(30, 0), 1e-3f);
  // Rotationally symmetric (one horizontal angle): the same all round.
  const IesProfile round = parsed(ies_file(1, v, {0}, I));
  EXPECT_NEAR(round.eval_angles(deg(60), deg(200)), kUnit * I(60, 0), 1e-3f);
}

TEST(IesProfile, UpwardOnlyFilesEmitUpward) {
  // Vertical angles 90..180: nothing below the horizon, the table above it (Cycles 3.4
  // renders such a file black; see ies_profile.h).
  const IesProfile up = parsed(ies_file(1, {90, 120, 150, 180}, {0}, [](float vv, float) { return vv; }));
  EXPECT_EQ(up.eval(direction(45, 0)), 0.0f);
  EXPECT_NEAR(up.eval_angles(deg(150), 0), kUnit * 150.0f, 1e-3f);
}

TEST(IesProfile, TypeBIsTurnedIntoTypeC) {
  // Type B: the file's "vertical" angles are about the horizontal axis. One side (0..90) of
  // each is mirrored; each mirrored angle keeps its own intensity.
  auto I = [](float vv, float hh) { return 100.0f + vv + 2.0f * hh; };
  const IesProfile b = parsed(ies_file(2, {0, 30, 60, 90}, {0, 45, 90}, I));
  // Type C's vertical = the file's horizontal + 90 (mirrored), type C's horizontal = the
  // file's vertical + 90 (mirrored).
  EXPECT_NEAR(b.eval_angles(deg(90 + 45), deg(90 + 30)), kUnit * I(30, 45), 1e-3f);
  EXPECT_NEAR(b.eval_angles(deg(90 - 45), deg(90 - 30)), kUnit * I(30, 45), 1e-3f);
  EXPECT_NEAR(b.eval_angles(deg(90 - 45), deg(90 + 60)), kUnit * I(60, 45), 1e-3f);
}

TEST(IesProfile, TiltIncludeAndCommasAreRead) {
  std::string text = ies_file(1, {0, 45, 90}, {0}, [](float, float) { return 300.0f; }, 1.0f,
                              "TILT=INCLUDE\n1\n3\n0 45 90\n1.0 0.9 0.8");
  for (char &c : text)
    if (c == ' ') c = ',';
  EXPECT_NEAR(parsed(text).eval_angles(deg(20), 0), kUnit * 300.0f, 1e-3f);
}

TEST(IesProfile, MalformedFilesAreRefusedWithAReason) {
  const std::string good = ies_file(1, {0, 45, 90}, {0, 90}, [](float, float) { return 1.0f; });
  auto with = [&](const std::string &from, const std::string &to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"", "no TILT"},
      {"IESNA:LM-63\nnot a profile\n", "no TILT"},
      {good.substr(0, good.size() - 7), "ends before"},  // the last column of intensities
      {with("1 -1 1 3 2 1 2", "1 -1 1 3 2 3 2"), "photometric type 3"},
      {with("1 -1 1 3 2 1 2", "1 -1 1 300000 2 1 2"), "300000 vertical"},
      {with("1 -1 1 3 2 1 2", "1 -1 1 -3 2 1 2"), "-3 vertical"},
      {with("0 45 90 \n", "0 45 nan \n"), "not a finite"},
      {with("0 45 90 \n", "0 90 45 \n"), "do not increase"},
      {with("0 90 \n", "10 90 \n"), "horizontal angles do not start"},
      {with("0 45 90 \n", "10 45 90 \n"), "vertical angles run neither"},
  };
  for (const auto &[text, reason] : bad) {
    IesProfile p;
    std::string error;
    EXPECT_FALSE(p.parse(text, error)) << reason;
    EXPECT_NE(error.find(reason), std::string::npos) << "'" << error << "' for " << reason;
  }
  IesProfile p;
  std::string error;
  EXPECT_FALSE(p.load("/nonexistent/lamp.ies", error));
  EXPECT_NE(error.find("no such file"), std::string::npos) << error;
}

namespace {

// A downlight-like profile: strongest 30 degrees off the axis, brighter toward h = 90.
const std::string kProfile = ies_file(1, {0, 15, 30, 45, 60, 75, 90}, {0, 90, 180, 270, 360}, [](float v, float h) {
  return (1000.0f - 9.0f * std::fabs(v - 30.0f)) * (1.0f + 0.5f * std::sin(deg(h)));
});

UserLight lamp(json j) {
  Params p(j.dump(), "light 'Downlight'");
  return make_light(p);
}

json ies_lamp(const std::string &type, float strength) {
  return {{"type", type}, {"power", 100}, {"radius", 0}, {"color", {1.0, 0.8, 0.6}},
          {"transform", {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1}},  // turned 90 degrees about z, at (1, 2, 3)
          {"emission", {{"strength", {{"node", "ies"}, {"profile", kProfile}, {"strength", strength}}}}}};
}

}  // namespace

TEST(LampEmission, AnIesProfileShapesAPointLampInEveryRoutine) {
  const UserLight ies = lamp(ies_lamp("point", 2.0f));
  json plain_json = ies_lamp("point", 1.0f);
  plain_json.erase("emission");
  const UserLight plain = lamp(plain_json);
  IesProfile profile;
  std::string error;
  ASSERT_TRUE(profile.parse(kProfile, error));
  ASSERT_NE(ies.light.emission, nullptr);
  const Vec3 at(1, 2, 3);
  for (const Vec3 ref : {Vec3(1.5f, 2.0f, 0.0f), Vec3(0.0f, 3.0f, 1.0f), Vec3(1.0f, 1.0f, 2.5f)}) {
    const Vec3 out = normalize(ref - at);
    // The lamp's space: world (x, y) = lamp (-y, x), so a lamp-space direction is (y, -x, z).
    const float expected_factor = 2.0f * profile.eval(Vec3(out.y, -out.x, out.z));
    LightSample s;
    ASSERT_TRUE(sample_light(ies.light, ref, {0.5f, 0.5f}, Vec3(0.5f), s) || expected_factor == 0);
    const Color expected = plain.light.radiance * expected_factor / length_squared(ref - at);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.L[c], expected[c], 1e-4f * expected[c] + 1e-9f);
    EXPECT_NEAR(lamp_radiance(ies.light, ies.light.position, out, 1.0f).y, plain.light.radiance.y * expected_factor, 1e-4f * expected.y + 1e-9f);
  }
  // Emission sampling: each sampled direction carries the profile along it.
  for (float u : {0.1f, 0.35f, 0.6f, 0.85f}) {
    EmissionSample e;
    if (!sample_emission(ies.light, {0.5f, 0.5f}, {u, 1.0f - u}, Vec3(0.5f), Vec3(0.0f), 10.0f, e)) continue;
    const Vec3 d = e.ray.d;
    EXPECT_NEAR(e.Le.y, plain.light.radiance.y * 2.0f * profile.eval(Vec3(d.y, -d.x, d.z)), 1e-4f * e.Le.y + 1e-9f);
  }
  // Light selection by power sees the profile's mean.
  Light with = ies.light, without = plain.light;
  compute_light_power(with, 10.0f);
  compute_light_power(without, 10.0f);
  EXPECT_NEAR(with.power / without.power, ies.light.emission->mean_luminance(), 1e-3f * with.power / without.power);
  EXPECT_GT(ies.light.emission->mean_luminance(), 0.0f);
}

TEST(LampEmission, SphereLampsAndSpotsToo) {
  json sphere = ies_lamp("point", 1.0f);
  sphere["radius"] = 0.1;
  const UserLight s = lamp(sphere);
  IesProfile profile;
  std::string error;
  ASSERT_TRUE(profile.parse(kProfile, error));
  // A ray meeting the sphere sees the profile along the direction back toward its origin.
  const Vec3 origin(1.6f, 2.1f, 0.0f), target(1, 2, 3);
  const Ray ray{origin, normalize(target - origin), kInf};
  float t;
  Color L;
  ASSERT_TRUE(intersect_light(s.light, ray, kInf, t, L));
  const Vec3 back = -ray.d;
  const float factor = profile.eval(Vec3(back.y, -back.x, back.z));
  EXPECT_NEAR(L.y / s.light.radiance.y, factor, 1e-4f * factor);
  json spot = ies_lamp("spot", 1.0f);
  spot["spot_size"] = 1.2;
  const UserLight sp = lamp(spot);
  const Vec3 down(0.2f, 0.1f, -1.0f);
  const Vec3 d = normalize(down);
  EXPECT_NEAR(lamp_radiance(sp.light, sp.light.position, d, 1.0f).y, sp.light.radiance.y * spot_attenuation(sp.light, d) * profile.eval(Vec3(d.y, -d.x, d.z)),
              1e-3f);
}

TEST(LampEmission, AreaLampsTakeTheProfileAlongTheirAxisAndBadFilesAreNamed) {
  // An area lamp's shader sees its normal: the profile straight down, folded into its colour.
  json area = ies_lamp("area", 1.0f);
  area.erase("radius");
  const UserLight a = lamp(area);
  EXPECT_EQ(a.light.emission, nullptr);
  area.erase("emission");
  IesProfile profile;
  std::string error;
  ASSERT_TRUE(profile.parse(kProfile, error));
  EXPECT_NEAR(a.light.radiance.y / lamp(area).light.radiance.y, profile.eval(Vec3(0, 0, -1)), 1e-4f);
  // A file that cannot be read: Cycles' 100, a warning naming the light and the file.
  json missing = ies_lamp("point", 0.5f);
  missing["emission"]["strength"] = {{"node", "ies"}, {"file", "/nonexistent/wash.ies"}, {"strength", 0.5}};
  const UserLight m = lamp(missing);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("light 'Downlight'"), std::string::npos) << m.warnings[0];
  EXPECT_NE(m.warnings[0].find("/nonexistent/wash.ies"), std::string::npos) << m.warnings[0];
  json plain = ies_lamp("point", 1.0f);
  plain.erase("emission");
  EXPECT_NEAR(m.light.radiance.y / lamp(plain).light.radiance.y, 50.0f, 1e-3f) << "constant: folded in";
  EXPECT_EQ(m.light.emission, nullptr);
}

// The extremes: the same turned lamp 1 km from the origin, lighting points 1 mm and 1 km away;
// an area lamp of 1 mm with a 30-degree spread 1 km from the origin. Each emission as close
// to the profile's (the spread's) as the directions' float rounding allows.
TEST(LampEmission, FarFromTheOriginAtMillimetresAndKilometres) {
  IesProfile profile;
  std::string error;
  ASSERT_TRUE(profile.parse(kProfile, error));
  json far = ies_lamp("point", 1.0f);
  far["transform"] = {0, -1, 0, 1000, 1, 0, 0, 1000, 0, 0, 1, 1000, 0, 0, 0, 1};
  const UserLight l = lamp(far);
  json plain_json = far;
  plain_json.erase("emission");
  const Color plain = lamp(plain_json).light.radiance;
  const Vec3 at(1000, 1000, 1000);
  for (const float d : {1e-3f, 1e3f}) {
    for (const Vec3 dir : {Vec3(0.3f, -0.2f, -0.93f), Vec3(-0.7f, 0.1f, -0.7f)}) {
      const Vec3 out = normalize(dir), ref = at + out * d;
      LightSample s;
      ASSERT_TRUE(sample_light(l.light, ref, {0.5f, 0.5f}, Vec3(0.5f), s)) << d;
      const Vec3 w = -s.wi;  // the direction the engine found, from rounded positions
      const float expected = plain.y * profile.eval(Vec3(w.y, -w.x, w.z)) / (s.dist * s.dist);
      EXPECT_NEAR(s.L.y, expected, 1e-4f * expected) << d;
      EXPECT_NEAR(length(w - out), 0.0f, d < 1 ? 0.2f : 1e-4f) << "1 mm at 1 km: float positions 6e-5 m apart";
    }
  }
  const json area = {{"type", "area"}, {"power", 1}, {"size", 1e-3}, {"spread", 30 * kPi / 180},
                     {"transform", {1, 0, 0, 1000, 0, 1, 0, -1000, 0, 0, 1, 1000, 0, 0, 0, 1}}};
  const UserLight a = lamp(area);
  const float t = 1.0f / std::tan(15.0f * kPi / 180.0f), norm = 2.0f / (2.0f - (30.0f * kPi / 180.0f) * t);
  for (const float d : {2e-3f, 2e3f}) {
    LightSample s;
    const Vec3 ref = Vec3(1000, -1000, 1000) + normalize(Vec3(0.1f, 0.05f, -1.0f)) * d;
    ASSERT_TRUE(sample_light(a.light, ref, {0.5f, 0.5f}, Vec3(0.5f), s)) << d;
    const float c = dot(a.light.axis, -s.wi), tan_off = std::sqrt(1 - c * c) / c;
    EXPECT_NEAR(s.L.y, a.light.radiance.y * std::max(0.0f, (1 - t * tan_off) * norm), 1e-4f * s.L.y + 1e-6f) << d;
    EXPECT_GT(s.L.y, 0.0f) << d << ": 6 degrees off the axis is inside the 15-degree cone";
  }
}

}  // namespace test_ies_profile
