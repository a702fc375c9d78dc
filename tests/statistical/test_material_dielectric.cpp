// Dielectric-specific checks the registry-wide tests cannot express: the smooth
// interface keeps all energy (R + T = 1 exactly) with the right Fresnel split, total
// internal reflection, the eta^2 rule for refraction (carried by Importance mode; Radiance
// mode leaves it out, as Cycles does), the adjoint relation f_importance(wo, wi) = f_radiance(wi, wo),
// and the Bsdf's side rules (refraction only through transmissive lobes; a back-face
// hit sees the inverse IOR). All checks are deterministic (no false alarms).
#include <gtest/gtest.h>
#include "bsdfs/bsdf.h"
#include "chi_square.h"
#include "core/hash.h"

namespace test_material_dielectric {

using namespace rdv;

namespace {

Lobe glass(float roughness, float ior) {
  Lobe l;
  l.ggx = {roughness * roughness, roughness * roughness};
  l.type = l.ggx.is_smooth() ? LobeType::SmoothDielectric : LobeType::GgxDielectric;
  l.ior = ior;
  return l;
}

Vec3 random_upper(Pcg32 &rng) {
  float a = rng.next_float();
  return uniform_hemisphere_for_test(std::max(a, 1e-3f), rng.next_float());
}

}  // namespace

TEST(Dielectric, SmoothKeepsAllEnergyWithFresnelSplit) {
  for (float ior : {1.0001f, 1.33f, 1.5f, 2.4f, 4.0f, 1.0f / 1.5f, 0.25f}) {
    for (float cos_o : {1.0f, 0.7f, 0.3f, 0.05f}) {
      Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);
      Lobe l = glass(0, ior);
      float F = fresnel_dielectric(cos_o, ior);
      Vec3 wi_r, wi_t;
      Color w_r, w_t;
      float p_r = 0, p_t = 0;
      ASSERT_TRUE(lobe_sample(l, wo, {F * 0.5f, 0.5f}, wi_r, w_r, p_r, TransportMode::Importance));
      EXPECT_NEAR(wi_r.z, cos_o, 1e-6f);
      EXPECT_NEAR(p_r, F, 1e-6f);
      bool refracts = lobe_sample(l, wo, {F + (1 - F) * 0.5f, 0.5f}, wi_t, w_t, p_t, TransportMode::Importance);
      if (F >= 1.0f) {
        EXPECT_FALSE(refracts && wi_t.z < 0) << "total internal reflection must not refract";
        continue;
      }
      ASSERT_TRUE(refracts) << ior << " " << cos_o;
      ASSERT_LT(wi_t.z, 0);
      // Snell: sin_t = sin_o / eta.
      EXPECT_NEAR(std::sqrt(1 - wi_t.z * wi_t.z), std::sqrt(1 - cos_o * cos_o) / ior, 1e-4f);
      // R + T = 1: the probabilities of the two events, each carrying weight 1.
      EXPECT_NEAR(p_r + p_t, 1.0f, 1e-6f);
      EXPECT_NEAR(w_r.x, 1.0f, 1e-6f);
      EXPECT_NEAR(w_t.x, 1.0f / (ior * ior), 1e-5f) << "Importance mode: 1 / eta^2";
      Color w_rad;
      float p;
      Vec3 wi;
      ASSERT_TRUE(lobe_sample(l, wo, {F + (1 - F) * 0.5f, 0.5f}, wi, w_rad, p, TransportMode::Radiance));
      EXPECT_NEAR(w_rad.x, 1.0f, 1e-6f) << "Radiance mode: no eta^2 (Cycles' convention)";
    }
  }
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
}

TEST(Dielectric, TotalInternalReflection) {
  float ior = 1.0f / 1.5f;  // from inside glass; critical angle asin(1/1.5) = 41.8 degrees
  Vec3 wo = normalize(Vec3(0.9f, 0.0f, 0.3f));  // 71.6 degrees from the normal
  EXPECT_EQ(fresnel_dielectric(wo.z, ior), 1.0f);
  Lobe l = glass(0, ior);
  for (float u : {0.0f, 0.5f, 0.999f}) {
    Vec3 wi;
    Color w;
    float p;
    ASSERT_TRUE(lobe_sample(l, wo, {u, 0.5f}, wi, w, p));
    EXPECT_GT(wi.z, 0);
    EXPECT_NEAR(w.x, 1.0f, 1e-6f);
  }
  // Rough: no refracted density beyond the critical angle for the macro normal's facets.
  Lobe r = glass(0.05f, ior);
  EXPECT_EQ(lobe_pdf(r, wo, normalize(Vec3(-0.2f, 0, -1))), 0.0f);
}

