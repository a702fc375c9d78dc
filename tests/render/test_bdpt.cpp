// Bidirectional path tracing against the reference path tracer.
// Images are rendered K times with independent seeds; every 8x8 block is compared
// with Welch's t-test. False-alarm rate: 1% for the whole file's block comparisons
// (Sidak-corrected per block); seeds are fixed, so each verdict is reproducible.
#include <gtest/gtest.h>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "render_helpers.h"
#include "statistics.h"

namespace test_bdpt {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kRuns = 8;
constexpr int kBlockTestsInFile = 13 * 36 + 4 * 4;  // consistency scenes + strategy images
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / kBlockTestsInFile);

std::vector<double> luminance_sum(const Image &img) {
  std::vector<double> v(size_t(img.width) * img.height);
  for (size_t i = 0; i < v.size(); ++i) v[i] = double(img.rgba[4 * i]) + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
  return v;
}

void expect_same_image(const json &scene, const std::string &what, int samples_pt, int samples_bdpt,
                       const char *mis = "power") {
  // The path tracer's runs are rendered once per process: the weightings' tests
  // (BalanceHeuristic, LafortuneWillemsWeights) share CornellBox's and GlossyAndEveryLightType's.
  const json p = {{"width", 48}, {"height", 48}, {"max_bounces", 8}, {"integrator", "path"}, {"samples", samples_pt}};
  const auto &pt = seeded_renders_once(scene.dump(), p.dump(), kRuns, 1);
  const json s = {{"width", 48}, {"height", 48}, {"max_bounces", 8}, {"mis", mis}, {"integrator", "bdpt"},
                  {"samples", samples_bdpt}};
  auto bd = seeded_renders(scene.dump(), s.dump(), kRuns, 1001);
  BlockComparison c = compare_blocks(bd, pt, 48, 48, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  const BrightnessComparison b = compare_brightness(bd, pt);  // each side's share of the noise
  std::printf("[ bdpt vs path ] %-12s errors of the run means: bdpt %.4f, path %.4f; %s\n", what.c_str(),
              b.error_a / b.mean_a, b.error_b / b.mean_b, c.detail.substr(0, 120).c_str());
}

// Two BDPT weightings (both share each path among the strategies that can make it) on
// a scene path tracing cannot converge on.
void expect_same_bdpt_image(const json &scene, const std::string &what, int samples, const char *mis_a,
                            const char *mis_b) {
  json s = {{"width", 48}, {"height", 48}, {"max_bounces", 8}, {"integrator", "bdpt"}, {"samples", samples}};
  s["mis"] = mis_a;
  auto a = seeded_renders(scene.dump(), s.dump(), kRuns, 1);
  s["mis"] = mis_b;
  auto b = seeded_renders(scene.dump(), s.dump(), kRuns, 1001);
  BlockComparison c = compare_blocks(a, b, 48, 48, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  std::printf("[ bdpt weights ] %-12s %s\n", what.c_str(), c.detail.substr(0, 120).c_str());
}

}  // namespace

TEST(BdptVsPath, CornellBox) { expect_same_image(load_scene("cornell_box.json"), "cornell", 64, 32); }

// Glossy spheres and a gold box under spot, point, area and sun lights and a world.
TEST(BdptVsPath, GlossyAndEveryLightType) { expect_same_image(load_scene("light_types.json"), "glossy", 64, 32); }

// Smooth and rough glass under an area light and a world.
TEST(BdptVsPath, GlassSpheres) { expect_same_image(load_scene("glass_sphere.json"), "glass", 128, 32); }

// The caustic scene with a lamp large enough for path tracing to converge too.
TEST(BdptVsPath, GlassCaustic) {
  json scene = load_scene("caustic.json");
  scene["lights"][0]["radius"] = 0.4;
  expect_same_image(scene, "caustic", 256, 32);
}

// A room lit only through a door gap.
TEST(BdptVsPath, DoorGap) { expect_same_image(load_scene("door_gap.json"), "door gap", 256, 32); }

// Mix Shaders by the viewing direction (Fresnel, Layer Weight, Backfacing: bsdfs/view_factor.h)
// on the Cornell box's blocks and back wall, on a ball (a Fresnel over a mirror: a delta lobe
// whose weight follows the camera side) and on a half-transparent two-sided card. Light subpaths reach these surfaces from the lamp's side; the
// factors are taken at each pair's camera-side direction, so BDPT's strategies sum to the path
// tracer's image (with the factor at the direction a Bsdf was built toward they would not).
TEST(BdptVsPath, ViewDependentMixes) {
  json scene = load_scene("cornell_box.json");
  auto mix = [](json fac, json a, json b) { return json{{"type", "mix"}, {"fac", fac}, {"shader1", a}, {"shader2", b}}; };
  const json white = {{"type", "diffuse"}, {"color", {0.73, 0.73, 0.73}}};
  auto glossy = [](double roughness) { return json{{"type", "glossy"}, {"color", {0.9, 0.9, 0.9}}, {"roughness", roughness}}; };
  json fresnel_gloss = mix({{"node", "fresnel"}, {"ior", 1.5}}, white, glossy(0.15));
  json facing = mix({{"node", "layer_weight"}, {"output", "facing"}, {"blend", 0.3}}, white, glossy(0.4));
  json layer_fresnel = mix({{"node", "layer_weight"}, {"blend", 0.5}}, white, glossy(0.25));
  json mirror_ball = mix({{"node", "fresnel"}, {"ior", 1.45}}, json{{"type", "diffuse"}, {"color", {0.63, 0.065, 0.05}}},
                         json{{"type", "glossy"}, {"roughness", 0}, {"distribution", "SHARP"}});
  fresnel_gloss["name"] = "fresnel_gloss";
  facing["name"] = "facing";
  layer_fresnel["name"] = "layer_fresnel";
  mirror_ball["name"] = "mirror_ball";
  for (json *m : {&fresnel_gloss, &facing, &layer_fresnel, &mirror_ball}) scene["materials"].push_back(*m);
  for (json &mesh : scene["meshes"]) {
    if (mesh["name"] == "short_block") mesh["materials"] = {"fresnel_gloss"};
    if (mesh["name"] == "tall_block") mesh["materials"] = {"facing"};
    if (mesh["name"] == "back") mesh["materials"] = {"layer_fresnel"};
  }
  scene["meshes"].push_back({{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.3}, {"segments", 32}}},
                             {"materials", {"mirror_ball"}}, {"transform", {{"translate", {-0.45, -0.45, 0.3}}}}});
  // A half-transparent two-sided card (Geometry > Backfacing beside a Transparent BSDF), tilted
  // so that the camera sees its back and the lamp its front.
  json leaf = mix(0.4, json{{"type", "transparent"}},
                  mix({{"node", "backfacing"}}, json{{"type", "diffuse"}, {"color", {0.2, 0.7, 0.2}}}, glossy(0.3)));
  leaf["name"] = "leaf";
  scene["materials"].push_back(leaf);
  scene["meshes"].push_back({{"name", "card"}, {"shape", {{"type", "quad"}, {"size", 0.5}}}, {"materials", {"leaf"}},
                             {"transform", {{"translate", {0.5, -0.6, 1.2}}, {"rotate", {-60, 0, 0}}}}});
  expect_same_image(scene, "view mixes", 128, 32);
}

