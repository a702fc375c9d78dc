// Cycles' Light Paths (integrators/light_path_limits.h): per-kind bounce limits, the
// caustics switches and the direct / indirect clamps, in the path tracer and in every
// BDPT strategy. The path tracer is checked against closed relations (diffuse bounces 0
// is direct light; a limit that never binds changes nothing, bit for bit); BDPT against
// the path tracer, K runs each, Welch's t-test on every 8x8 block (1% false alarms over
// the file, Sidak-corrected per block; fixed seeds, so each verdict is reproducible).
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <string>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_light_path_limits {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kRuns = 8;
constexpr int kSize = 48;
// Fourteen BDPT-vs-path, two pssmlt / mmlt-vs-path, one mlt-vs-path and seven mlt-vs-BDPT
// comparisons of 6x6 blocks (the check that unfiltered BDPT differs expects failures and
// takes no share).
constexpr int kBlockTestsInFile = 24 * 36;
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / kBlockTestsInFile);

json small(json settings) {
  settings["width"] = kSize;
  settings["height"] = kSize;
  return settings;
}

// K seeded renders of `integrator` with the limits (Metropolis: a small bootstrap, 64 chains).
// Deterministic, so a reference several comparisons of one test ask for (the same scene,
// settings and seeds) is rendered once per process.
std::vector<std::vector<double>> runs_of(const json &scene, const json &limits, const char *integrator, int samples,
                                         uint32_t first_seed) {
  json s = small(limits);
  s["integrator"] = integrator;
  s["samples"] = samples;
  if (std::strcmp(integrator, "mlt") == 0) {
    s["mlt_bootstrap"] = 4;
    s["mlt_chains"] = 64;
  }
  return seeded_renders_once(scene.dump(), s.dump(), kRuns, first_seed);
}

// `test` (integrator, samples) against `reference` on every 8x8 block; with `brightness`
// also the runs' mean within 3.3 standard errors of the reference's (false alarms 1e-3).
void expect_same_image(const json &scene, const json &limits, const std::string &what,
                       std::pair<const char *, int> reference, std::pair<const char *, int> test,
                       bool brightness = false) {
  auto ref = runs_of(scene, limits, reference.first, reference.second, 1);
  auto got = runs_of(scene, limits, test.first, test.second, std::strcmp(test.first, "mlt") == 0 ? 2001 : 1001);
  BlockComparison c = compare_blocks(got, ref, kSize, kSize, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  // Each side's relative error of its mean printed: how the test's noise is shared.
  const BrightnessComparison b = compare_brightness(got, ref);
  if (brightness)
    EXPECT_LT(std::fabs(b.z), 3.3) << what << ": mean " << b.mean_a << " vs " << reference.first << " " << b.mean_b;
  char mean[160];
  std::snprintf(mean, sizeof mean, "mean ratio %.4f +- %.4f (z %.2f; errors %s %.4f, %s %.4f); ",
                b.mean_a / b.mean_b, b.error / b.mean_b, b.z, test.first, b.error_a / b.mean_a, reference.first,
                b.error_b / b.mean_b);
  std::printf("[ light paths ] %s %-28s %s%s\n", test.first, what.c_str(), mean,
              c.detail.substr(0, 120).c_str());
}

void expect_bdpt_matches_path(const json &scene, const json &limits, const std::string &what, int samples_pt,
                              int samples_bdpt) {
  expect_same_image(scene, limits, what, {"path", samples_pt}, {"bdpt", samples_bdpt});
}

// Path-space MLT (integrators/mlt/path_space.h) against BDPT: the limits make f = 0 outside
// them, so the chains' image is BDPT's with the same limits. Sample counts: each side's
// error of its mean is printed; where the chains' runs spread 5-20x more than BDPT's at
// 32-64 spp, BDPT renders 8-16 (its share of the comparison's variance stays a few %).
void expect_mlt_matches_bdpt(const json &scene, const json &limits, const std::string &what, int samples_bdpt,
                             int mutations) {
  expect_same_image(scene, limits, what, {"bdpt", samples_bdpt}, {"mlt", mutations}, true);
}

double mean_of(const Image &img) { return (img.channel_mean(0) + img.channel_mean(1) + img.channel_mean(2)) / 3; }

}  // namespace