// f_rad(eta; wo, wi) = eta^2 f_rad(1/eta; -wi, -wo): the BTDF's generalised reciprocity
// (Radiance mode leaves out the eta^2 radiance gain, as Cycles does); and the adjoint
// f_imp(eta; wo, wi) = f_rad(1/eta; -wi, -wo), also for Cycles 3.4's glass (split by the
// camera side's Fresnel at the shading normal, so not reciprocal in one mode).
TEST(Dielectric, EtaSquaredRuleAndAdjoint) {
  Pcg32 rng(21);
  int checked = 0;
  for (bool cycles34 : {false, true})
  for (float ior : {1.5f, 1.0f / 1.5f, 1.01f, 4.0f}) {
    for (float rough : {0.1f, 0.4f, 1.0f}) {
      Lobe l = glass(rough, ior), flipped = glass(rough, 1.0f / ior);
      l.ggx.separable = flipped.ggx.separable = l.macro_fresnel = flipped.macro_fresnel = cycles34;
      for (int i = 0; i < 500; ++i) {
        Vec3 wo = random_upper(rng), wi = random_upper(rng);
        wi.z = -wi.z;
        Color f_rad = lobe_eval(l, wo, wi, TransportMode::Radiance);
        Color f_imp = lobe_eval(l, wo, wi, TransportMode::Importance);
        Color g_rad = lobe_eval(flipped, -wi, -wo, TransportMode::Radiance);
        // 1%: float rounding of the half vector and of cos_t near the critical angle.
        float tol = 1e-2f * std::max(1e-3f, g_rad.x);
        if (!cycles34) EXPECT_NEAR(f_rad.x, g_rad.x * ior * ior, tol * ior * ior) << ior << " " << rough;
        EXPECT_NEAR(f_imp.x, g_rad.x, tol) << ior << " " << rough << (cycles34 ? " (Cycles 3.4)" : "");
        if (f_rad.x > 0) ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

TEST(Dielectric, BsdfSideRules) {
  Vec3 n(0, 0, 1), wo = normalize(Vec3(0.3f, 0.1f, 1.0f)), below = normalize(Vec3(-0.2f, 0.1f, -1.0f));
  // A diffuse surface never transmits, whatever the shading normal says.
  Lobe lambert;
  lambert.type = LobeType::Lambert;
  Bsdf d(n, normalize(Vec3(0.3f, 0, 1)), wo);
  d.add_lobe(lambert, 1);
  EXPECT_TRUE(is_black(d.eval(wo, below, TransportMode::Radiance)));
  EXPECT_EQ(d.pdf(wo, below), 0.0f);
  // Rough glass: transmission has density from the front ...
  Bsdf g(n, n, wo);
  g.add_lobe(glass(0.3f, 1.5f), 1);
  EXPECT_FALSE(is_black(g.eval(wo, below, TransportMode::Radiance)));
  EXPECT_GT(g.pdf(wo, below), 0.0f);
  EXPECT_FALSE(g.backfacing());
  // ... and a ray arriving from the back face sees the inverse IOR (leaving the glass).
  Vec3 wo_back = -wo;
  Bsdf b(n, n, wo_back);
  b.add_lobe(glass(0, 1.5f), 1);
  EXPECT_TRUE(b.backfacing());
  BsdfSample s;
  // Pick refraction (u >> F) and check Snell with eta = 1 / 1.5.
  ASSERT_TRUE(b.sample(wo_back, 0.999f, {0.999f, 0.5f}, TransportMode::Importance, s));
  EXPECT_GT(dot(s.wi, n), 0) << "leaves through the front";
  float sin_o = std::sqrt(1 - sqr(dot(wo_back, n))), sin_t = std::sqrt(1 - sqr(dot(s.wi, n)));
  EXPECT_NEAR(sin_t, sin_o * 1.5f, 1e-4f);
}

// The rough-glass limit: roughness 1e-4 is the smooth (delta) model.
TEST(Dielectric, SmoothLimit) {
  EXPECT_EQ(glass(1e-4f, 1.5f).type, LobeType::SmoothDielectric);
  EXPECT_EQ(glass(0.05f, 1.5f).type, LobeType::GgxDielectric);
}

}  // namespace test_material_dielectric