// The other weightings share each path among the strategies too (sum one), so they
// converge to the same image: the balance heuristic, and Lafortune & Willems' weights by
// the specularity of camera-path vertices, which must also hand the share of "the camera
// path finds the lamp" to next-event estimation for point, spot and sun lamps (light_types).
// Not glass_sphere: there Lafortune & Willems' weights give heavy-tailed connections
// through rough glass a large share, and the image is dark until their tail is sampled
// (docs/bdpt.md: variance, not bias; too slow to converge for a test).
TEST(BdptVsPath, BalanceHeuristic) {
  expect_same_image(load_scene("cornell_box.json"), "balance", 64, 32, "balance");
  expect_same_image(load_scene("light_types.json"), "balance gl", 64, 32, "balance");
}
TEST(BdptVsPath, LafortuneWillemsWeights) {
  expect_same_image(load_scene("cornell_box.json"), "l&w cornell", 64, 32, "lafortune_willems");
  expect_same_image(load_scene("light_types.json"), "l&w glossy", 64, 32, "lafortune_willems");
  json delta = load_scene("light_types.json");  // point, spot and sun made delta lights
  for (json &light : delta["lights"]) {
    if (light.contains("radius")) light["radius"] = 0;
    if (light.contains("angle")) light["angle"] = 0;
  }
  expect_same_image(delta, "l&w delta", 64, 32, "lafortune_willems");
}

