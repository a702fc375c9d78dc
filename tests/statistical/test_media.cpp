// Participating media: phase-function sampling (chi-square), distance sampling and
// transmittance against Beer-Lambert.
#include <gtest/gtest.h>
#include "chi_square.h"
#include "core/hash.h"
#include "media/medium.h"

namespace test_media {

using namespace rdv;

// False-alarm rate 1% over the set of g values (Sidak).
TEST(PhaseFunction, ChiSquareHenyeyGreenstein) {
  const std::vector<float> gs = {-0.99f, -0.5f, 0.0f, 0.3f, 0.9f, 0.99f};
  const double alpha = test::sidak(0.01, int(gs.size()));
  const Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f));
  uint64_t seed = 300;
  for (float g : gs) {
    HenyeyGreenstein hg{g};
    auto r = test::chi_square_directions([&](Vec2 u, Vec3 &wi) { wi = hg.sample(wo, u); return true; },
                                         [&](Vec3 wi) { return hg.pdf(wo, wi); }, 300000, seed++, 32, 32);
    EXPECT_FALSE(r.impossible_sample) << "g=" << g << " " << r.detail;
    EXPECT_GT(r.p_value, alpha) << "g=" << g << " " << r.detail;
  }
}

TEST(PhaseFunction, IntegratesToOne) {
  Pcg32 rng(5);
  for (float g : {-0.9f, 0.0f, 0.7f}) {
    HenyeyGreenstein hg{g};
    double sum = 0;
    const int n = 400000;
    for (int i = 0; i < n; ++i) {  // uniform sphere estimator of the integral
      float z = 1 - 2 * rng.next_float(), r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * rng.next_float();
      sum += hg.eval(Vec3(0, 0, 1), Vec3(r * std::cos(phi), r * std::sin(phi), z)) * 4 * kPi;
    }
    EXPECT_NEAR(sum / n, 1.0, 0.02) << "g=" << g;
  }
}

static Medium chromatic_medium() {
  Params p(R"({"sigma_a":[0.2,0.5,1.5],"sigma_s":[0.8,0.3,0.1],"anisotropy":0.4})", "test medium");
  Medium m = Medium::from_params(p, "test");
  p.check_all_used();
  return m;
}

// Mean and standard error of the estimator weight over a slab of thickness d, counting
// either the samples that scattered or those that passed.
struct WeightEstimate { double mean[3], se[3]; };
static WeightEstimate mean_weight(const Medium &m, float d, uint64_t seed, bool scattered) {
  SampleRun rng{Pcg32(seed)};
  const int n = 400000;
  Color sum(0.0f), sum2(0.0f);
  for (int i = 0; i < n; ++i) {
    MediumSample s = m.sample_distance(Vec3(0.0f), Vec3(0, 0, 1), d, rng);
    Color v = s.scattered == scattered ? s.weight : Color(0.0f);
    sum += v;
    sum2 += v * v;
  }
  WeightEstimate e;
  for (int c = 0; c < 3; ++c) {
    e.mean[c] = sum[c] / n;
    e.se[c] = std::sqrt(std::max(0.0, sum2[c] / n - e.mean[c] * e.mean[c]) / n);
  }
  return e;
}

// The probability of passing a slab unscattered, weighted as the estimator weights it,
// reproduces exp(-sigma_t d) in every channel (chromatic one-sample MIS is unbiased).
TEST(DistanceSampling, ChromaticTransmittanceIsUnbiased) {
  Medium m = chromatic_medium();
  const float d = 1.3f;
  auto est = mean_weight(m, d, 9, false);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(est.mean[c], std::exp(-m.sigma_t[c] * d), 4.5 * est.se[c] + 1e-6) << "channel " << c;
}

// Collisions: E[weight at a scattering event] = integral of sigma_s Tr = sigma_s/sigma_t (1 - Tr(d)).
TEST(DistanceSampling, ScatteringWeightIsUnbiased) {
  Medium m = chromatic_medium();
  const float d = 0.7f;
  auto est = mean_weight(m, d, 10, true);
  for (int c = 0; c < 3; ++c) {
    double expected = m.sigma_s[c] / m.sigma_t[c] * (1 - std::exp(-m.sigma_t[c] * d));
    EXPECT_NEAR(est.mean[c], expected, 4.5 * est.se[c] + 1e-6) << "channel " << c;
  }
}

TEST(Medium, CyclesParametersAndBadInput) {
  Params p(R"({"density":2,"color":[0.5,0.5,0.5],"absorption_color":[0,0,0]})", "volume");
  Medium m = Medium::from_params(p, "v");
  EXPECT_NEAR(m.sigma_s.x, 1.0f, 1e-6f);
  EXPECT_NEAR(m.sigma_a.x, 1.0f, 1e-6f);  // (1 - absorption colour) (1 - colour) density
  Params bad(R"({"density":-1})", "volume 'Smoke'");
  EXPECT_THROW(Medium::from_params(bad, "Smoke"), Error);
}

}  // namespace test_media