// Cycles' diffuse bounces 0 is direct light only: in the all-diffuse Cornell box that is
// max_bounces 1 (one scattering vertex), sample for sample.
TEST(LightPathLimits, DiffuseZeroIsDirectLightInThePathTracer) {
  json scene = load_scene("cornell_box.json");
  json s = small({{"integrator", "path"}, {"samples", 16}, {"seed", 3}, {"max_bounces", 1}});
  Image direct = render_json(scene.dump(), s.dump());
  s["max_bounces"] = 12;
  s["diffuse_bounces"] = 0;
  Image limited = render_json(scene.dump(), s.dump());
  ASSERT_TRUE(limited.all_finite());
  EXPECT_EQ(std::memcmp(direct.rgba.data(), limited.rgba.data(), direct.rgba.size() * sizeof(float)), 0);
}

// Limits that never bind classify every path and keep all of them: the image is the
// same, bit for bit (path tracing and BDPT).
TEST(LightPathLimits, LimitsThatNeverBindChangeNothing) {
  json scene = load_scene("glass_sphere.json");
  for (const char *integrator : {"path", "bdpt"}) {
    json s = small({{"integrator", integrator}, {"samples", 8}, {"seed", 5}, {"max_bounces", 6}});
    Image plain = render_json(scene.dump(), s.dump());
    s["diffuse_bounces"] = s["glossy_bounces"] = s["transmission_bounces"] = s["volume_bounces"] = 6;
    Image classified = render_json(scene.dump(), s.dump());
    EXPECT_EQ(std::memcmp(plain.rgba.data(), classified.rgba.data(), plain.rgba.size() * sizeof(float)), 0)
        << integrator;
  }
}

// Filter Glossy (integrators/filter_glossy.h): 0 is the image without it, bit for bit; on,
// the glass ball's caustic on the floor (seen after the floor's diffuse bounce) changes,
// and nothing seen straight from the camera that has no glossy lobe after a bounce: the
// path tracer only.
TEST(LightPathLimits, FilterGlossyZeroChangesNothingAndOnBlursCaustics) {
  json scene = load_scene("caustic.json");
  json s = small({{"integrator", "path"}, {"samples", 16}, {"seed", 3}});
  Image plain = render_json(scene.dump(), s.dump());
  s["filter_glossy"] = 0;
  Image zero = render_json(scene.dump(), s.dump());
  EXPECT_EQ(std::memcmp(plain.rgba.data(), zero.rgba.data(), plain.rgba.size() * sizeof(float)), 0);
  s["filter_glossy"] = 1;
  Image filtered = render_json(scene.dump(), s.dump());
  ASSERT_TRUE(filtered.all_finite());
  int changed = 0;
  for (size_t i = 0; i < plain.rgba.size(); ++i) changed += plain.rgba[i] != filtered.rgba[i];
  EXPECT_GT(changed, 0);
  s["filter_glossy"] = -1;
  EXPECT_THROW(render_json(scene.dump(), s.dump()), std::runtime_error);
}

