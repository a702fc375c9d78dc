// Environment-map importance sampling: chi-square of the sampled directions against
// the map's own solid-angle pdf (rotated and unrotated maps, with black regions), the
// pdf integrating to one, sample() agreeing with pdf() and eval(), and Blender's
// equirectangular orientation. False-alarm rate: 1% over this file's chi-square tests
// (Sidak-corrected); the other checks are deterministic.
#include <gtest/gtest.h>
#include "chi_square.h"
#include "core/hash.h"
#include "lights/environment.h"
#include "lights/light.h"

namespace test_environment_sampling {

using namespace rdv;

namespace {

// A small HDRI: random radiance with a black band and one bright "sun" pixel.
EnvironmentMap make_map(int w, int h, uint64_t seed, Vec3 rotation) {
  Pcg32 rng(seed);
  std::vector<float> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = y == h / 2 ? 0.0f : rng.next_float() * 2;
      if (x == w / 3 && y == h / 4) v = 60;
      for (int k = 0; k < 3; ++k) rgb[(size_t(y) * w + x) * 3 + k] = v * (0.6f + 0.2f * k);
    }
  return EnvironmentMap(w, h, rgb, rotation, Color(1.0f));
}

}  // namespace

TEST(EnvironmentSampling, ChiSquareAgainstPdf) {
  struct C { int w, h; Vec3 rot; };
  const std::vector<C> cases = {{16, 8, Vec3(0.0f)}, {12, 6, Vec3(0.3f, -0.5f, 1.2f)}};
  const double alpha = test::sidak(0.01, int(cases.size()));
  uint64_t seed = 40;
  for (const C &c : cases) {
    EnvironmentMap env = make_map(c.w, c.h, seed, c.rot);
    auto r = test::chi_square_directions(
        [&](Vec2 u, Vec3 &d) {
          Color L;
          float pdf;
          return env.sample(u, d, L, pdf);
        },
        [&](Vec3 d) { return env.pdf(d); }, 300000, seed++);
    EXPECT_FALSE(r.impossible_sample) << r.detail;
    EXPECT_GT(r.p_value, alpha) << r.detail;
  }
}

TEST(EnvironmentSampling, SampleAgreesWithPdfAndEval) {
  EnvironmentMap env = make_map(16, 8, 3, Vec3(0.2f, 0.1f, -0.7f));
  Light light = make_environment_light(&env);
  Pcg32 rng(4);
  double integral = 0;  // E[L / pdf] / (4 pi) = mean radiance
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    float a = rng.next_float();
    LightSample s;
    if (!sample_light(light, Vec3(0.0f), {a, rng.next_float()}, Vec3(0.0f), s)) continue;
    EXPECT_NEAR(s.pdf, light_pdf(light, Vec3(0.0f), s.wi, kInf), 1e-3f * s.pdf);
    Color L = infinite_light_radiance(light, s.wi);
    EXPECT_NEAR(s.L.y, L.y, 1e-5f * std::max(1.0f, L.y));
    integral += s.L.y / s.pdf;
  }
  // The map's mean (pixel solid angles) against the importance-sampled estimate of the
  // bilinear radiance: equal up to the bilinear vs piecewise-constant difference.
  double mean = integral / n / (4 * M_PI);
  EXPECT_NEAR(mean, env.mean().y, 0.03 * env.mean().y);
}

TEST(EnvironmentSampling, BlenderEquirectangularOrientation) {
  // 4 x 2 map: top row 1, bottom row 0 in red; green = column index.
  std::vector<float> rgb;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) rgb.insert(rgb.end(), {y == 0 ? 1.0f : 0.0f, float(x), 0.0f});
  EnvironmentMap env(4, 2, rgb, Vec3(0.0f), Color(1.0f));
  EXPECT_NEAR(env.eval(Vec3(0, 0, 1)).x, 1.0f, 1e-5f);   // zenith: top row
  EXPECT_NEAR(env.eval(Vec3(0, 0, -1)).x, 0.0f, 1e-5f);  // nadir: bottom row
  // u = 0.5 - atan2(y, x) / 2pi: +X looks at the image centre, +Y at u = 0.25.
  Vec3 px = normalize(Vec3(1, 0, -0.01f)), py = normalize(Vec3(0, 1, -0.01f));
  EXPECT_NEAR(env.eval(px).y, 1.5f, 1e-3f);  // between columns 1 and 2
  EXPECT_NEAR(env.eval(py).y, 0.5f, 1e-3f);  // between columns 0 and 1
  // Mapping (Point) rotates the vector: lookup(R d); R(+90 z) maps -Y to +X.
  EnvironmentMap rot(4, 2, rgb, Vec3(0, 0, kPi / 2), Color(1.0f));
  EXPECT_NEAR(rot.eval(normalize(Vec3(0, -1, -0.01f))).y, 1.5f, 1e-3f);
  // pdf integrates to 1 over the sphere.
  EnvironmentMap m = make_map(8, 4, 9, Vec3(0.4f, 0.2f, 0.1f));
  double sum = 0;
  const int nt = 400, np = 800;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      double z = -1 + 2 * (i + 0.5) / nt, phi = 2 * M_PI * (j + 0.5) / np, s = std::sqrt(1 - z * z);
      sum += m.pdf(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)));
    }
  EXPECT_NEAR(sum * 4 * M_PI / (double(nt) * np), 1.0, 5e-3);
}

}  // namespace test_environment_sampling
