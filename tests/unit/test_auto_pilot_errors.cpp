// Integrator auto's estimate of each pilot's error from the candidates' differences
// (errors_against_each_other, integrators/auto/auto_integrator.h), on synthetic pilot
// images with known noise: the estimate recovers each variance, and a candidate that
// never found a bright feature gets that feature's squared error, which its own half
// images could not show.
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include "integrators/auto/auto_integrator.h"

namespace test_auto_pilot_errors {

namespace {

constexpr size_t kValues = 120000;
constexpr double kTruth = 0.5;
const double kDenominator = kTruth * kTruth + 0.01;

std::vector<float> noisy(double sigma, std::mt19937 &rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<float> image(kValues);
  for (float &v : image) v = float(kTruth + noise(rng));
  return image;
}

}  // namespace

// Four pilots with noise 0.02..0.05: each V_i = sigma_i^2 / (0.25 + 0.01). With 120,000
// values a pairwise mean square D_ij has relative spread sqrt(2 / 120000) = 0.4%, and every
// V_i mixes all D_ij with weights below 1, so its spread is below 0.4% of the largest D
// (< 2 V_max); the tolerance is 6 times that: false-alarm rate < 1e-8 (fixed seed).
TEST(AutoPilotErrors, RecoverEachPilotsVarianceFromTheDifferences) {
  std::mt19937 rng(7);
  const double sigmas[] = {0.02, 0.03, 0.04, 0.05};
  std::vector<std::vector<float>> images;
  for (double s : sigmas) images.push_back(noisy(s, rng));
  const std::vector<double> reference(kValues, kTruth);
  const std::vector<double> v = rdv::errors_against_each_other(images, reference, {true, true, true, true});
  ASSERT_EQ(v.size(), 4u);
  const double largest_d = 2 * 0.05 * 0.05 / kDenominator;
  const double tolerance = 6 * std::sqrt(2.0 / double(kValues)) * largest_d;
  for (int i = 0; i < 4; ++i) {
    const double expected = sigmas[i] * sigmas[i] / kDenominator;
    EXPECT_NEAR(v[i], expected, tolerance) << "candidate " << i;
  }
}

// Candidate 0 is smooth (noise 0.01) but lacks a caustic: 1% of the values are 4.5 brighter
// in every other image. Its error is that caustic's (1% of 4.5^2 / (ref^2 + 0.01)), ~40x its
// noise; the others keep their noise.
TEST(AutoPilotErrors, ACandidateThatMissedABrightFeatureCarriesItsError) {
  std::mt19937 rng(11);
  std::vector<std::vector<float>> images = {noisy(0.01, rng), noisy(0.03, rng), noisy(0.03, rng)};
  std::vector<double> reference(kValues, kTruth);
  double expected_bias = 0;
  for (size_t i = 0; i < kValues; i += 100) {
    for (size_t c = 1; c < images.size(); ++c) images[c][i] += 4.5f;
    reference[i] += 4.5 * 2.0 / 3.0;  // the candidates' mean, as the auto integrator pools
    expected_bias += 4.5 * 4.5 / (reference[i] * reference[i] + 0.01);
  }
  expected_bias /= double(kValues);
  const std::vector<double> v = rdv::errors_against_each_other(images, reference, {true, true, true});
  // Tolerance as above, 6 x sqrt(2 / N) x the largest pairwise D (~ bias + noise).
  const double tolerance = 6 * std::sqrt(2.0 / double(kValues)) * (expected_bias + 2 * 0.03 * 0.03 / kDenominator);
  const double noise_1 = 0.03 * 0.03 / kDenominator;
  EXPECT_NEAR(v[0], expected_bias + 0.01 * 0.01 / kDenominator, tolerance);
  EXPECT_GT(v[0], 20 * 0.01 * 0.01 / kDenominator);  // what its own halves would have shown
  EXPECT_NEAR(v[1], noise_1, tolerance);
  EXPECT_NEAR(v[2], noise_1, tolerance);
}

// Fewer than three candidates with samples: no evidence (-1), never a guess.
TEST(AutoPilotErrors, NeedsThreeCandidatesWithSamples) {
  std::mt19937 rng(3);
  std::vector<std::vector<float>> images = {noisy(0.01, rng), noisy(0.02, rng), noisy(0.03, rng)};
  const std::vector<double> reference(kValues, kTruth);
  for (double v : rdv::errors_against_each_other(images, reference, {true, false, true})) EXPECT_EQ(v, -1.0);
  for (double v : rdv::errors_against_each_other({images[0], images[1]}, reference, {true, true})) EXPECT_EQ(v, -1.0);
}

}  // namespace test_auto_pilot_errors