// Filter Glossy in BDPT (integrators/filter_glossy.h): the glass ball's caustic on the
// floor, blurred by Filter Glossy 2, is the path tracer's in BDPT (its light-tracing
// strategies through the blurred ball give way to the connections and next-event
// estimation at the blurred glass) and in pssmlt and mmlt, which sample BDPT's strategies,
// and in path-space mlt (the blur a function of each path's camera-side prefix, in f and in
// both sides' densities; the mean too); unfiltered, BDPT's caustic differs (the test sees the
// filter). Light_types' glossy and gold spheres (GGX lobes smoother than the blur) with
// Filter Glossy 1 too, BDPT against the path tracer and mlt against BDPT.
TEST(LightPathLimits, FilterGlossyInBdptAndMetropolisMatchesPath) {
  json caustic = load_scene("caustic.json");
  const json filtered = {{"max_bounces", 8}, {"filter_glossy", 2}};
  expect_bdpt_matches_path(caustic, filtered, "filter glossy 2 caustic", 256, 4);
  expect_bdpt_matches_path(load_scene("light_types.json"), {{"max_bounces", 8}, {"filter_glossy", 1}},
                           "filter glossy 1 light_types", 32, 16);
  for (const char *integrator : {"pssmlt", "mmlt"})
    expect_same_image(caustic, filtered, "filter glossy 2 caustic", {"path", 256}, {integrator, 64});
  expect_same_image(caustic, filtered, "filter glossy 2 caustic", {"path", 256}, {"mlt", 64}, true);
  expect_mlt_matches_bdpt(load_scene("light_types.json"), {{"max_bounces", 8}, {"filter_glossy", 1}},
                          "filter glossy 1 light_types", 32, 64);
  auto pt = runs_of(caustic, filtered, "path", 256, 1);
  json unfiltered = filtered;
  unfiltered["filter_glossy"] = 0;
  BlockComparison c = compare_blocks(runs_of(caustic, unfiltered, "bdpt", 64, 3001), pt, kSize, kSize, 8,
                                     kAlphaPerBlock);
  EXPECT_GT(c.failed, 0) << "unfiltered BDPT should differ from the filtered path tracer: " << c.detail;
  std::printf("[ light paths ] unfiltered bdpt vs filtered path: %s\n", c.detail.substr(0, 120).c_str());
}

// Every BDPT strategy keeps the paths the path tracer keeps: diffuse bounces 1 in the
// Cornell box; glossy and transmission limits on glass and glossy spheres; volume bounces in
// fog. Samples sized by each side's printed error of its mean: where one side's was 3-15x
// the other's, the more precise side renders fewer (the comparison's error grows < 6%).
TEST(LightPathLimits, BdptMatchesPathWithBounceLimits) {
  expect_bdpt_matches_path(load_scene("cornell_box.json"), {{"max_bounces", 8}, {"diffuse_bounces", 1}},
                           "cornell diffuse 1", 64, 32);
  expect_bdpt_matches_path(load_scene("glass_sphere.json"),
                           {{"max_bounces", 8}, {"transmission_bounces", 1}, {"glossy_bounces", 0}},
                           "glass transmission 1 glossy 0", 64, 32);
  expect_bdpt_matches_path(load_scene("fog_spot.json"), {{"max_bounces", 8}, {"volume_bounces", 1}},
                           "fog volume 1", 128, 8);
}

// Fog around a spot lamp with a radius, at volume bounces 0, 1 and unlimited: BDPT (its
// light subpaths carry most of the weight there) matches the path tracer (next-event
// estimation and hits) in brightness and block by block. Both see the lamp as one sphere
// (lights/sphere_lamp.h); when light subpaths emitted the sphere and the other strategies
// a disk facing each fog point, BDPT was 1.16x the path tracer here at every limit (the
// "volume bounces 1 excess" was this, not the limits). Brightness false alarms 1e-3 each.
TEST(LightPathLimits, FogAroundASphereLampBdptMatchesPath) {
  json scene = load_scene("fog_spot.json");
  scene["lights"][0]["radius"] = 0.3;
  for (int volume : {0, 1, -1}) {
    json limits = {{"max_bounces", 8}};
    if (volume >= 0) limits["volume_bounces"] = volume;
    expect_same_image(scene, limits, "fog sphere spot volume " + std::to_string(volume), {"path", 128}, {"bdpt", 8},
                      true);
  }
}

