// Motion blur (scene/motion.h): a square moving under an orthographic camera smears
// exactly as its coverage over the shutter says (and so does a static square seen from
// a moving camera); BDPT and pssmlt agree with the path tracer on a moving scene, path-space
// mlt with BDPT on moving objects, a moving camera and a moving emitter; a scene
// whose shutter is open but where nothing moves renders bit for bit as with the shutter
// closed; bad motion values are errors naming the object.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "motion_blur_stage.h"
#include "render_helpers.h"
#include "statistics.h"

namespace test_motion_blur {

using namespace rdv::test;
using nlohmann::json;

namespace {

// ---- The smear. An orthographic camera looks down at a black square (8 x 12 units) over
// a white world, one unit per pixel (64 x 16 pixels). The square moves along x from -16
// to +16 while the shutter is open; a pixel's value is 1 minus the fraction of the
// shutter for which the square covers it:
//   coverage(x) = max(0, min(x + 4, 16) - max(x - 4, -16)) / 32,
// a trapezoid (0.25 for |x| <= 12, down to 0 at |x| = 20). The pixel filter (1.5 px
// either side, symmetric) leaves a linear function unchanged, so away from the kinks
// every pixel's expectation is the trapezoid's value at its centre.
constexpr int kSmearWidth = 64, kSmearHeight = 16;

double smear_coverage(double x) {
  return std::max(0.0, std::min(x + 4, 16.0) - std::max(x - 4, -16.0)) / 32.0;
}

json smear_scene(const json &square_motion, const json &camera_motion) {
  json camera = {{"type", "orthographic"},
                 {"ortho_scale", kSmearWidth},
                 {"transform", {{"look_at", {{"from", {0, 0, 10}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}},
                 {"shutter_open", -0.25},
                 {"shutter_close", 0.25}};
  if (!camera_motion.is_null()) camera["motion"] = camera_motion;
  json square = {{"name", "square"}, {"shape", {{"type", "quad"}, {"size_x", 8}, {"size_y", 12}}}, {"materials", {"black"}}};
  if (!square_motion.is_null()) square["motion"] = square_motion;
  return {{"settings", {{"width", kSmearWidth}, {"height", kSmearHeight}, {"samples", 256}, {"max_bounces", 1}, {"seed", 3}}},
          {"camera", camera},
          {"world", {{"color", {1, 1, 1}}}},
          {"materials", {{{"name", "black"}, {"type", "diffuse"}, {"color", {0, 0, 0}}}}},
          {"meshes", {square}}};
}

json translate(double x) { return {{"translate", {x, 0, 0}}}; }

// Columns more than 2 px from the trapezoid's kinks (|x| = 12, 20), rows 4..11 (the square
// spans rows 2..13): each column's mean within 0.04 of 1 - coverage. With independent
// samples a column's mean (8 rows x 256 samples, coverage <= 0.25) has a standard error
// of 0.0096, so 0.04 is 4.2 sigma: about 1.5e-3 false alarms over the 56 columns of both
// tests (Sobol-stratified times are far less noisy; the seed is fixed).
// emissive: the square emits 1 over a black world, so a pixel is its coverage itself.
void expect_smear(const Image &img, double direction, const std::string &what, bool emissive = false) {
  ASSERT_TRUE(img.all_finite()) << what;
  int checked = 0;
  double worst = 0;
  for (int i = 0; i < kSmearWidth; ++i) {
    const double x = (i + 0.5 - kSmearWidth / 2) * direction;
    if (std::fabs(std::fabs(x) - 12) < 2 || std::fabs(std::fabs(x) - 20) < 2) continue;
    double sum = 0;
    for (int y = 4; y < 12; ++y) sum += img.rgba[(size_t(y) * kSmearWidth + i) * 4 + 1];
    const double mean = sum / 8, expected = emissive ? smear_coverage(x) : 1 - smear_coverage(x);
    worst = std::max(worst, std::fabs(mean - expected));
    EXPECT_NEAR(mean, expected, 0.04) << what << ": column " << i << " (x = " << x << ")";
    ++checked;
  }
  std::printf("[ motion blur ] %-44s %d columns, worst |mean - expected| %.4f\n", what.c_str(), checked, worst);
}

}  // namespace

// The square moves; two steps (one segment) and three (two segments) give the same
// linear motion.
TEST(MotionBlur, MovingSquareSmearsAsItsCoverage) {
  for (const char *integrator : {"path", "bdpt"}) {
    json settings = {{"integrator", integrator}};
    Image two = render_json(smear_scene(json::array({translate(-16), translate(16)}), nullptr).dump(), settings.dump());
    expect_smear(two, 1, std::string(integrator) + ", 2 steps");
    Image three = render_json(
        smear_scene(json::array({translate(-16), translate(0), translate(16)}), nullptr).dump(), settings.dump());
    expect_smear(three, 1, std::string(integrator) + ", 3 steps");
  }
}

// An emitting square moves with its light (scene/scene.cpp, Scene::light_now): seen
// directly it smears as its coverage too, path and BDPT (whose s = 0 strategies weigh
// the camera's hit by the light's density where the square is at that time).
TEST(MotionBlur, MovingEmitterSmearsAsItsCoverage) {
  json scene = smear_scene(json::array({translate(-16), translate(16)}), nullptr);
  scene["world"]["color"] = {0, 0, 0};
  scene["materials"][0] = {{"name", "black"}, {"type", "emission"}, {"color", {1, 1, 1}}, {"strength", 1}};
  for (const char *integrator : {"path", "bdpt"})
    expect_smear(render_json(scene.dump(), json{{"integrator", integrator}}.dump()), 1,
                 std::string(integrator) + ", emitting square", true);
}

// A static square seen by a camera moving the other way smears the same (mirrored).
TEST(MotionBlur, MovingCameraSmearsAsItsCoverage) {
  auto camera_at = [](double x) {
    return json{{"look_at", {{"from", {x, 0, 10}}, {"to", {x, 0, 0}}, {"up", {0, 1, 0}}}}};
  };
  Image img = render_json(smear_scene(nullptr, json::array({camera_at(16), camera_at(-16)})).dump());
  expect_smear(img, 1, "path, moving camera");
}

namespace {

constexpr int kSize = 32, kRuns = 6;
// Seven comparisons of 4x4 blocks (BDPT and pssmlt against the path tracer; the moving
// emitter's path and BDPT against still renders; mlt against BDPT on three scenes): 1%
// false alarms over the file, Sidak-corrected per block.
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / (7 * 16));

// A red box sliding and a glossy ball rising and turning, over a floor, under an area lamp.
json moving_scene() {
  const json box_motion = {{{"translate", {-1.8, 0, 0.4}}}, {{"translate", {-1, 0, 0.4}}}, {{"translate", {-0.2, 0, 0.4}}}};
  const json ball = {{"name", "ball"},
                     {"shape", {{"type", "sphere"}, {"radius", 0.5}, {"segments", 24}}},
                     {"materials", {"blue"}},
                     {"transform", {{"translate", {1, 0.3, 0.5}}}},
                     {"motion",
                      {{{"translate", {1, 0.3, 0.5}}, {"rotate", {0, 0, -30}}},
                       {{"translate", {1, 0.3, 1.3}}, {"rotate", {0, 0, 30}}}}}};
  return motion_blur_stage(kSize, box_motion, ball);
}

}  // namespace

// One path contribution however sampled: BDPT's strategies (light tracing and
// connections at the camera sample's time) and pssmlt's (the time a primary sample,
// mutated) agree with the path tracer, block by block (Welch's t-test over K runs).
TEST(MotionBlur, BdptAndPssmltMatchPathTracing) {
  const std::string scene = moving_scene().dump();
  auto pt = seeded_renders(scene, json{{"integrator", "path"}, {"samples", 64}}.dump(), kRuns, 1);
  auto bd = seeded_renders(scene, json{{"integrator", "bdpt"}, {"samples", 32}}.dump(), kRuns, 1001);
  BlockComparison c = compare_blocks(bd, pt, kSize, kSize, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << "bdpt: " << c.detail;
  std::printf("[ motion blur ] bdpt vs path: %s\n", c.detail.substr(0, 120).c_str());
  auto mlt = seeded_renders(scene, json{{"integrator", "pssmlt"}, {"samples", 64}, {"mlt_bootstrap", 16}}.dump(), kRuns, 2001);
  c = compare_blocks(mlt, pt, kSize, kSize, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << "pssmlt: " << c.detail;
  std::printf("[ motion blur ] pssmlt vs path: %s\n", c.detail.substr(0, 120).c_str());
}

namespace {

// A small emitting square sliding 3 units along x at 1.2 over the floor (the only light):
// the floor's light is the mean over the shutter of where the square is.
constexpr int kEmitterPositions = 16;
json moving_emitter_scene(const json &motion, double x) {
  json lamp = {{"name", "lamp"},
               {"shape", {{"type", "quad"}, {"size", 0.5}}},
               {"materials", {"lamp"}},
               {"transform", {{"translate", {x, 0, 1.2}}, {"rotate", {180, 0, 0}}}}};
  if (!motion.is_null()) lamp["motion"] = motion;
  return emitter_stage(kSize, lamp);
}

}  // namespace

// Next-event estimation, BDPT's light subpaths and every MIS density place the emitter at
// the sample's shutter time: path and BDPT renders of the sliding square match the mean of
// renders of it standing at 16 evenly spaced points of its slide (the midpoint rule's
// error, about 1e-3 of the floor's light, is far below a block's noise), block by block.
// (Before, a moving emitter was rendered still, where its transform put it.)
TEST(MotionBlur, MovingEmitterLightsAsTheMeanOfItsPositions) {
  auto at = [](double x) { return json{{"translate", {x, 0, 1.2}}, {"rotate", {180, 0, 0}}}; };
  const std::string moving = moving_emitter_scene(json::array({at(-1.5), at(1.5)}), 0).dump();
  std::vector<std::vector<double>> still(kRuns);
  for (int k = 0; k < kEmitterPositions; ++k) {
    const double x = -1.5 + 3.0 * (k + 0.5) / kEmitterPositions;
    auto runs = seeded_renders(moving_emitter_scene(nullptr, x).dump(), json{{"integrator", "path"}, {"samples", 8}}.dump(),
                               kRuns, uint32_t(100 * k + 7));
    for (int r = 0; r < kRuns; ++r) {
      still[r].resize(runs[r].size());
      for (size_t i = 0; i < runs[r].size(); ++i) still[r][i] += runs[r][i] / kEmitterPositions;
    }
  }
  for (const char *integrator : {"path", "bdpt"}) {
    auto blurred = seeded_renders(moving, json{{"integrator", integrator}, {"samples", 128}}.dump(), kRuns, 3001);
    BlockComparison c = compare_blocks(blurred, still, kSize, kSize, 8, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << integrator << ": " << c.detail;
    std::printf("[ motion blur ] moving emitter, %s vs the mean of 16 still renders: %s\n", integrator,
                c.detail.substr(0, 120).c_str());
  }
}

// Motion blur switched on (the shutter open) in a scene where nothing moves: no time is
// drawn, every ray is traced as before, bit for bit. Also one motion step (no motion).
TEST(MotionBlur, StaticSceneWithShutterOpenIsBitIdentical) {
  for (const char *integrator : {"path", "bdpt", "mlt"}) {
    json closed = load_scene("cornell_box.json");
    closed["settings"].update({{"width", 32}, {"height", 32}, {"samples", 8}, {"integrator", integrator}});
    json open = closed;
    open["camera"]["shutter_open"] = -0.25;
    open["camera"]["shutter_close"] = 0.25;
    open["meshes"][0]["motion"] = json::array({json{{"translate", {0, 0, 0}}}});
    Image a = render_json(closed.dump()), b = render_json(open.dump());
    ASSERT_TRUE(a.all_finite());
    EXPECT_EQ(a.rgba, b.rgba) << integrator;
  }
}

// The shutter closed (shutter_open = shutter_close, or the loader's motion_blur off): a
// moving scene renders as the same scene without its "motion" keys, bit for bit.
TEST(MotionBlur, ClosedShutterIgnoresMotion) {
  json moving = moving_scene();
  moving["settings"]["samples"] = 4;
  json still = moving;
  for (json &m : still["meshes"]) m.erase("motion");
  moving["camera"]["shutter_close"] = -0.25;
  EXPECT_EQ(render_json(moving.dump()).rgba, render_json(still.dump()).rgba);
}

TEST(MotionBlur, BadValuesNameTheObject) {
  SceneHandle scene;
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  uint32_t material, mesh, instance;
  ASSERT_EQ(rdv_scene_add_material(scene.s, "grey", R"({"type":"diffuse"})", &material), RDV_OK);
  ASSERT_EQ(rdv_scene_add_mesh(scene.s, "Plane.007", positions, 3, nullptr, nullptr, indices, 1, nullptr, material, &mesh),
            RDV_OK);
  float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(rdv_scene_add_instance(scene.s, mesh, identity, &instance), RDV_OK);
  float steps[32];
  for (int k = 0; k < 32; ++k) steps[k] = identity[k % 16];
  steps[16 + 3] = std::nanf("");
  EXPECT_EQ(rdv_scene_set_instance_motion(scene.s, instance, steps, 2), RDV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(rdv_last_error()).find("object 'Plane.007'"), std::string::npos) << rdv_last_error();
  EXPECT_NE(std::string(rdv_last_error()).find("not finite"), std::string::npos) << rdv_last_error();
  steps[16 + 3] = 1;
  EXPECT_EQ(rdv_scene_set_instance_motion(scene.s, instance, steps, 2), RDV_OK);
  EXPECT_EQ(rdv_scene_set_instance_motion(scene.s, instance, steps, 1u << 30), RDV_ERROR_LIMIT);  // nothing read
  // A shutter that closes before it opens.
  EXPECT_NE(rdv_scene_set_camera(scene.s, R"({"shutter_open": 0.25, "shutter_close": -0.25})"), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("shutter_close"), std::string::npos) << rdv_last_error();
  // Motion through a zero scale: static, with a warning naming the object.
  float collapse[32];
  for (int k = 0; k < 32; ++k) collapse[k] = identity[k % 16];
  collapse[16] = collapse[21] = collapse[26] = -1;  // a point reflection: the blend passes zero
  EXPECT_EQ(rdv_scene_set_instance_motion(scene.s, instance, collapse, 2), RDV_OK);
}

// Path-space Metropolis (integrators/mlt/path_space.h): the shutter time is a coordinate of
// the path, drawn anew by large steps and kept by every other mutation; f, the densities and
// the lights at the path's time. Against BDPT (one time per camera sample) on the sliding box
// and rising ball, the same seen by a camera that moves while the shutter is open, and the
// glowing square sliding over the floor (Scene::light_now): 4x4 blocks of 8x8 (Welch's t-test,
// 1% false alarms over the file) and the mean of the K runs within 3.3 standard errors (1e-3
// each). Deterministic: fixed seeds.
TEST(MotionBlur, PathSpaceMltMatchesBdpt) {
  json moving_camera = moving_scene();
  moving_camera["camera"]["motion"] = json::array({json{{"look_at", {{"from", {-0.6, -5, 2.0}}, {"to", {0, 0, 0.6}}}}},
                                                   json{{"look_at", {{"from", {0.6, -5, 2.4}}, {"to", {0, 0, 0.6}}}}}});
  const json emitter = moving_emitter_scene(
      json::array({json{{"translate", {-1.5, 0, 1.2}}, {"rotate", {180, 0, 0}}},
                   json{{"translate", {1.5, 0, 1.2}}, {"rotate", {150, 0, 0}}}}),
      0);
  const std::pair<const char *, json> scenes[] = {
      {"moving objects", moving_scene()}, {"moving camera", moving_camera}, {"moving emitter", emitter}};
  for (const auto &[what, scene] : scenes) {
    auto bd = seeded_renders(scene.dump(), json{{"integrator", "bdpt"}, {"samples", 32}}.dump(), kRuns, 4001);
    auto mlt = seeded_renders(
        scene.dump(), json{{"integrator", "mlt"}, {"samples", 64}, {"mlt_bootstrap", 16}, {"mlt_chains", 64}}.dump(),
        kRuns, 5001);
    BlockComparison c = compare_blocks(mlt, bd, kSize, kSize, 8, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
    BrightnessComparison b = compare_brightness(mlt, bd);
    EXPECT_LT(std::fabs(b.z), 3.3) << what << ": mlt mean " << b.mean_a << " vs bdpt " << b.mean_b;
    std::printf("[ motion blur ] mlt vs bdpt, %-15s mean ratio %.4f +- %.4f; %s\n", what, b.mean_a / b.mean_b,
                b.error / b.mean_b, c.detail.substr(0, 100).c_str());
  }
}

}  // namespace test_motion_blur
