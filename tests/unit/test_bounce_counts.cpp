// Cycles' bounce limits on mixed reflections (integrators/light_path_limits.h,
// Bsdf::glossy_odds): a reflection off a mixture of diffuse and glossy closures is one or
// the other by the closure Cycles sampled there. BounceCounts keeps the distribution of how
// many mixed reflections were diffuse; kept_share must be the odds, enumerated here over
// every assignment, that the limits keep the path. glossy_odds must be each closure's share
// of the density of the direction, with Cycles' selection weights (and its defensive floor
// at a camera path's first bounce). Deterministic.
#include <gtest/gtest.h>
#include <vector>
#include "bsdfs/material.h"
#include "integrators/light_path_limits.h"
#include "lcg.h"
#include "test_materials.h"

namespace test_bounce_counts {

using namespace rdv;
using rdv::test::flat_point;
using rdv::test::material_from_json;

namespace {

struct Bounce {
  ScatterKind kind;
  float glossy_odds;  // < 0: the kind alone decides
};

// The odds that the limits keep a path of these bounces, over all 2^m ways its mixed
// reflections can each be diffuse or glossy.
double enumerated_kept(const std::vector<Bounce> &bounces, const LightPathLimits &limits) {
  std::vector<int> mixed;
  for (size_t i = 0; i < bounces.size(); ++i)
    if (bounces[i].glossy_odds > 0 && bounces[i].glossy_odds < 1) mixed.push_back(int(i));
  double kept = 0;
  for (uint32_t bits = 0; bits < (1u << mixed.size()); ++bits) {
    double odds = 1;
    int n[4] = {0, 0, 0, 0};
    for (size_t i = 0, m = 0; i < bounces.size(); ++i) {
      const Bounce &b = bounces[i];
      ScatterKind k = b.kind;
      if (m < mixed.size() && mixed[m] == int(i)) {
        const bool glossy = (bits >> m) & 1;
        odds *= glossy ? b.glossy_odds : 1 - b.glossy_odds;
        k = glossy ? ScatterKind::Glossy : ScatterKind::Diffuse;
        ++m;
      } else if (b.glossy_odds >= 1) {
        k = ScatterKind::Glossy;
      } else if (b.glossy_odds == 0) {
        k = ScatterKind::Diffuse;
      }
      switch (k) {
        case ScatterKind::Diffuse: ++n[0]; break;
        case ScatterKind::Glossy: ++n[1]; break;
        case ScatterKind::Transmission: ++n[2]; break;
        case ScatterKind::Volume: ++n[3]; break;
        default: break;
      }
    }
    if (n[0] <= limits.diffuse && n[1] <= limits.glossy && n[2] <= limits.transmission && n[3] <= limits.volume)
      kept += odds;
  }
  return kept;
}

LightPathLimits limits_of(int diffuse, int glossy, int transmission = LightPathLimits::kNoLimit) {
  LightPathLimits l;
  l.diffuse = diffuse;
  l.glossy = glossy;
  l.transmission = transmission;
  return l;
}

}  // namespace

// Random paths of up to 12 bounces (mixed, pure and transmissions) against every limit pair
// up to 6: kept_share equals the enumerated odds, whether the counts were built one bounce at
// a time or as the sum (operator+) of a camera-side and a light-side part, as BDPT joins them.
TEST(BounceCounts, KeptShareIsTheEnumeratedOdds) {
  rdv::test::Lcg random{12345};
  auto next = [&]() { return random.next(); };
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Bounce> bounces;
    const int length = 1 + int(next() * 12);
    for (int i = 0; i < length; ++i) {
      const float r = next();
      if (r < 0.6f) bounces.push_back({ScatterKind::Diffuse, 0.05f + 0.9f * next()});
      else if (r < 0.75f) bounces.push_back({ScatterKind::Diffuse, 0.0f});
      else if (r < 0.9f) bounces.push_back({ScatterKind::Glossy, 1.0f});
      else bounces.push_back({ScatterKind::Transmission, -1.0f});
    }
    const size_t split = size_t(next() * float(bounces.size() + 1));
    BounceCounts whole, camera_side, light_side;
    for (size_t i = 0; i < bounces.size(); ++i) {
      whole.add(bounces[i].kind, bounces[i].glossy_odds);
      (i < split ? camera_side : light_side).add(bounces[i].kind, bounces[i].glossy_odds);
    }
    const BounceCounts joined = camera_side + light_side;
    for (int d = 0; d <= 6; ++d)
      for (int g = 0; g <= 6; ++g) {
        const LightPathLimits limits = limits_of(d, g, 3);
        const double expected = enumerated_kept(bounces, limits);
        SCOPED_TRACE("trial " + std::to_string(trial) + " diffuse " + std::to_string(d) + " glossy " +
                     std::to_string(g));
        EXPECT_NEAR(limits.kept_share(whole), expected, 2e-5);
        EXPECT_NEAR(limits.kept_share(joined), expected, 2e-5);
        EXPECT_EQ(limits.within(whole), expected > 1e-12);
      }
  }
}

// More mixed reflections than the distribution keeps apart: the odds still sum to 1 and a
// limit no path can exceed keeps everything.
TEST(BounceCounts, LongPathsKeepTheirMass) {
  BounceCounts c;
  for (int i = 0; i < 60; ++i) c.add(ScatterKind::Diffuse, 0.5f);
  EXPECT_NEAR(limits_of(LightPathLimits::kNoLimit, LightPathLimits::kNoLimit).kept_share(c), 1.0, 1e-4);
  EXPECT_NEAR(limits_of(LightPathLimits::kNoLimit, 0).kept_share(c), 0.0, 1e-6);  // 2^-60
}

