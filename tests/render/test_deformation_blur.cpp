// Deformation motion blur (scene/motion.h): a mesh whose vertices move over the shutter
// renders as the same motion done by an instance's transform steps (Embree blends vertex
// steps and transform steps alike, linearly); a mesh with one step, or any steps with
// the shutter closed, renders bit for bit as without them; bad steps are errors naming
// the mesh; an emitting mesh deforms with its light; BDPT and pssmlt agree with the path
// tracer on a deforming mesh, path-space mlt refuses it.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "motion_blur_stage.h"
#include "render_helpers.h"
#include "statistics.h"

namespace test_deformation_blur {

using namespace rdv::test;
using nlohmann::json;

namespace {

// ---- The smear: a black 8 x 12 square over a white world under an orthographic camera,
// one unit per pixel, moving along x from -16 to +16 while the shutter is open, either by
// its vertices or by its transform. Both are traced with the same samples (same seed, the
// same shutter time per sample), so they differ only where rounding puts a sample's hit
// on the other side of an edge: the two images are compared column by column, and each
// with the square's coverage over the shutter (as MotionBlur.MovingSquareSmearsAsItsCoverage).
constexpr int kWidth = 64, kHeight = 16;

json square_vertices(double x) {
  return json::array({x - 4, -6, 0, x + 4, -6, 0, x + 4, 6, 0, x - 4, 6, 0});
}

json smear_scene(const json &square) {
  json camera = {{"type", "orthographic"},
                 {"ortho_scale", kWidth},
                 {"transform", {{"look_at", {{"from", {0, 0, 10}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}},
                 {"shutter_open", -0.25},
                 {"shutter_close", 0.25}};
  return {{"settings", {{"width", kWidth}, {"height", kHeight}, {"samples", 256}, {"max_bounces", 1}, {"seed", 3}}},
          {"camera", camera},
          {"world", {{"color", {1, 1, 1}}}},
          {"materials", {{{"name", "black"}, {"type", "diffuse"}, {"color", {0, 0, 0}}}}},
          {"meshes", {square}}};
}

json square_mesh() {
  return {{"name", "square"}, {"positions", square_vertices(0)}, {"indices", {0, 1, 2, 0, 2, 3}}, {"materials", {"black"}}};
}

// Column means over rows 4..11 (the square spans rows 2..13), green channel.
std::vector<double> column_means(const Image &img) {
  std::vector<double> means(kWidth, 0.0);
  for (int i = 0; i < kWidth; ++i) {
    for (int y = 4; y < 12; ++y) means[i] += img.rgba[(size_t(y) * kWidth + i) * 4 + 1] / 8;
  }
  return means;
}

}  // namespace

// Vertices that move as a translation smear as the same translation by transform steps
// (2 steps, and 3 with the middle one at the frame), path and bdpt. Tolerances: a column
// of the two images differs by at most 0.01 (the samples are the same, only an edge
// sample's rounding differs: deterministic, no false alarms); each column within 0.04 of
// 1 - coverage away from the kinks (4.2 sigma of a column's mean for independent
// samples: 1.5e-3 false alarms over the test's 112 columns, as the transformation test).
TEST(DeformationBlur, MovingVerticesSmearAsTransformMotion) {
  for (const char *integrator : {"path", "bdpt"}) {
    const json settings = {{"integrator", integrator}};
    for (int steps : {2, 3}) {
      json by_vertices = square_mesh(), by_transform = square_mesh();
      by_vertices["motion_positions"] = json::array();
      by_transform["motion"] = json::array();
      for (int k = 0; k < steps; ++k) {
        const double x = -16 + 32.0 * k / (steps - 1);
        by_vertices["motion_positions"].push_back(square_vertices(x));
        by_transform["motion"].push_back({{"translate", {x, 0, 0}}});
      }
      Image a = render_json(smear_scene(by_vertices).dump(), settings.dump());
      Image b = render_json(smear_scene(by_transform).dump(), settings.dump());
      ASSERT_TRUE(a.all_finite());
      EXPECT_EQ(a.warnings.find("deformation"), std::string::npos) << a.warnings;
      const std::vector<double> ca = column_means(a), cb = column_means(b);
      double worst_pair = 0, worst_coverage = 0;
      for (int i = 0; i < kWidth; ++i) {
        worst_pair = std::max(worst_pair, std::fabs(ca[i] - cb[i]));
        const double x = i + 0.5 - kWidth / 2;
        if (std::fabs(std::fabs(x) - 12) < 2 || std::fabs(std::fabs(x) - 20) < 2) continue;
        const double coverage = std::max(0.0, std::min(x + 4, 16.0) - std::max(x - 4, -16.0)) / 32.0;
        worst_coverage = std::max(worst_coverage, std::fabs(ca[i] - (1 - coverage)));
        EXPECT_NEAR(ca[i], 1 - coverage, 0.04) << integrator << ", " << steps << " steps, column " << i;
      }
      EXPECT_LE(worst_pair, 0.01) << integrator << ", " << steps << " steps";
      std::printf("[ deformation blur ] %s, %d steps: worst column vs transform %.4f, vs coverage %.4f\n",
                  integrator, steps, worst_pair, worst_coverage);
    }
  }
}

// An instance that moves and a mesh that deforms at once (Embree blends both): the square's
// vertices slide -8 .. 8 and its transform -8 .. 8, together the same -16 .. 16 smear.
TEST(DeformationBlur, DeformingMeshOnAMovingInstanceAddsBothMotions) {
  json both = square_mesh(), by_transform = square_mesh();
  both["motion_positions"] = json::array({square_vertices(-8), square_vertices(8)});
  both["motion"] = json::array({json{{"translate", {-8, 0, 0}}}, json{{"translate", {8, 0, 0}}}});
  by_transform["motion"] = json::array({json{{"translate", {-16, 0, 0}}}, json{{"translate", {16, 0, 0}}}});
  const std::vector<double> a = column_means(render_json(smear_scene(both).dump()));
  const std::vector<double> b = column_means(render_json(smear_scene(by_transform).dump()));
  double worst = 0;
  for (int i = 0; i < kWidth; ++i) worst = std::max(worst, std::fabs(a[i] - b[i]));
  EXPECT_LE(worst, 0.01);  // the same samples: only an edge sample's rounding may differ
  std::printf("[ deformation blur ] moving instance + deforming mesh vs one transform: worst column %.4f\n", worst);
}

namespace {

constexpr int kSize = 32, kRuns = 6;
// Six comparisons of 4x4 blocks (four of the deforming ball, two of the deforming
// lamp): 1% false alarms over the file, Sidak-corrected per block.
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / (6 * 16));

// A smooth UV sphere of radius 0.5 placed by `to_world` (3x4 row-major, a rotation and a
// translation): positions and normals, 3 floats per vertex.
struct SphereArrays {
  json positions = json::array(), normals = json::array(), indices = json::array();
};
SphereArrays sphere(const double m[3][4]) {
  constexpr int kRings = 12, kSegments = 24;
  constexpr double kPi = 3.14159265358979323846;
  SphereArrays s;
  for (int r = 0; r <= kRings; ++r)
    for (int g = 0; g <= kSegments; ++g) {
      const double theta = kPi * r / kRings, phi = 2 * kPi * g / kSegments;
      const double n[3] = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      for (int i = 0; i < 3; ++i) {
        const double rotated = m[i][0] * n[0] + m[i][1] * n[1] + m[i][2] * n[2];
        s.positions.push_back(0.5 * rotated + m[i][3]);
        s.normals.push_back(rotated);
      }
    }
  for (int r = 0; r < kRings; ++r)
    for (int g = 0; g < kSegments; ++g) {
      const int a = r * (kSegments + 1) + g, b = a + kSegments + 1;
      if (r > 0) s.indices.insert(s.indices.end(), {a, b, a + 1});
      if (r < kRings - 1) s.indices.insert(s.indices.end(), {a + 1, b, b + 1});
    }
  return s;
}

// The ball at shutter step k of 3: rising from z = 0.5 to 1.3 and turning -30 .. 30
// degrees about z, at (1, 0.3).
void ball_placement(int k, double m[3][4]) {
  const double angle = (-30.0 + 30.0 * k) * 3.14159265358979323846 / 180, c = std::cos(angle), s = std::sin(angle);
  const double rows[3][4] = {{c, -s, 0, 1}, {s, c, 0, 0.3}, {0, 0, 1, 0.5 + 0.4 * k}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = rows[i][j];
}

// A red box and the glossy ball over a floor under an area lamp; the ball's motion given
// by its transform steps or by its vertices (and normals) at the same steps.
json ball_scene(bool deform) {
  double at[3][4];
  ball_placement(1, at);
  double origin[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  SphereArrays frame = sphere(deform ? at : origin);
  json ball = {{"name", "ball"},
               {"positions", frame.positions},
               {"normals", frame.normals},
               {"indices", frame.indices},
               {"materials", {"blue"}}};
  json positions = json::array(), normals = json::array(), transforms = json::array();
  for (int k = 0; k < 3; ++k) {
    ball_placement(k, at);
    SphereArrays step = sphere(at);
    positions.push_back(step.positions);
    normals.push_back(step.normals);
    json matrix = json::array();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) matrix.push_back(at[i][j]);
    matrix.insert(matrix.end(), {0, 0, 0, 1});
    transforms.push_back(matrix);
  }
  if (deform) {
    ball["motion_positions"] = positions;
    ball["motion_normals"] = normals;
  } else {
    ball["transform"] = transforms[1];
    ball["motion"] = transforms;
  }
  return motion_blur_stage(kSize, nullptr, ball);
}

}  // namespace

// A glossy ball that rises and turns, by its vertices and normals, matches the same
// motion by transform steps (path, independent seeds), and BDPT (light subpaths and
// connections at the camera sample's time, hitting the deformed ball) matches the path
// tracer, and so does pssmlt (the time one more primary sample, mutated): Welch's t-test
// per 8x8 block over 6 runs each.
TEST(DeformationBlur, DeformingBallMatchesTransformMotionEveryIntegrator) {
  const std::string deforming = ball_scene(true).dump(), moving = ball_scene(false).dump();
  auto by_transform = seeded_renders(moving, json{{"integrator", "path"}, {"samples", 64}}.dump(), kRuns, 1);
  auto by_vertices = seeded_renders(deforming, json{{"integrator", "path"}, {"samples", 64}}.dump(), kRuns, 101);
  BlockComparison c = compare_blocks(by_vertices, by_transform, kSize, kSize, 8, kAlphaPerBlock);
  EXPECT_EQ(c.failed, 0) << "path: " << c.detail;
  std::printf("[ deformation blur ] vertices vs transform, path: %s\n", c.detail.substr(0, 120).c_str());
  // Each integrator against path's deforming renders (path-space mlt: the path's shutter
  // time places every vertex on the deformed mesh).
  const struct { json settings; uint32_t seed; } others[] = {
      {{{"integrator", "bdpt"}, {"samples", 32}}, 1001},
      {{{"integrator", "pssmlt"}, {"samples", 64}, {"mlt_bootstrap", 16}}, 2001},
      {{{"integrator", "mlt"}, {"samples", 64}, {"mlt_bootstrap", 16}}, 3001},
  };
  for (const auto &other : others) {
    const std::string name = other.settings["integrator"];
    c = compare_blocks(seeded_renders(deforming, other.settings.dump(), kRuns, other.seed), by_vertices, kSize, kSize,
                       8, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << name << ": " << c.detail;
    std::printf("[ deformation blur ] %s vs path, deforming: %s\n", name.c_str(), c.detail.substr(0, 120).c_str());
  }
}

// One step is no deformation, and steps with the shutter closed are ignored: both render
// bit for bit as the mesh without steps (a static scene pays nothing).
TEST(DeformationBlur, OneStepOrClosedShutterIsBitIdentical) {
  for (const char *integrator : {"path", "bdpt"}) {
    json plain = ball_scene(true);
    plain["settings"].update({{"samples", 8}, {"integrator", integrator}});
    json &ball = plain["meshes"][2];
    const json steps = ball["motion_positions"], normals = ball["motion_normals"];
    ball.erase("motion_positions");
    ball.erase("motion_normals");
    json one_step = plain;
    one_step["meshes"][2]["motion_positions"] = json::array({steps[1]});
    json closed = plain;
    closed["meshes"][2]["motion_positions"] = steps;
    closed["meshes"][2]["motion_normals"] = normals;
    closed["camera"]["shutter_close"] = -0.25;
    json still = plain;
    still["camera"]["shutter_close"] = -0.25;
    const Image a = render_json(plain.dump()), b = render_json(one_step.dump());
    ASSERT_TRUE(a.all_finite());
    EXPECT_EQ(a.rgba, b.rgba) << integrator << ": one step";
    EXPECT_EQ(render_json(still.dump()).rgba, render_json(closed.dump()).rgba) << integrator << ": shutter closed";
  }
}

TEST(DeformationBlur, BadStepsNameTheMesh) {
  SceneHandle scene;
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  uint32_t material, mesh;
  ASSERT_EQ(rdv_scene_add_material(scene.s, "grey", R"({"type":"diffuse"})", &material), RDV_OK);
  ASSERT_EQ(rdv_scene_add_mesh(scene.s, "Cloth.003", positions, 3, nullptr, nullptr, indices, 1, nullptr, material, &mesh),
            RDV_OK);
  float steps[18];
  for (int k = 0; k < 18; ++k) steps[k] = positions[k % 9];
  // A vertex count other than the mesh's.
  EXPECT_EQ(rdv_scene_set_mesh_motion(scene.s, mesh, steps, nullptr, 2, 2), RDV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(rdv_last_error()).find("mesh 'Cloth.003'"), std::string::npos) << rdv_last_error();
  EXPECT_NE(std::string(rdv_last_error()).find("2 vertices"), std::string::npos) << rdv_last_error();
  // A NaN in the second step.
  steps[9 + 4] = std::nanf("");
  EXPECT_EQ(rdv_scene_set_mesh_motion(scene.s, mesh, steps, nullptr, 3, 2), RDV_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(rdv_last_error()).find("mesh 'Cloth.003'"), std::string::npos) << rdv_last_error();
  EXPECT_NE(std::string(rdv_last_error()).find("step 1, vertex 1"), std::string::npos) << rdv_last_error();
  steps[9 + 4] = 0;
  EXPECT_EQ(rdv_scene_set_mesh_motion(scene.s, mesh, steps, nullptr, 3, 2), RDV_OK);
  EXPECT_EQ(rdv_scene_set_mesh_motion(scene.s, mesh, steps, nullptr, 3, 1u << 30), RDV_ERROR_LIMIT);  // nothing read
  EXPECT_EQ(rdv_scene_set_mesh_motion(scene.s, 7, steps, nullptr, 3, 2), RDV_ERROR_INVALID_ARGUMENT);
  // In a scene file: a step of the wrong length, and steps of normals that disagree.
  json file = smear_scene(square_mesh());
  file["meshes"][0]["motion_positions"] = json::array({square_vertices(-1), json::array({0, 0, 0})});
  Image img = render_json(file.dump());
  EXPECT_NE(img.warnings.find("mesh 'square': 'motion_positions' step 1 has 3 numbers"), std::string::npos)
      << img.warnings;
  file["meshes"][0]["motion_positions"] = json::array({square_vertices(-1), square_vertices(1)});
  file["meshes"][0]["motion_normals"] = json::array({square_vertices(0)});
  img = render_json(file.dump());
  EXPECT_NE(img.warnings.find("'motion_normals' has 1 steps, 'motion_positions' 2"), std::string::npos) << img.warnings;
}

// An emitting mesh deforms with its light (Scene::light_now): a 0.5 square lamp whose
// vertices slide 3 units over the floor lights it as the same slide by transform steps,
// path and BDPT (next-event points, light subpaths and MIS densities where the vertices
// are at the sample's time), block by block.
TEST(DeformationBlur, EmissiveMeshDeformsWithItsLight) {
  auto quad_at = [](double x) {
    return json::array({x - 0.25, -0.25, 1.2, x - 0.25, 0.25, 1.2, x + 0.25, 0.25, 1.2, x + 0.25, -0.25, 1.2});
  };
  json by_vertices = {{"name", "Glow"}, {"positions", quad_at(0)}, {"indices", {0, 1, 2, 0, 2, 3}}, {"materials", {"lamp"}}};
  by_vertices["motion_positions"] = json::array({quad_at(-1.5), quad_at(1.5)});
  json by_transform = by_vertices;
  by_transform.erase("motion_positions");
  by_transform["motion"] = json::array({json{{"translate", {-1.5, 0, 0}}}, json{{"translate", {1.5, 0, 0}}}});
  const std::string deforming = emitter_stage(kSize, by_vertices).dump(), moving = emitter_stage(kSize, by_transform).dump();
  Image check = render_json(deforming, R"({"samples": 4})");
  EXPECT_EQ(check.warnings.find("Glow"), std::string::npos) << check.warnings;
  auto reference = seeded_renders(moving, json{{"integrator", "path"}, {"samples", 64}}.dump(), kRuns, 1);
  for (const char *integrator : {"path", "bdpt"}) {
    auto runs = seeded_renders(deforming, json{{"integrator", integrator}, {"samples", 64}}.dump(), kRuns, 301);
    BlockComparison c = compare_blocks(runs, reference, kSize, kSize, 8, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << integrator << ": " << c.detail;
    std::printf("[ deformation blur ] emitting square by vertices, %s vs by transform (path): %s\n", integrator,
                c.detail.substr(0, 120).c_str());
  }
}

}  // namespace test_deformation_blur
