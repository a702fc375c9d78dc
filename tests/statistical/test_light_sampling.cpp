// Light sampling against the light's own solid-angle pdf (chi-square), and the
// irradiance each light type delivers against the closed form in Blender's units.
#include <gtest/gtest.h>
#include "chi_square.h"
#include "core/hash.h"
#include "film/pixel_filter.h"
#include "lights/light.h"

namespace test_light_sampling {

using namespace rdv;

namespace {

Light light_from(const std::string &json) {
  Params p(json, "test light");
  return make_light(p).light;
}

// Distance along wi to the light, or -1 if wi misses it (triangles: Moller-Trumbore).
float distance_to(const Light &l, Vec3 ref, Vec3 wi) {
  Ray r{ref, wi, kInf};
  float t;
  Color L;
  if (l.type == LightType::Triangle) {
    Vec3 e1 = l.edge_u, e2 = l.edge_v, p = cross(wi, e2);
    float det = dot(e1, p);
    if (std::fabs(det) < 1e-12f) return -1;
    Vec3 s = ref - l.p0;
    float u = dot(s, p) / det;
    Vec3 q = cross(s, e1);
    float v = dot(wi, q) / det;
    t = dot(e2, q) / det;
    return (u >= 0 && v >= 0 && u + v <= 1 && t > 0) ? t : -1;
  }
  if (l.is_infinite()) return kInf;
  return intersect_light(l, r, kInf, t, L) ? t : -1;
}

struct Case {
  std::string name;
  Light light;
};

std::vector<Case> sampled_lights() {
  return {
      {"point_r0.5", light_from(R"({"type":"point","position":[0,0,2],"radius":0.5,"power":100})")},
      {"spot_r0.3", light_from(R"({"type":"spot","position":[0.5,0,1.5],"direction":[0,0,-1],"radius":0.3,"power":100,"spot_size":2.0})")},
      {"area_rect", light_from(R"({"type":"area","position":[0,0.5,1],"direction":[0,-0.3,-1],"shape":"rectangle","size":1.5,"size_y":0.5,"power":100})")},
      // Rectangles by solid angle: one wide and close, one whose 40-degree spread lets only a
      // corner of it light the point (lights/rectangle_lamp.h).
      {"area_rect_close", light_from(R"({"type":"area","position":[0.3,0,0.25],"direction":[0.2,0,-1],"shape":"rectangle","size":2,"size_y":1.2,"power":100})")},
      {"area_rect_spread", light_from(R"({"type":"area","position":[1.2,0.6,0.8],"direction":[0,0,-1],"shape":"rectangle","size":2,"size_y":1.5,"spread":0.7,"power":100})")},
      {"area_disk", light_from(R"({"type":"area","position":[0,0,0.6],"direction":[0,0,-1],"shape":"disk","size":2,"power":100})")},
      {"sun_10deg", light_from(R"({"type":"sun","direction":[0.2,0.1,-1],"angle":0.1745,"strength":3})")},
      {"triangle", make_triangle_light(Vec3(-1, -1, 1), Vec3(1, -0.5f, 1.2f), Vec3(0, 1, 0.8f), Color(2.0f))},
      {"background", make_background_light(Color(1.0f))},
  };
}

}  // namespace

// False-alarm rate 1% over the set (Sidak).
TEST(LightSampling, ChiSquareEveryLightType) {
  auto lights = sampled_lights();
  const double alpha = test::sidak(0.01, int(lights.size()));
  const Vec3 ref(0.1f, -0.2f, 0.0f);
  uint64_t seed = 100;
  for (const auto &c : lights) {
    SCOPED_TRACE(c.name);
    auto result = test::chi_square_directions(
        [&](Vec2 u, Vec3 &wi) {
          LightSample s;
          if (!sample_light(c.light, ref, u, Vec3(0.0f), s)) return false;
          wi = s.wi;
          return true;
        },
        [&](Vec3 wi) {
          float t = distance_to(c.light, ref, wi);
          return t < 0 ? 0.0f : light_pdf(c.light, ref, wi, t);
        },
        200000, seed++, 24, 48);
    EXPECT_FALSE(result.impossible_sample) << result.detail;
    EXPECT_GT(result.p_value, alpha) << result.detail;
  }
}

// Irradiance at the origin on a surface facing +Z: Monte Carlo over sample_light
// against the closed form. Tolerance: 4 standard errors plus 0.2% (float rounding).
static void expect_irradiance(const Light &l, double expected, const std::string &name) {
  Pcg32 rng(3);
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    LightSample s;
    double v = 0;
    float a = rng.next_float();
    if (sample_light(l, Vec3(0.0f), {a, rng.next_float()}, Vec3(0.0f), s) && s.pdf > 0 && s.wi.z > 0)
      v = average(s.L) * s.wi.z / s.pdf;
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, expected, 4 * se + 2e-3 * expected) << name;
}