// Mixed reflections: every wall of the Cornell box a Principled BSDF (roughness 0.3), whose
// bounces Cycles counts as diffuse or glossy by the closure it sampled (Bsdf::glossy_odds,
// BounceCounts). Each path is kept with the odds its mixed reflections fit both limits: the
// path tracer, every BDPT strategy (which sees the same path's bounces from both ends) and
// path-space MLT keep the same share (brightness too). Diffuse 0 / glossy 1 is the case
// that sees the light subpath's side: with a light vertex counted by its dominant kind,
// BDPT was 0.994 of the path tracer (z -3.3, one block) and passed under diffuse 1 / glossy 0.
TEST(LightPathLimits, MixedReflectionsKeepTheSameShareInEveryIntegrator) {
  json scene = load_scene("cornell_box.json");
  for (json &m : scene["materials"])
    if (m["type"] == "diffuse")
      m = {{"name", m["name"]}, {"type", "principled"}, {"base_color", m["color"]}, {"roughness", 0.3}};
  const json glossy_only = {{"max_bounces", 8}, {"diffuse_bounces", 0}, {"glossy_bounces", 1}};
  expect_same_image(scene, glossy_only, "principled diffuse 0 glossy 1", {"path", 64}, {"bdpt", 32}, true);
  expect_same_image(scene, {{"max_bounces", 8}, {"diffuse_bounces", 1}, {"glossy_bounces", 0}},
                    "principled diffuse 1 glossy 0", {"path", 64}, {"bdpt", 32}, true);
  expect_mlt_matches_bdpt(scene, glossy_only, "principled diffuse 0 glossy 1", 32, 64);
}

// The caustics switches on mixtures (caustics_switches.h): the Principled Cornell box with
// the reflective switch off keeps, after a diffuse bounce, only each wall's diffuse part,
// with the odds the bounce before it was diffuse. The path tracer (forward chain), every BDPT
// strategy (light subpaths carry the chain backward and connections meet the two) and
// path-space MLT weigh each path alike (brightness too). Judged by the BSDFs' dominant kind
// (diffuse), no path lost anything: the image was 2-3% brighter than Cycles'
// (blender.light_paths_principled_caustics).
TEST(LightPathLimits, CausticsOffOnMixturesInEveryIntegrator) {
  json scene = load_scene("cornell_box.json");
  for (json &m : scene["materials"])
    if (m["type"] == "diffuse")
      m = {{"name", m["name"]}, {"type", "principled"}, {"base_color", m["color"]}, {"roughness", 0.3}};
  const json off = {{"max_bounces", 8}, {"caustics_reflective", false}};
  expect_same_image(scene, off, "principled reflective caustics off", {"path", 64}, {"bdpt", 32}, true);
  expect_mlt_matches_bdpt(scene, off, "principled reflective caustics off", 32, 64);
}

// With the caustics switches off, the floor under the glass ball loses the light that
// reaches it through the ball after a diffuse bounce; BDPT (whose light paths make the
// caustic) agrees with the path tracer. With the same seed the switches only remove
// contributions: no pixel gets brighter, and the caustic's light is gone.
TEST(LightPathLimits, CausticsOffInEveryStrategy) {
  json scene = load_scene("caustic.json");
  scene["lights"][0]["radius"] = 0.4;  // large enough for path tracing to converge
  json off = {{"max_bounces", 8}, {"caustics_refractive", false}, {"caustics_reflective", false}};
  expect_bdpt_matches_path(scene, {{"max_bounces", 8}, {"caustics_refractive", false}}, "refractive caustics off",
                           256, 32);
  expect_bdpt_matches_path(scene, off, "caustics off", 256, 32);
  for (const char *integrator : {"path", "bdpt"}) {
    json s = small({{"integrator", integrator}, {"samples", 16}, {"seed", 1}, {"max_bounces", 8}});
    Image on = render_json(scene.dump(), s.dump());
    s.update(off);
    Image without = render_json(scene.dump(), s.dump());
    double removed = 0, total = 0;
    int brighter = 0;
    for (size_t i = 0; i < on.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      total += on.rgba[i];
      removed += on.rgba[i] - without.rgba[i];
      if (without.rgba[i] > on.rgba[i] * (1 + 1e-5f) + 1e-6f) ++brighter;
    }
    EXPECT_EQ(brighter, 0) << integrator;
    EXPECT_GT(removed, 0.003 * total) << integrator << ": the caustic should be gone";
    std::printf("[ light paths ] %s: caustics off removes %.2f%% of the image\n", integrator, 100 * removed / total);
  }
}

