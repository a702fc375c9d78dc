// Cycles' caustics switches as a function of the path (integrators/caustics_switches.h):
// the chain's weight must be the expectation, enumerated here over every assignment of
// diffuse / other labels to the path's bounces, of the product of the shares each vertex
// keeps after a diffuse bounce; the camera side's forward chain, the light side's backward
// one and their meeting at any vertex must all give it. For BSDFs of one kind it must be
// the plain rule (a glossy reflection or a refraction right after a diffuse or translucent
// bounce drops the path). Bsdf::caustic_share must be the switched-on closures' part of f,
// per colour channel. Deterministic.
#include <gtest/gtest.h>
#include <vector>
#include "bsdfs/material.h"
#include "integrators/caustics_switches.h"
#include "lcg.h"
#include "test_materials.h"

namespace test_caustics_switches {

using namespace rdv;
using rdv::test::flat_point;
using rdv::test::material_from_json;

namespace {

LightPathLimits switches(bool reflective, bool refractive) {
  LightPathLimits l;
  l.caustics_reflective = reflective;
  l.caustics_refractive = refractive;
  l.finish();
  return l;
}

// The expected weight of a path whose scattering vertices make these steps (the last one
// meets the light): over all 2^(k-1) labels of the bounces before the last, each vertex's
// factor is its kept share where the bounce before it was diffuse, and its label is diffuse
// with odds `diffuse` or, after a diffuse bounce, `diffuse_kept`.
Color enumerated(const std::vector<CausticStep> &steps) {
  const size_t k = steps.size();
  Color sum(0.0f);
  for (uint32_t bits = 0; bits < (1u << (k - 1)); ++bits) {
    Color w(1.0f);
    bool after_diffuse = false;
    for (size_t i = 0; i < k; ++i) {
      const CausticStep &s = steps[i];
      if (after_diffuse) w *= s.kept;
      if (i + 1 == k) break;
      const bool diffuse = (bits >> i) & 1;
      const float odds = after_diffuse ? s.diffuse_kept : s.diffuse;
      w *= diffuse ? odds : 1 - odds;
      after_diffuse = diffuse;
    }
    sum += w;
  }
  return sum;
}

void expect_near(Color a, Color b, float tolerance, const std::string &what) {
  EXPECT_NEAR(a.x, b.x, tolerance) << what;
  EXPECT_NEAR(a.y, b.y, tolerance) << what;
  EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

}  // namespace

// Random paths of up to 10 vertices (mixed and pure reflections, refractions, translucency,
// volume scatterings and straight passes) under each setting of the two switches: the
// forward chain's weight at the last vertex, the backward chain's from the camera and every
// meeting point (a camera side past vertex j, a light side from vertex j + 1 on) equal the
// enumeration.
TEST(CausticsSwitches, ChainIsTheEnumeratedExpectation) {
  rdv::test::Lcg random{777};
  auto next = [&]() { return random.next(); };
  const ScatterKind kinds[] = {ScatterKind::Diffuse,     ScatterKind::Glossy, ScatterKind::Transmission,
                               ScatterKind::Translucent, ScatterKind::Volume, ScatterKind::Transparent};
  for (int trial = 0; trial < 400; ++trial) {
    const LightPathLimits limits = switches(trial % 3 == 1, trial % 3 == 2);
    std::vector<CausticStep> steps;
    const int length = 1 + int(next() * 10);
    for (int i = 0; i < length; ++i) {
      const ScatterKind kind = kinds[int(next() * 6) % 6];
      const float glossy = next() < 0.5f ? next() : -1.0f;
      const Color kept = caustic_share_needed(limits, kind) ? Color(next(), next(), next()) : Color(1.0f);
      steps.push_back(caustic_step(limits, kind, glossy, kept));
    }
    const Color expected = enumerated(steps);
    const std::string what = "trial " + std::to_string(trial);
    CausticState camera;
    for (int i = 0; i + 1 < length; ++i) camera = camera.after(steps[size_t(i)]);
    expect_near(camera.at_last(steps.back().kept), expected, 1e-5f, what + " camera chain");
    // Light side: the rest from vertex j on, for every j; met by the camera side past j - 1.
    CausticState rest = CausticState::last(steps.back().kept);
    for (int j = length - 1; j >= 0; --j) {
      if (j < length - 1) rest = rest.before(steps[size_t(j)]);
      CausticState past;
      for (int i = 0; i < j; ++i) past = past.after(steps[size_t(i)]);
      expect_near(past.meet(rest), expected, 1e-5f, what + " meeting at vertex " + std::to_string(j));
    }
  }
}

// Pure kinds: the weight is 1 or 0 by the plain rule on neighbouring pairs.
TEST(CausticsSwitches, OneKindPerVertexIsThePlainRule) {
  const ScatterKind kinds[] = {ScatterKind::Diffuse, ScatterKind::Glossy, ScatterKind::Transmission,
                               ScatterKind::Translucent, ScatterKind::Volume};
  for (int setting = 0; setting < 3; ++setting) {
    const bool reflective = setting == 1, refractive = setting == 2;
    const LightPathLimits limits = switches(reflective, refractive);
    for (int code = 0; code < 5 * 5 * 5 * 5; ++code) {
      std::vector<ScatterKind> path;
      for (int c = code, i = 0; i < 4; ++i, c /= 5) path.push_back(kinds[c % 5]);
      bool allowed = true;
      for (size_t i = 1; i < path.size(); ++i) {
        const bool after_diffuse = path[i - 1] == ScatterKind::Diffuse || path[i - 1] == ScatterKind::Translucent;
        if (after_diffuse && path[i] == ScatterKind::Glossy && !reflective) allowed = false;
        if (after_diffuse && path[i] == ScatterKind::Transmission && !refractive) allowed = false;
      }
      // What a BSDF of one kind keeps after a diffuse bounce: all of it or nothing.
      auto kept = [&](ScatterKind k) {
        const bool dropped = (k == ScatterKind::Glossy && !reflective) || (k == ScatterKind::Transmission && !refractive);
        return Color(dropped ? 0.0f : 1.0f);
      };
      CausticState s;
      for (size_t i = 0; i + 1 < path.size(); ++i) s = s.after(caustic_step(limits, path[i], -1, kept(path[i])));
      const Color w = s.at_last(kept(path.back()));
      expect_near(w, Color(allowed ? 1.0f : 0.0f), 0.0f, "setting " + std::to_string(setting) + " code " + std::to_string(code));
    }
  }
}

// A Mix of a coloured diffuse and a white glossy closure: after a diffuse bounce, with the
// reflective switch off, f keeps its diffuse part, (1 - fac) f_diffuse, channel by channel;
// with it on, all of f. A Mix of a translucent and a rough glass closure, refracting: the
// refractive switch keeps the translucent part. Delta events by their side's kind.
TEST(CausticsSwitches, ShareIsTheSwitchedOnClosuresPartOfF) {
  const ShadingPoint sp = flat_point();
  const Vec3 wo = normalize(Vec3(0.4f, 0.1f, 0.8f));
  const float fac = 0.35f;
  const std::string diffuse = R"({"type":"diffuse","color":[0.8,0.25,0.05]})";
  const Material mix = material_from_json(R"({"type":"mix","fac":0.35,"shader1":)" + diffuse +
                                          R"(,"shader2":{"type":"glossy","color":[1,1,1],"roughness":0.3}})");
  const Bsdf b = mix.make_bsdf(sp, wo), d = material_from_json(diffuse).make_bsdf(sp, wo);
  for (Vec3 wi : {normalize(Vec3(-0.4f, -0.1f, 0.8f)), normalize(Vec3(0.3f, -0.6f, 0.3f)), Vec3(0, 0, 1)}) {
    const Color f = b.f(wo, wi, TransportMode::Radiance), fd = d.f(wo, wi, TransportMode::Radiance) * (1 - fac);
    const Color share = b.caustic_share(wo, wi, false, false, true);
    expect_near(share * f, fd, 1e-4f * max_component(f), "reflective off, wi.z " + std::to_string(wi.z));
    expect_near(b.caustic_share(wo, wi, false, true, false), Color(1.0f), 0.0f, "reflective on");
  }
  EXPECT_TRUE(is_black(b.caustic_share(wo, Vec3(-wo.x, -wo.y, wo.z), true, false, true)));  // a delta reflection

  const std::string translucent = R"({"type":"translucent","color":[0.3,0.6,0.9]})";
  const Material refracting = material_from_json(R"({"type":"mix","fac":0.5,"shader1":)" + translucent +
                                                 R"(,"shader2":{"type":"glass","roughness":0.4,"ior":1.5}})");
  const Bsdf r = refracting.make_bsdf(sp, wo), t = material_from_json(translucent).make_bsdf(sp, wo);
  const Vec3 below = normalize(Vec3(-0.2f, 0.1f, -0.9f));
  const Color f = r.f(wo, below, TransportMode::Radiance), ft = t.f(wo, below, TransportMode::Radiance) * 0.5f;
  ASSERT_GT(max_component(f - ft), 0.0f);  // the glass refracts toward `below` too
  expect_near(r.caustic_share(wo, below, false, true, false) * f, ft, 1e-4f * max_component(f), "refractive off");
  expect_near(r.caustic_share(wo, below, false, false, true), Color(1.0f), 0.0f, "refractive on");
}

}  // namespace test_caustics_switches