// A point lamp's caustic under a smooth glass ball: only light tracing (t = 1) makes those
// paths, so Lafortune & Willems' weights must give it the share their camera-side split
// cannot place; against the power heuristic (path tracing never finds this caustic).
TEST(BdptWeights, LafortuneWillemsKeepsThePointLampCaustic) {
  json scene = load_scene("caustic.json");
  scene["lights"][0]["radius"] = 0;
  expect_same_bdpt_image(scene, "l&w caustic", 32, "power", "lafortune_willems");
}

// Each strategy on its own, without MIS, converges to the same depth-2 image: on the
// Cornell box every strategy can make every path of that length.
TEST(BdptStrategies, EachAloneMatchesPathTracingAtDepthTwo) {
  json scene = load_scene("cornell_box.json");
  json s = {{"width", 32}, {"height", 32}, {"integrator", "path"}, {"samples", 64}};
  std::vector<std::vector<double>> depth2;
  for (int k = 0; k < kRuns; ++k) {
    s["seed"] = 7 + k;
    s["max_bounces"] = 2;
    auto two = luminance_sum(render_json(scene.dump(), s.dump()));
    s["max_bounces"] = 1;  // same seed: the same first bounce, so the difference is exactly depth 2
    auto one = luminance_sum(render_json(scene.dump(), s.dump()));
    for (size_t i = 0; i < two.size(); ++i) two[i] -= one[i];
    depth2.push_back(two);
  }
  for (auto [st_s, st_t] : {std::pair{0, 4}, {1, 3}, {2, 2}, {3, 1}}) {
    json b = {{"width", 32}, {"height", 32}, {"integrator", "bdpt"}, {"samples", st_s == 0 ? 256 : 64},
              {"max_bounces", 2}, {"strategy", {st_s, st_t}}, {"strategy_unweighted", true}};
    auto runs = seeded_renders(scene.dump(), b.dump(), kRuns, 500 + 10 * st_s);
    BlockComparison c = compare_blocks(runs, depth2, 32, 32, 16, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << "strategy s=" << st_s << " t=" << st_t << ": " << c.detail;
  }
}

namespace {
std::string sphere_scene(double albedo, double emission, const std::string &light, int segments) {
  json j = {{"camera", {{"focal_length", 20}, {"transform", {{"look_at", {{"from", {0, 0, 0}}, {"to", {1, 0.3, 0.2}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "shell"}, {"type", "diffuse"}, {"color", {albedo, albedo, albedo}},
                            {"emission", {emission, emission, emission}}}}},
            {"meshes", {{{"name", "sphere"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", segments}, {"smooth", false}}},
                         {"materials", {"shell"}}}}}};
  if (!light.empty()) j["lights"] = json::array({json::parse(light)});
  return j.dump();
}
void expect_mean(const Image &img, double expected, const char *what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  MeanEstimate m = pixel_mean(img, 1);
  double z = (m.mean - expected) / std::hypot(m.standard_error, 1e-5 * expected);
  EXPECT_LT(std::fabs(z), 4.5) << what << ": mean " << m.mean << " expected " << expected << " (se " << m.standard_error << ")";
}
const char *kBdpt16 = R"({"integrator":"bdpt","width":16,"height":16,"samples":64,"max_bounces":200})";
}  // namespace

// The analytic furnaces of the foundation, with BDPT (z-tests at |z| < 4.5).
TEST(BdptFurnace, ClosedEmittingSphere) {
  expect_mean(render_json(sphere_scene(0.5, 1.0, "", 24), kBdpt16), 2.0, "albedo 0.5");
}
TEST(BdptFurnace, PointLightInDiffuseSphere) {
  std::string light = json{{"type", "point"}, {"position", {0, 0, 0}}, {"radius", 0}, {"power", 4 * M_PI * M_PI}}.dump();
  expect_mean(render_json(sphere_scene(0.5, 0.0, light, 256), kBdpt16), 1.0, "point light in sphere");
}
TEST(BdptFurnace, WhiteSphereUnderUniformWorld) {
  json j = {{"camera", {{"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0.8, 0.8, 0.8}}}},
            {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
            {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"smooth", false}}}, {"materials", {"white"}}}}}};
  expect_mean(render_json(j.dump(), kBdpt16), 0.8, "white sphere in uniform world");
}

// No NaN or Inf anywhere: a point lamp a hair above a surface, an area lamp touching a
// wall, a camera inside a glass ball, an orthographic camera and depth of field.
TEST(BdptRobustness, ExtremeConfigurationsStayFinite) {
  std::vector<json> scenes;
  scenes.push_back({{"camera", {{"transform", {{"look_at", {{"from", {0, -3, 0.5}}, {"to", {0, 0, 0}}}}}}}},
                    {"world", {{"color", {0, 0, 0}}}},
                    {"materials", {{{"name", "grey"}, {"type", "diffuse"}}, {{"name", "mirror"}, {"type", "glossy"}, {"roughness", 0}}}},
                    {"meshes", {{{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"grey"}}},
                                {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.3}}}, {"materials", {"mirror"}},
                                 {"transform", {{"translate", {0.6, 0, 0.3}}}}}}},
                    {"lights", {{{"type", "point"}, {"position", {0, 0, 1e-5}}, {"radius", 0}, {"power", 1e4}},
                                {{"type", "point"}, {"position", {0.3, 0, 1e-4}}, {"radius", 1e-6}, {"power", 1e4}},
                                {{"type", "area"}, {"position", {-0.5, 0, 1e-6}}, {"direction", {0, 0, -1}}, {"size", 1e-3}, {"power", 1e3}}}}});
  json inside_glass = load_scene("glass_sphere.json");
  inside_glass["camera"]["transform"] = {{"look_at", {{"from", {-0.9, 0, 0.8}}, {"to", {0, 0, 0.5}}}}};
  scenes.push_back(inside_glass);
  json ortho = load_scene("cornell_box.json");
  ortho["camera"] = {{"type", "orthographic"}, {"ortho_scale", 2.2}, {"transform", {{"look_at", {{"from", {0, -3.9, 1}}, {"to", {0, 0, 1}}}}}}};
  scenes.push_back(ortho);
  json dof = load_scene("instanced_pebbles.json");
  scenes.push_back(dof);
  for (const json &scene : scenes) {
    Image img = render_json(scene.dump(), R"({"integrator":"bdpt","width":24,"height":24,"samples":8})");
    EXPECT_TRUE(img.all_finite());
    EXPECT_EQ(img.progress.samples_dropped, 0u);
  }
}

// Splats are added in tile order after each pass: BDPT images are bit-identical on
// one and two threads too.
TEST(BdptDeterminism, SameImageOnOneAndTwoThreads) {
  std::string scene = load_scene("cornell_box.json").dump();
  Image a = render_json(scene, R"({"integrator":"bdpt","width":40,"height":40,"samples":4,"threads":1})");
  Image b = render_json(scene, R"({"integrator":"bdpt","width":40,"height":40,"samples":4,"threads":2})");
  EXPECT_EQ(0, std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)));
}

// An orthographic camera cannot be reached by light paths; BDPT still converges to the
// path tracer's image through its other strategies.
TEST(BdptVsPath, OrthographicCamera) {
  json scene = load_scene("cornell_box.json");
  scene["camera"] = {{"type", "orthographic"}, {"ortho_scale", 2.2}, {"transform", {{"look_at", {{"from", {0, -3.9, 1}}, {"to", {0, 0, 1}}}}}}};
  expect_same_image(scene, "ortho", 64, 32);
}

}  // namespace test_bdpt