// Clamping indirect light to nearly nothing leaves direct light (at most one scattering
// vertex) alone: the path tracer's image is then that of max_bounces 1 plus contributions
// of at most 1e-6 each; clamped direct light never exceeds its cap per sample.
TEST(LightPathLimits, ClampIndirectKeepsDirectLight) {
  json scene = load_scene("cornell_box.json");
  json s = small({{"integrator", "path"}, {"samples", 16}, {"seed", 9}, {"max_bounces", 2}});
  s["max_bounces"] = 2;
  Image two = render_json(scene.dump(), s.dump());
  s["clamp_indirect"] = 1e-6;
  Image clamped = render_json(scene.dump(), s.dump());
  s["max_bounces"] = 1;
  s.erase("clamp_indirect");
  Image direct = render_json(scene.dump(), s.dump());
  ASSERT_TRUE(clamped.all_finite());
  EXPECT_NEAR(mean_of(clamped), mean_of(direct), 1e-4);
  EXPECT_GT(mean_of(two), 1.05 * mean_of(direct));  // the bounce the clamp removed mattered
  s["max_bounces"] = 8;
  s["clamp_direct"] = 0.01;  // RGB sum per contribution
  s["clamp_indirect"] = 0.01;
  for (const char *integrator : {"path", "bdpt"}) {
    s["integrator"] = integrator;
    Image capped = render_json(scene.dump(), s.dump());
    ASSERT_TRUE(capped.all_finite());
    EXPECT_GT(mean_of(capped), 0.0) << integrator;
    EXPECT_LT(mean_of(capped), 0.5 * mean_of(two)) << integrator;
  }
}

// Path-space MLT: the per-kind limits and the caustics switches as BDPT has them (a diffuse
// limit in the Cornell box, the caustics switched off under the glass ball, one volume
// bounce in fog lit by a spot with a radius); limits that never bind change nothing, bit for
// bit; clamps are refused, naming why (a chain has no per-sample estimate to cap).
TEST(LightPathLimits, PathSpaceMltMatchesBdpt) {
  expect_mlt_matches_bdpt(load_scene("cornell_box.json"), {{"max_bounces", 8}, {"diffuse_bounces", 1}},
                          "cornell diffuse 1", 32, 64);
  json caustic = load_scene("caustic.json");
  caustic["lights"][0]["radius"] = 0.4;
  expect_mlt_matches_bdpt(caustic, {{"max_bounces", 8}, {"caustics_refractive", false}, {"caustics_reflective", false}},
                          "caustics off", 8, 64);
  expect_mlt_matches_bdpt(load_scene("fog_spot.json"), {{"max_bounces", 8}, {"volume_bounces", 1}}, "fog volume 1",
                          8, 64);
}

TEST(LightPathLimits, PathSpaceMltLimitsThatNeverBindChangeNothing) {
  json scene = load_scene("cornell_box.json");
  json s = small({{"integrator", "mlt"}, {"samples", 8}, {"seed", 5}, {"max_bounces", 6}, {"mlt_chains", 16}});
  Image plain = render_json(scene.dump(), s.dump());
  s["diffuse_bounces"] = s["glossy_bounces"] = s["transmission_bounces"] = s["volume_bounces"] = 6;
  Image classified = render_json(scene.dump(), s.dump());
  EXPECT_EQ(std::memcmp(plain.rgba.data(), classified.rgba.data(), plain.rgba.size() * sizeof(float)), 0);
}