TEST(LightUnits, IrradianceMatchesClosedForms) {
  const double pi = M_PI, d = 2.0;
  // Point, no radius: E = P / (4 pi d^2).
  expect_irradiance(light_from(R"({"type":"point","position":[0,0,2],"radius":0,"power":100})"),
                    100 / (4 * pi * d * d), "point");
  // Point with radius r: a sphere of radiance P / (4 pi * pi r^2) seen whole from a surface
  // facing it: E = L pi sin^2 = P / (4 pi d^2), as without a radius (lights/sphere_lamp.h).
  expect_irradiance(light_from(R"({"type":"point","position":[0,0,2],"radius":0.5,"power":100})"),
                    100 / (4 * pi * d * d), "point_radius");
  // Spot on its axis: cos(0) * smoothstep(..) = 1: same as a point.
  expect_irradiance(light_from(R"({"type":"spot","position":[0,0,2],"direction":[0,0,-1],"radius":0,"power":100})"),
                    100 / (4 * pi * d * d), "spot");
  // Sun without angle: E = strength; with a disk of radius r = tan(angle/2):
  // E = strength * 2 (sqrt(1 + r^2) - 1) / r^2 (the disk's cosines).
  expect_irradiance(light_from(R"({"type":"sun","direction":[0,0,-1],"angle":0,"strength":3})"), 3.0, "sun");
  double r = std::tan(0.2 / 2);
  expect_irradiance(light_from(R"({"type":"sun","direction":[0,0,-1],"angle":0.2,"strength":3})"),
                    3.0 * 2 * (std::sqrt(1 + r * r) - 1) / (r * r), "sun_angle");
  // Area square of side s at height d, radiance P / (4 A): E = pi L F, with the
  // rectangle form factor over four quarters.
  {
    double s = 1.0, a = s / 2, L = 100 / (4 * s * s);
    double F = (a / std::sqrt(a * a + d * d)) * std::atan(a / std::sqrt(a * a + d * d)) * 2 / (2 * pi);
    expect_irradiance(light_from(R"({"type":"area","position":[0,0,2],"direction":[0,0,-1],"shape":"square","size":1,"power":100})"),
                      pi * L * 4 * F, "area_square");
  }
  // The same square a quarter of a metre away (sampled by solid angle, 2.2 sr: the estimate is
  // cos alone), and 1 cm wide 30 m away (1.1e-7 sr: by area, its form factor ~ A / (pi d^2)).
  {
    const double s = 1.0, a = s / 2, h = 0.25, L = 100 / (4 * s * s);
    const double F = (a / std::sqrt(a * a + h * h)) * std::atan(a / std::sqrt(a * a + h * h)) * 2 / (2 * pi);
    expect_irradiance(light_from(R"({"type":"area","position":[0,0,0.25],"direction":[0,0,-1],"shape":"square","size":1,"power":100})"),
                      pi * L * 4 * F, "area_square_close");
    const double w = 0.01, far = 30.0, L_far = 100 / (4 * w * w), b = w / 2;
    const double F_far = (b / std::sqrt(b * b + far * far)) * std::atan(b / std::sqrt(b * b + far * far)) * 2 / (2 * pi);
    expect_irradiance(light_from(R"({"type":"area","position":[0,0,30],"direction":[0,0,-1],"shape":"square","size":0.01,"power":100})"),
                      pi * L_far * 4 * F_far, "area_square_far");
  }
  // Area disk of radius R: E = pi L R^2 / (R^2 + d^2), L = P / (4 A).
  {
    double R = 0.75, L = 100 / (4 * pi * R * R);
    expect_irradiance(light_from(R"({"type":"area","position":[0,0,2],"direction":[0,0,-1],"shape":"disk","size":1.5,"power":100})"),
                      pi * L * R * R / (R * R + d * d), "area_disk");
  }
  // Emissive triangle (half of a square), radiance 1 at height d: half the square's E.
  {
    double a = 0.5, F = (a / std::sqrt(a * a + d * d)) * std::atan(a / std::sqrt(a * a + d * d)) * 2 / (2 * pi);
    Light tri = make_triangle_light(Vec3(-0.5f, -0.5f, 2), Vec3(0.5f, -0.5f, 2), Vec3(0.5f, 0.5f, 2), Color(1.0f));
    expect_irradiance(tri, pi * 1.0 * 4 * F / 2, "triangle");
  }
  // Uniform background of radiance L: E = pi L.
  expect_irradiance(make_background_light(Color(0.5f)), pi * 0.5, "background");
}