// glossy_odds of a Mix of a white diffuse and a white glossy closure (no Fresnel: the Glossy
// BSDF's weight is its colour times the mix factor) is the glossy closure's share of the
// density of the direction: fac pg / (fac pg + (1 - fac) pd), pg and pd the densities of
// each closure alone; with the defensive floor, a weight no smaller than 1/8 of the sum.
TEST(BounceCounts, GlossyOddsAreTheClosuresShareOfTheDensity) {
  const ShadingPoint sp = flat_point();
  Material diffuse = material_from_json(R"({"type":"diffuse","color":[1,1,1]})");
  Material glossy = material_from_json(R"({"type":"glossy","color":[1,1,1],"roughness":0.4})");
  const Vec3 wo = normalize(Vec3(0.4f, 0.1f, 0.8f));
  for (float fac : {0.05f, 0.3f, 0.8f}) {
    const std::string json = R"({"type":"mix","fac":)" + std::to_string(fac) +
                             R"(,"shader1":{"type":"diffuse","color":[1,1,1]},"shader2":{"type":"glossy","color":[1,1,1],"roughness":0.4}})";
    Material mix = material_from_json(json);
    const Bsdf b = mix.make_bsdf(sp, wo);
    for (Vec3 wi : {normalize(Vec3(-0.4f, -0.1f, 0.8f)), normalize(Vec3(0.3f, -0.6f, 0.3f)), Vec3(0, 0, 1)}) {
      const float pg = glossy.make_bsdf(sp, wo).pdf(wo, wi), pd = diffuse.make_bsdf(sp, wo).pdf(wo, wi);
      SCOPED_TRACE("fac " + std::to_string(fac) + " wi.z " + std::to_string(wi.z));
      EXPECT_NEAR(b.glossy_odds(wo, wi, false, false), fac * pg / (fac * pg + (1 - fac) * pd), 1e-4);
      const float floored = std::max(fac, 0.125f);
      EXPECT_NEAR(b.glossy_odds(wo, wi, false, true), floored * pg / (floored * pg + (1 - fac) * pd), 1e-4);
    }
  }
}

// One kind decides alone: 0 for a diffuse BSDF, 1 for a glossy one and for any delta
// reflection, -1 for a transmission.
TEST(BounceCounts, GlossyOddsOfOneKind) {
  const ShadingPoint sp = flat_point();
  const Vec3 wo = normalize(Vec3(0.4f, 0.1f, 0.8f)), wi = normalize(Vec3(-0.2f, 0.3f, 0.7f));
  EXPECT_EQ(material_from_json(R"({"type":"diffuse"})").make_bsdf(sp, wo).glossy_odds(wo, wi, false, true), 0.0f);
  EXPECT_EQ(material_from_json(R"({"type":"glossy","roughness":0.3})").make_bsdf(sp, wo).glossy_odds(wo, wi, false, true), 1.0f);
  const Bsdf principled = material_from_json(R"({"type":"principled","roughness":0.3})").make_bsdf(sp, wo);
  const float g = principled.glossy_odds(wo, wi, false, false);
  EXPECT_GT(g, 0.0f);
  EXPECT_LT(g, 1.0f);
  EXPECT_EQ(principled.glossy_odds(wo, wi, true, false), 1.0f);
  EXPECT_EQ(principled.glossy_odds(wo, Vec3(wi.x, wi.y, -wi.z), false, false), -1.0f);
}

// The path tracer takes the odds from sample() (the pass over the lobes that weighs the
// sampled mixture): they must be glossy_odds' of the sampled direction, plain and defensive,
// for mixtures, single lobes, delta reflections and transmissions alike.
TEST(BounceCounts, SampledOddsAreGlossyOddsOfTheSampledDirection) {
  const ShadingPoint sp = flat_point();
  const Vec3 wo = normalize(Vec3(0.4f, 0.1f, 0.8f));
  for (const char *json :
       {R"({"type":"principled","roughness":0.3})", R"({"type":"principled","roughness":0.2,"clearcoat":0.5,"sheen":0.5})",
        R"({"type":"principled","roughness":0.3,"transmission":0.5})", R"({"type":"diffuse"})",
        R"({"type":"mix","fac":0.4,"shader1":{"type":"diffuse"},"shader2":{"type":"glass","roughness":0}})"}) {
    const Bsdf b = material_from_json(json).make_bsdf(sp, wo);
    int mixed = 0;
    for (int i = 0; i < 256; ++i) {
      const float u_lobe = (float(i) + 0.5f) / 256.0f;
      const Vec2 u{float((i * 37) % 256) / 256.0f + 0.001f, float((i * 101) % 256) / 256.0f + 0.001f};
      for (Bsdf::Odds odds : {Bsdf::Odds::Plain, Bsdf::Odds::Defensive}) {
        BsdfSample s;
        if (!b.sample(wo, u_lobe, u, TransportMode::Radiance, s, odds)) continue;
        const float expected = b.glossy_odds(wo, s.wi, s.is_delta, odds == Bsdf::Odds::Defensive);
        EXPECT_NEAR(s.glossy_odds, expected, 1e-6f) << json << " sample " << i;
        mixed += s.glossy_odds > 0 && s.glossy_odds < 1;
      }
    }
    if (std::string(json).find("principled") != std::string::npos) EXPECT_GT(mixed, 100) << json;
  }
}

}  // namespace test_bounce_counts