TEST(LightPathLimits, PathSpaceMltRefusesClampsNamingWhy) {
  json scene = load_scene("cornell_box.json");
  try {
    render_json(scene.dump(), small({{"integrator", "mlt"}, {"samples", 1}, {"clamp_indirect", 10}}).dump());
    ADD_FAILURE() << "mlt accepted clamp_indirect";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("clamp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("estimate"), std::string::npos) << e.what();
  }
}

// Transparent max bounces (light_path_limits.h), as Cycles 3.4 counts passes: a scattering
// vertex needs at most the limit behind it and its shadow rays pass only what is left; an
// emitter seen straight through one more than the limit still shows. Ortho camera and sun
// straight down through full-size Transparent BSDF cards: the path tracer's estimate is
// exact (every pass certain, the sun a delta), so each value is checked to 1e-5.
static json sun_under_cards(int cards, const json &floor) {
  json meshes = json::array({{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}}});
  for (int i = 0; i < cards; ++i)
    meshes.push_back({{"name", "card" + std::to_string(i)}, {"shape", {{"type", "quad"}, {"size", 4}}},
                      {"materials", {"clear"}}, {"transform", {{"translate", {0, 0, 0.5 + 0.5 * i}}}}});
  json f = floor;
  f["name"] = "floor";
  return {{"camera", {{"type", "orthographic"}, {"ortho_scale", 0.2}, {"clip_start", 0.01},
                      {"transform", {{"look_at", {{"from", {0, 0.001, 3}}, {"to", {0, 0, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {f, {{"name", "clear"}, {"type", "transparent"}}}},
          {"meshes", meshes},
          {"lights", {{{"type", "sun"}, {"strength", 3}, {"angle", 0}, {"direction", {0, 0, -1}}}}}};
}

static double mean_under_cards(const json &scene, int limit) {
  json s = {{"width", 4}, {"height", 4}, {"samples", 4}, {"max_bounces", 1}};
  if (limit >= 0) s["transparent_max_bounces"] = limit;
  Image img = render_json(scene.dump(), s.dump());
  EXPECT_TRUE(img.all_finite());
  return img.channel_mean(0);
}

TEST(LightPathLimits, TransparentMaxBouncesInThePathTracer) {
  // A white floor lit by the sun through two cards, seen through the same two: 4 passes.
  const json lit = sun_under_cards(2, {{"type", "diffuse"}, {"color", {0.8, 0.8, 0.8}}});
  const double sunlit = 3 * 0.8 / M_PI;
  EXPECT_NEAR(mean_under_cards(lit, -1), sunlit, 1e-5) << "no limit";
  EXPECT_NEAR(mean_under_cards(lit, 4), sunlit, 1e-5) << "4 passes at a limit of 4";
  EXPECT_EQ(mean_under_cards(lit, 3), 0.0) << "4 passes at a limit of 3: the shadow ray is blocked";
  EXPECT_EQ(mean_under_cards(lit, 1), 0.0) << "the floor seen through 2 at a limit of 1 does not scatter";
  // An emitting floor seen through three cards: it shows down to a limit of 2 (Cycles stops
  // the path on it, its emission counted), not at 1.
  const json glow = sun_under_cards(3, {{"type", "emission"}, {"color", {1, 1, 1}}, {"strength", 2}});
  EXPECT_NEAR(mean_under_cards(glow, 2), 2.0, 1e-5) << "emitter seen through 3 at a limit of 2";
  EXPECT_EQ(mean_under_cards(glow, 1), 0.0) << "emitter behind 3 at a limit of 1";
}

// A floor lit by an area lamp through a staircase of six Transparent BSDF cards (x of the
// image behind 0 .. 6 of them, the lamp's light through about as many), an emitting strip
// on it: at a limit of 4 the floor is lit behind 0 .. 2 cards (as many passes each way) and
// the strip shows behind up to 5. BDPT (the lamp found through the cards by its camera walk, or
// light tracing) matches the path tracer (shadow rays through them); path-space MLT matches
// BDPT with two cards at a limit of 1 (lit behind none, the strip seen behind both): its
// chains are slow to find light through the cards (docs/mlt.md). A limit that never binds
// changes nothing, bit for bit.
static json staircase(int cards) {
  json meshes = json::array(
      {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}},
       {{"name", "strip"}, {"shape", {{"type", "quad"}, {"size", 1}}}, {"materials", {"glow"}},
        {"transform", {{"translate", {0, 0.5, 0.001}}, {"scale", {3, 0.15, 1}}}}}});
  for (int i = 1; i <= cards; ++i)  // card i covers x <= 0.6 - 0.2 i
    meshes.push_back({{"name", "card" + std::to_string(i)}, {"shape", {{"type", "quad"}, {"size", 4}}},
                      {"materials", {"clear"}}, {"transform", {{"translate", {-1.4 - 0.2 * i, 0, 0.15 + 0.12 * i}}}}});
  return {{"camera", {{"type", "perspective"}, {"focal_length", 40}, {"clip_start", 0.01},
                      {"transform", {{"look_at", {{"from", {0, -0.4, 3}}, {"to", {0, 0, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.8, 0.8, 0.8}}},
                         {{"name", "clear"}, {"type", "transparent"}, {"color", {0.9, 0.95, 1}}},
                         {{"name", "glow"}, {"type", "emission"}, {"color", {1, 0.6, 0.3}}, {"strength", 2}}}},
          {"meshes", meshes},
          {"lights", {{{"type", "area"}, {"power", 60}, {"size", 0.6}, {"position", {0.3, -0.6, 2.2}},
                       {"direction", {0, 0.3, -1}}}}}};
}

TEST(LightPathLimits, TransparentMaxBouncesInBdptAndMetropolis) {
  expect_bdpt_matches_path(staircase(6), {{"max_bounces", 12}, {"transparent_max_bounces", 4}},
                           "transparent 4, six cards", 128, 64);
  expect_mlt_matches_bdpt(staircase(2), {{"max_bounces", 12}, {"transparent_max_bounces", 1}},
                          "transparent 1, two cards", 8, 256);
  for (const char *integrator : {"path", "bdpt", "mlt"}) {
    json s = small({{"integrator", integrator}, {"samples", 8}, {"seed", 5}, {"max_bounces", 12}, {"mlt_chains", 16}});
    Image plain = render_json(staircase(3).dump(), s.dump());
    s["transparent_max_bounces"] = 6;  // at most 3 passes each way
    Image limited = render_json(staircase(3).dump(), s.dump());
    EXPECT_EQ(std::memcmp(plain.rgba.data(), limited.rgba.data(), plain.rgba.size() * sizeof(float)), 0) << integrator;
  }
}

// The clamps count scattering vertices: light through the staircase's cards onto the floor
// is direct light (the floor is its one scattering vertex; a plane lights nothing of itself
// and the world is black), so Clamp Indirect at 1e-6 changes nothing, bit for bit. BDPT
// counted the cards passed as bounces and clamped that light away (Cycles' default Clamp
// Indirect 10 darkened Blender scenes behind alpha cards).
TEST(LightPathLimits, PassesThroughCardsAreNotBouncesForTheClamps) {
  for (const char *integrator : {"path", "bdpt"}) {
    json s = small({{"integrator", integrator}, {"samples", 8}, {"seed", 5}, {"max_bounces", 12}});
    Image plain = render_json(staircase(3).dump(), s.dump());
    s["clamp_indirect"] = 1e-6;
    Image clamped = render_json(staircase(3).dump(), s.dump());
    ASSERT_GT(mean_of(plain), 0.0);
    EXPECT_EQ(std::memcmp(plain.rgba.data(), clamped.rgba.data(), plain.rgba.size() * sizeof(float)), 0) << integrator;
  }
}

TEST(LightPathLimits, BadValuesAreRefusedWithTheirName) {
  json scene = load_scene("cornell_box.json");
  for (json bad : {json{{"diffuse_bounces", -1}}, json{{"glossy_bounces", 5000}}, json{{"clamp_direct", -1}},
                   json{{"transparent_max_bounces", -2}}}) {
    try {
      render_json(scene.dump(), small(bad).dump());
      ADD_FAILURE() << bad.dump() << " was accepted";
    } catch (const std::runtime_error &e) {
      EXPECT_NE(std::string(e.what()).find(bad.begin().key()), std::string::npos) << bad.dump() << ": " << e.what();
    }
  }
}

// Cycles' Light > Max Bounces (Light::lights_path): a lamp lights only the paths of at most
// that many bounces, as the scene's Max Bounces would for it alone (Blender 3.4 measured:
// a lamp's max bounces 0 and 1 render bit for bit as the scene's 0 and 1). The Cornell box
// lit by lamps with a radius (so every strategy meets them) instead of its mesh lamp.
json cornell_lamps(int limited_bounces) {
  json scene = load_scene("cornell_box.json");
  json meshes = json::array();
  for (const auto &m : scene["meshes"])
    if (m["name"] != "lamp") meshes.push_back(m);
  scene["meshes"] = meshes;
  scene["lights"] = json::array({{{"type", "point"}, {"position", {0.3, 0.0, 1.8}}, {"power", 60}, {"radius", 0.1}},
                                 {{"type", "point"}, {"position", {-0.4, 0.2, 1.7}}, {"power", 30}, {"radius", 0.1}}});
  if (limited_bounces >= 0) scene["lights"][0]["max_bounces"] = limited_bounces;
  return scene;
}

// The path tracer: one lamp with max bounces 0 (1) is the scene's max bounces 1 (2 scattering
// vertices) sample for sample: every decision draws from a fixed dimension, and the longer
// paths add nothing.
TEST(LightPathLimits, LampMaxBouncesIsTheScenesForItsLightInThePathTracer) {
  for (int bounces : {0, 1}) {
    json one = cornell_lamps(bounces);
    one["lights"].erase(1);
    json s = small({{"integrator", "path"}, {"samples", 16}, {"seed", 3}, {"max_bounces", 12}});
    Image limited = render_json(one.dump(), s.dump());
    one["lights"][0].erase("max_bounces");
    s["max_bounces"] = bounces + 1;
    Image scene_wide = render_json(one.dump(), s.dump());
    EXPECT_EQ(std::memcmp(limited.rgba.data(), scene_wide.rgba.data(), limited.rgba.size() * sizeof(float)), 0)
        << "lamp max bounces " << bounces;
    s["max_bounces"] = 12;
    EXPECT_GT(mean_of(render_json(cornell_lamps(-1).dump(), s.dump())), 1.2 * mean_of(limited)) << "the limit binds";
  }
}

// Every strategy keeps the same paths: BDPT against the path tracer, mlt against BDPT, with
// a lamp at max bounces 0 and 1 beside an unlimited one.
TEST(LightPathLimits, LampMaxBouncesInBdptAndMetropolis) {
  const json limits = {{"max_bounces", 8}};
  for (int bounces : {0, 1}) {
    const json scene = cornell_lamps(bounces);
    const std::string what = "lamp max bounces " + std::to_string(bounces);
    expect_same_image(scene, limits, what, {"path", 128}, {"bdpt", 32}, true);
    expect_mlt_matches_bdpt(scene, limits, what, 8, 64);
  }
}

}  // namespace test_light_path_limits