TEST(PixelFilter, ChiSquareBlackmanHarris) {
  PixelFilter filter(1.5f);
  double integral = 0;
  const int n = 100000;
  // Cycles 3.4 doubles a Blackman-Harris filter's width: 1.5 px reaches +-1.5 px.
  for (int i = 0; i < n; ++i) integral += filter.evaluate(-1.5f + 3.0f * (i + 0.5f) / n) * 3.0 / n;
  auto result = test::chi_square_1d([&](float u) { return filter.sample(u); },
                                    [&](double x) { return filter.evaluate(float(x)) / integral; }, -1.5, 1.5,
                                    500000, 21, 50);
  EXPECT_GT(result.p_value, 0.01) << result.detail;
  EXPECT_NEAR(filter.evaluate(0), 1.0f, 1e-5f) << "Blackman-Harris peaks at 1";
  EXPECT_NEAR(filter.evaluate(1.5f), 0.0f, 1e-4f);
  EXPECT_GT(filter.evaluate(0.75f), 0.2f) << "the 3.4 filter is twice Blender's width wide";
}

// sample() inverts the CDF of the density pdf() reports: the integral of pdf() from -radius to
// sample(u) is u, on a dense grid of u and at the edges of sample()'s guide cells (k / 1024,
// and the float just below) where a search that starts in the wrong cell would show.
// Deterministic.
TEST(PixelFilter, SampleInvertsTheCdfOfItsPdf) {
  for (float width : {1.5f, 0.3f, 10.0f}) {
    PixelFilter filter(width);
    const int bins = 1024;  // pdf() is constant over each of the table's bins
    const double bin = 2.0 * width / bins;
    std::vector<double> below(bins + 1, 0.0);  // the CDF at each bin's left edge
    for (int j = 0; j < bins; ++j) below[j + 1] = below[j] + filter.pdf(float(-width + (j + 0.5) * bin)) * bin;
    ASSERT_NEAR(below[bins], 1.0, 1e-4) << "width " << width;
    auto cdf = [&](double x) {
      int j = std::clamp(int((x + width) / bin), 0, bins - 1);
      return below[j] + filter.pdf(float(-width + (j + 0.5) * bin)) * (x - (-width + j * bin));
    };
    std::vector<float> us;
    for (int k = 0; k < 65536; ++k) us.push_back((k + 0.37f) / 65536);
    for (int g = 1; g < 1024; ++g) {
      us.push_back(g / 1024.0f);
      us.push_back(std::nextafter(g / 1024.0f, 0.0f));
    }
    int wrong = 0;
    double worst = 0;
    for (float u : us) {
      float x = filter.sample(u);
      double error = std::fabs(cdf(x) - u);
      worst = std::max(worst, error);
      wrong += !(x >= -width && x <= width) || error > 2e-5;
    }
    EXPECT_EQ(wrong, 0) << "width " << width << ": worst |CDF(sample(u)) - u| " << worst;
  }
}

// A point feature's energy in the image does not depend on where it falls in a pixel:
// the filter's copies over the pixel lattice sum to nearly 1 (0.967..1.033 per axis for
// Cycles' 3.4 filter; the half-width filter summed to 0.21..1.86, losing most of a
// sub-pixel lamp's reflection).
TEST(PixelFilter, PartitionOfUnity) {
  PixelFilter filter(1.5f);
  double integral = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) integral += filter.evaluate(-1.5f + 3.0f * (i + 0.5f) / n) * 3.0 / n;
  for (int i = 0; i <= 20; ++i) {
    float x = i / 20.0f;
    double sum = 0;
    for (int k = -3; k <= 3; ++k) sum += filter.evaluate(x - k) / integral;
    EXPECT_NEAR(sum, 1.0, 0.035) << "offset " << x;
  }
}

}  // namespace test_light_sampling
