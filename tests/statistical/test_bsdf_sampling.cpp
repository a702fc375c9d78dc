// BSDF sampling against its pdf (chi-square), sample weights against eval / pdf,
// energy (albedo <= 1), reciprocity, and the mirror limit, for every lobe of the
// registry at normal, oblique and grazing incidence.
#include <gtest/gtest.h>
#include "bsdfs/registry.h"
#include "chi_square.h"
#include "core/hash.h"
#include "core/sampling.h"

namespace test_bsdf_sampling {

using namespace rdv;

namespace {

const std::vector<Vec3> &incident_directions() {
  static const std::vector<Vec3> dirs = {normalize(Vec3(0, 0, 1)), normalize(Vec3(0.5f, 0.2f, 0.7f)),
                                         normalize(Vec3(0.8f, 0.3f, 0.05f))};
  return dirs;
}

int count_chi_square_tests() {
  int n = 0;
  for (const auto &c : lobe_test_cases())
    if (!c.lobe.is_delta()) n += int(incident_directions().size());
  return n;
}

}  // namespace

// False-alarm rate: 1% for the whole suite of chi-square tests (Sidak-corrected).
TEST(BsdfSampling, ChiSquareEveryLobe) {
  const double alpha = test::sidak(0.01, count_chi_square_tests());
  uint64_t seed = 1;
  for (const auto &c : lobe_test_cases()) {
    if (c.lobe.is_delta()) continue;
    for (Vec3 wo : incident_directions()) {
      SCOPED_TRACE(c.name + " wo=(" + std::to_string(wo.x) + "," + std::to_string(wo.y) + "," + std::to_string(wo.z) + ")");
      auto result = test::chi_square_directions(
          [&](Vec2 u, Vec3 &wi) {
            Color w;
            float pdf;
            return lobe_sample(c.lobe, wo, u, wi, w, pdf);
          },
          [&](Vec3 wi) { return lobe_pdf(c.lobe, wo, wi); }, 200000, seed++);
      EXPECT_FALSE(result.impossible_sample) << result.detail;
      EXPECT_GT(result.p_value, alpha) << result.detail;
    }
  }
}

TEST(BsdfSampling, WeightMatchesEvalOverPdf) {
  for (const auto &c : lobe_test_cases()) {
    if (c.lobe.is_delta()) continue;
    Pcg32 rng(std::hash<std::string>{}(c.name));  // each lobe its own directions: a new lobe moves no other's
    for (Vec3 wo : incident_directions()) {
      int checked = 0;
      for (int i = 0; i < 2000; ++i) {
        Vec3 wi;
        Color w;
        float pdf;
        float a = rng.next_float();
        // Both transport modes (they differ for refraction by the eta^2 scaling).
        TransportMode mode = (i & 1) ? TransportMode::Importance : TransportMode::Radiance;
        if (!lobe_sample(c.lobe, wo, {a, rng.next_float()}, wi, w, pdf, mode)) continue;
        ASSERT_GT(pdf, 0) << c.name;
        EXPECT_NEAR(pdf, lobe_pdf(c.lobe, wo, wi), 1e-3f * pdf) << c.name;
        Color f = lobe_eval(c.lobe, wo, wi, mode);
        Color expected = f * (std::fabs(wi.z) / pdf);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(w[k], expected[k], 2e-3f * std::max(1.0f, expected[k])) << c.name;
        // The combined evaluation gives what eval and pdf give alone.
        float pdf_both;
        Color f_both = lobe_eval_and_pdf(c.lobe, wo, wi, mode, pdf_both);
        EXPECT_NEAR(pdf_both, lobe_pdf(c.lobe, wo, wi), 1e-5f * pdf) << c.name;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(f_both[k], f[k], 1e-5f * std::max(1.0f, f[k])) << c.name;
        ++checked;
      }
      EXPECT_GT(checked, 100) << c.name;
    }
  }
}

// Directional albedo by Monte Carlo: never above 1 (beyond 4 standard errors); lossless
// lobes reflect everything within 1%.
TEST(BsdfEnergy, AlbedoAtMostOne) {
  Pcg32 rng(11);
  for (const auto &c : lobe_test_cases()) {
    for (Vec3 wo : incident_directions()) {
      const int n = 100000;
      double sum = 0, sum2 = 0;
      for (int i = 0; i < n; ++i) {
        Vec3 wi;
        Color w(0.0f);
        float pdf;
        float a = rng.next_float();
        // Radiance mode: the flux a lobe scatters (Importance mode carries refraction's
        // 1 / eta^2, which exceeds 1 leaving a dense medium).
        if (!lobe_sample(c.lobe, wo, {a, rng.next_float()}, wi, w, pdf, TransportMode::Radiance)) w = Color(0.0f);
        double v = max_component(w);
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
      if (!c.exceeds_one_by_design) EXPECT_LE(mean, 1.0 + 4 * se + 1e-4) << c.name << " albedo " << mean;
      if (c.energy_conserving) EXPECT_NEAR(mean, 1.0, 0.01) << c.name;
    }
  }
}

// Reflection is reciprocal: a light path's f (Importance, the adjoint) is the camera path's
// with the directions swapped; for all but Cycles 3.4's glass (weighted by the camera side's
// Fresnel) that is also f(a, b) = f(b, a) in one mode.
TEST(BsdfReciprocity, ReflectionIsSymmetric) {
  Pcg32 rng(13);
  for (const auto &c : lobe_test_cases()) {
    if (c.lobe.is_delta()) continue;
    for (int i = 0; i < 2000; ++i) {
      Vec3 a = uniform_hemisphere_for_test(rng.next_float(), rng.next_float());
      Vec3 b = uniform_hemisphere_for_test(rng.next_float(), rng.next_float());
      Color fab = lobe_eval(c.lobe, a, b), fba = lobe_eval(c.lobe, b, a, TransportMode::Importance);
      if (!c.lobe.macro_fresnel) {
        Color same_mode = lobe_eval(c.lobe, b, a);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(same_mode[k], fba[k], 1e-6f * std::max(1.0f, fba[k])) << c.name;
      }
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(fab[k], fba[k], 1e-4f * std::max(1.0f, fab[k])) << c.name;
    }
  }
}

TEST(BsdfSampling, MirrorLimitReflectsExactly) {
  for (const auto &c : lobe_test_cases()) {
    if (c.lobe.type != LobeType::SpecularConductor) continue;  // dielectrics: test_material_dielectric.cpp
    for (Vec3 wo : incident_directions()) {
      Vec3 wi;
      Color w;
      float pdf;
      ASSERT_TRUE(lobe_sample(c.lobe, wo, {0.3f, 0.7f}, wi, w, pdf)) << c.name;
      EXPECT_NEAR(wi.x, -wo.x, 1e-6f);
      EXPECT_NEAR(wi.y, -wo.y, 1e-6f);
      EXPECT_NEAR(wi.z, wo.z, 1e-6f);
      EXPECT_NEAR(w.x, 1.0f, 1e-6f) << "white mirror reflects everything";
      EXPECT_EQ(lobe_pdf(c.lobe, wo, wi), 0.0f) << "delta lobes have no density";
    }
  }
}

// A Bsdf with several lobes samples its mixture pdf (lobe selection included).
TEST(BsdfSampling, ChiSquareMixture) {
  Bsdf bsdf(Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1));
  Lobe diffuse;
  diffuse.type = LobeType::Lambert;
  diffuse.color = Color(0.5f);
  Lobe glossy;
  glossy.type = LobeType::GgxConductor;
  glossy.ggx = {0.09f, 0.09f};
  bsdf.add_lobe(diffuse, 1.0f);
  bsdf.add_lobe(glossy, 2.0f);
  Vec3 wo = normalize(Vec3(0.4f, -0.3f, 0.6f));
  Pcg32 lobe_rng(99);
  auto result = test::chi_square_directions(
      [&](Vec2 u, Vec3 &wi) {
        BsdfSample s;
        if (!bsdf.sample(wo, lobe_rng.next_float(), u, TransportMode::Radiance, s)) return false;
        wi = s.wi;
        return true;
      },
      [&](Vec3 wi) { return bsdf.pdf(wo, wi); }, 200000, 5);
  EXPECT_FALSE(result.impossible_sample) << result.detail;
  EXPECT_GT(result.p_value, 0.01) << result.detail;
}

// A Bsdf of one Lambert lobe evaluates f and its densities from the normal components
// alone (Bsdf::lambert_: f, eval_and_pdf, f_and_pdfs, pdf); it must agree with the general path (frame change, side and
// lobe rules), here a Bsdf of two half-strength Lambert lobes, for directions on both
// sides of tilted shading normals, in both transport modes. Deterministic.
TEST(BsdfEvaluation, LambertFastPathMatchesGeneralPath) {
  Pcg32 rng(2027);
  Lobe lambert;
  lambert.type = LobeType::Lambert;
  lambert.color = Color(0.8f, 0.5f, 0.2f);
  Lobe half = lambert;
  half.color = lambert.color * 0.5f;
  int nonzero = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 ng = uniform_sphere({rng.next_float(), rng.next_float()});
    Vec3 ns = normalize(ng + uniform_sphere({rng.next_float(), rng.next_float()}) * (0.6f * rng.next_float()));
    Vec3 wo_build = uniform_sphere({rng.next_float(), rng.next_float()});
    Vec3 wo = rng.next_float() < 0.7f ? wo_build : uniform_sphere({rng.next_float(), rng.next_float()});
    Vec3 wi = uniform_sphere({rng.next_float(), rng.next_float()});
    Bsdf fast(ng, ns, wo_build), general(ng, ns, wo_build);
    fast.add_lobe(lambert, 1.0f);
    general.add_lobe(half, 1.0f);
    general.add_lobe(half, 1.0f);
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      float fwd_fast, rev_fast, fwd_general, rev_general;
      Color f_fast = fast.f_and_pdfs(wo, wi, mode, fwd_fast, rev_fast);
      Color f_general = general.f_and_pdfs(wo, wi, mode, fwd_general, rev_general);
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(f_fast[k], f_general[k], 1e-5f * std::max(1.0f, f_general[k])) << i;
      ASSERT_NEAR(fast.pdf(wo, wi), general.pdf(wo, wi), 1e-6f) << i;
      Color f_alone = fast.f(wo, wi, mode), f_alone_general = general.f(wo, wi, mode);
      float pdf_eval, pdf_eval_general;
      Color e = fast.eval_and_pdf(wo, wi, mode, pdf_eval), e_general = general.eval_and_pdf(wo, wi, mode, pdf_eval_general);
      for (int k = 0; k < 3; ++k) {
        ASSERT_NEAR(f_alone[k], f_alone_general[k], 1e-5f * std::max(1.0f, f_alone_general[k])) << i;
        ASSERT_NEAR(e[k], e_general[k], 1e-5f * std::max(1.0f, e_general[k])) << i;
      }
      ASSERT_NEAR(pdf_eval, pdf_eval_general, 1e-6f) << i;
      if (is_black(f_general)) continue;  // the densities of a zero contribution are not used
      ++nonzero;
      ASSERT_NEAR(fwd_fast, fwd_general, 1e-6f) << i;
      ASSERT_NEAR(rev_fast, rev_general, 1e-6f) << i;
    }
  }
  EXPECT_GT(nonzero, 5000);
}

}  // namespace test_bsdf_sampling
