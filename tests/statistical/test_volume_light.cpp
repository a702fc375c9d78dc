// Volume lights (lights/volume_light.h): the density of the sampled points is the one
// pdf() reports, and it integrates to one; blackbody colours (media/blackbody.h).
//
// False alarms: the chi-square tests use alpha = 1e-3 each (2 tests: suite rate
// < 0.2%), with fixed seeds, so each outcome is reproducible.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "chi_square.h"
#include "core/params.h"
#include "lights/volume_light.h"
#include "media/blackbody.h"

namespace rdv::test_volume_light {
namespace {

using nlohmann::json;

constexpr int kCells = 8;  // per axis, over the unit cube: the test's histogram

// Sparse values with sharp peaks on an 8^3 lattice over the unit cube (aligned with
// the histogram cells, so the pdf is constant in every cell).
json peaks_grid() {
  std::vector<float> v(kCells * kCells * kCells, 0.0f);
  v[0] = 1.0f;
  v[(3 * kCells + 4) * kCells + 2] = 7.0f;
  v[(5 * kCells + 5) * kCells + 5] = 0.3f;
  v[(7 * kCells + 7) * kCells + 7] = 2.0f;
  return {{"resolution", {kCells, kCells, kCells}}, {"values", v}};
}

// Histogram of sampled points against pdf() x cell volume, pooled where < 5 expected.
void expect_density_matches_pdf(const VolumeEmitter &e, const std::string &what) {
  const int n = 400000;
  std::vector<double> observed(kCells * kCells * kCells, 0.0), expected(observed.size(), 0.0);
  const double cell_volume = 1.0 / (kCells * kCells * kCells);
  double integral = 0;
  for (int k = 0; k < kCells; ++k)
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i) {
        float p = e.pdf(Vec3((i + 0.5f) / kCells, (j + 0.5f) / kCells, (k + 0.5f) / kCells));
        expected[(k * kCells + j) * kCells + i] = p * cell_volume * n;
        integral += p * cell_volume;
      }
  EXPECT_NEAR(integral, 1.0, 1e-4) << what << ": the pdf does not integrate to one";
  Pcg32 rng(17);
  for (int s = 0; s < n; ++s) {
    float pdf;
    Vec2 u(rng.next_float(), rng.next_float());
    Vec3 p = e.sample(u, Vec3(rng.next_float(), rng.next_float(), rng.next_float()), &pdf);
    ASSERT_TRUE(pdf > 0) << what;
    ASSERT_NEAR(pdf, e.pdf(p), 1e-4f * pdf) << what << ": sample() and pdf() disagree";
    int i = std::clamp(int(p.x * kCells), 0, kCells - 1), j = std::clamp(int(p.y * kCells), 0, kCells - 1),
        k = std::clamp(int(p.z * kCells), 0, kCells - 1);
    observed[(k * kCells + j) * kCells + i] += 1;
  }
  double chi2 = 0, pooled_o = 0, pooled_e = 0;
  int dof = -1;
  for (size_t c = 0; c < observed.size(); ++c) {
    if (expected[c] == 0) {
      ASSERT_EQ(observed[c], 0) << what << ": a sample where the pdf is zero (cell " << c << ")";
      continue;
    }
    if (expected[c] < 5) { pooled_o += observed[c]; pooled_e += expected[c]; continue; }
    chi2 += (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c];
    ++dof;
  }
  if (pooled_e > 0) { chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e; ++dof; }
  double p_value = test::gamma_q(dof / 2.0, chi2 / 2.0);
  EXPECT_GT(p_value, 1e-3) << what << ": chi2 " << chi2 << " dof " << dof;
}

Medium medium_from(const json &j) {
  Params p(j.dump(), "test medium");
  return Medium::from_params(p, "fire");
}

// Uniform emission in two overlapping regions (the boxes of two instances).
TEST(VolumeLight, UniformRegionsSampleTheirDensity) {
  Medium m = medium_from({{"density", 1.0}, {"emission_strength", 2.0}});
  std::vector<VolumeEmitter::Region> regions = {{Vec3(0, 0, 0), Vec3(0.5f, 1, 1), 0.5f},
                                                {Vec3(0.25f, 0.25f, 0.5f), Vec3(1, 1, 1), 0.375f}};
  VolumeEmitter e(m, 0, regions);
  EXPECT_NEAR(e.power(), 4 * kPi * 2.0 * (0.5 + 0.375), 1e-3);
  expect_density_matches_pdf(e, "uniform regions");
}

// A grid-shaped emission (emission grid x colour, plus blackbody from a temperature
// grid) and a uniform part: voxels by emitted power, the defensive share everywhere.
TEST(VolumeLight, GridEmissionSamplesItsDensity) {
  json temperature = peaks_grid();
  for (auto &v : temperature["values"]) v = float(v) * 400.0f;  // kelvin / 1000 K
  Medium m = medium_from({{"density", 1.0}, {"emission_strength", 3.0}, {"emission_color", {1, 0.5, 0.2}},
                          {"emission_grid", peaks_grid()}, {"blackbody_intensity", 1.0}, {"temperature", 1.0},
                          {"temperature_grid", temperature}});
  ASSERT_TRUE(m.has_emission_grids());
  VolumeEmitter grid_only(m, 0, {{Vec3(0.0f), Vec3(1.0f), 1.0f}});
  expect_density_matches_pdf(grid_only, "grid emission");
  // The emission itself: zero where both grids are zero, Cycles' blackbody at a peak.
  EXPECT_EQ(luminance(m.emission_at(Vec3(0.5f, 0.06f, 0.06f))), 0.0f);
  Vec3 peak((2 + 0.5f) / kCells, (4 + 0.5f) / kCells, (3 + 0.5f) / kCells);
  Color expected = Color(1, 0.5f, 0.2f) * 3.0f * 7.0f + m.blackbody.radiance(2800.0f);
  Color got = m.emission_at(peak);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-3f * expected[c] + 1e-6f);
}

// Blackbody colours: luminance one, and Cycles 3.4's fit at its ends (within the
// accuracy of the colour matching function fit we integrate with).
TEST(Blackbody, ColoursMatchCycles) {
  for (float T : {1000.0f, 1500.0f, 3000.0f, 6500.0f, 10000.0f})
    EXPECT_NEAR(luminance(blackbody_color(T)), 1.0f, 0.02f) << T;  // negatives clipped: a little above 1 at 1000 K
  Color hot = blackbody_color(12000.0f), cycles_hot(0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(hot[c], cycles_hot[c], 0.005f * cycles_hot[c]) << c;
  // Cycles: (5.41, -0.20, -0.08) at 800 K and below, before negatives are clipped. Only the
  // far-red tail of the colour matching functions sees 800 K (an analytic fit of them
  // gave 4.86; the CIE table 5.406).
  Color cold = blackbody_color(700.0f);
  EXPECT_NEAR(cold.x, 5.41f, 0.02f);
  EXPECT_EQ(cold.y + cold.z, 0.0f);
  // On the Planckian locus: CIE 1931 chromaticity at 2000 K (0.5269, 0.4133) after Kim et
  // al.'s fit of the locus; the colour back to xy through Rec.709 -> XYZ.
  Color c2000 = blackbody_color(2000.0f);  // no negative component to clip
  double X = 0.4124564 * c2000.x + 0.3575761 * c2000.y + 0.1804375 * c2000.z;
  double Y = 0.2126729 * c2000.x + 0.7151522 * c2000.y + 0.0721750 * c2000.z;
  double Z = 0.0193339 * c2000.x + 0.1191920 * c2000.y + 0.9503041 * c2000.z;
  EXPECT_NEAR(X / (X + Y + Z), 0.5269, 1e-3);
  EXPECT_NEAR(Y / (X + Y + Z), 0.4133, 1e-3);
  // Redder when colder.
  EXPECT_GT(blackbody_color(1500.0f).x, blackbody_color(3000.0f).x);
  EXPECT_LT(blackbody_color(1500.0f).z, blackbody_color(3000.0f).z);
  // Stefan-Boltzmann at intensity 1: sigma T^4 / pi x 1e-6 in luminance; none at 0 K.
  Blackbody bb;
  bb.intensity = 1;
  EXPECT_NEAR(luminance(bb.radiance(1500.0f)), 5.670373e-14 * std::pow(1500.0, 4) / kPi, 2e-2 * 0.0914);
  EXPECT_EQ(luminance(bb.radiance(0.0f)), 0.0f);
}

}  // namespace
}  // namespace rdv::test_volume_light
