// Grid media rendered end to end: Beer-Lambert through a grid (dense and VDB), an
// albedo-1 cloud under a uniform world, extremes, VDB files with empty tiles and
// missing files. z-tests on the mean over pixels at |z| < 4.5 (false alarm < 1e-5 per
// check); fixed seeds.
#include <gtest/gtest.h>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include "media_grids.h"
#include "render_helpers.h"

namespace test_media_grid_render {

using namespace rdv::test;
using nlohmann::json;

namespace {

void expect_channels(const Image &img, std::array<double, 3> expected, const std::string &what, double rel_tol = 2e-5) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected[c]) / std::hypot(m.standard_error, rel_tol * expected[c] + 1e-7);
    EXPECT_LT(std::fabs(z), 4.5) << what << " channel " << c << ": mean " << m.mean << " expected " << expected[c]
                                 << " (se " << m.standard_error << ")";
  }
}

// Densities along y for the slab tests; along a line through the whole box the optical
// depth of trilinear, edge-clamped voxels is exactly voxel size x sum.
const std::vector<float> kProfile = {0.2f, 1.5f, 0.1f, 3.0f, 0.5f, 0.0f, 2.0f, 1.0f};

// An orthographic camera looks along +y through a purely absorbing chromatic grid slab
// (an index-matched box of thickness 0.8) at a uniform world of radiance 2.
json slab_scene(const json &volume) {
  return {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}}},
          {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.5}, {"transform", {{"look_at", {{"from", {0, -5, 0}}, {"to", {0, 0, 0}}}}}}}},
          {"world", {{"color", {2.0, 2.0, 2.0}}}},
          {"materials", {{{"name", "smoke"}, {"type", "volume"}, {"volume", volume}}}},
          {"meshes", {{{"name", "slab"}, {"shape", {{"type", "box"}, {"size", {3.0, 0.8, 3.0}}}}, {"materials", {"smoke"}}}}}};
}
std::array<double, 3> slab_expected(double depth) {
  return {2 * std::exp(-0.5 * depth), 2 * std::exp(-1.0 * depth), 2 * std::exp(-2.5 * depth)};
}
json dense_slab_volume(const std::string &method) {
  return {{"sigma_a", {0.5, 1.0, 2.5}}, {"sigma_s", 0}, {"method", method},
          {"grid", {{"resolution", {1, 8, 1}}, {"values", kProfile}, {"bounds", {{-1.5, -0.4, -1.5}, {1.5, 0.4, 1.5}}}}}};
}
double profile_depth() {
  double s = 0;
  for (float v : kProfile) s += v;
  return s * 0.1;
}

// Writes a VDB with a "density" grid (voxel size 0.1) holding kProfile along y over
// x, z in [-1.5, 1.5), plus a far block of active zero tiles (empty tiles) and a
// "smoke" grid of constant 0.5, by the tests' VDB tool (tests/support/write_test_vdb.cpp).
std::string write_test_vdb() {
  std::string path = temp_path("density.vdb");
  std::string command = std::string("\"") + RDV_WRITE_TEST_VDB + "\" \"" + path + "\" slab";
  for (float v : kProfile) command += " " + std::to_string(v);
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return path;
}

}  // namespace

TEST(GridMediaRender, BeerLambertThroughADenseGrid) {
  expect_channels(render_json(slab_scene(dense_slab_volume("tracking")).dump()), slab_expected(profile_depth()),
                  "grid slab, tracking");
}

// Ray marching is approximate: within 2% here (step = one voxel).
TEST(GridMediaRender, RayMarchingIsCloseOnTheSlab) {
  expect_channels(render_json(slab_scene(dense_slab_volume("ray_marching")).dump()), slab_expected(profile_depth()),
                  "grid slab, ray marching", 0.02);
}

TEST(GridMediaRender, BeerLambertThroughAVdbWithEmptyTiles) {
  std::string path = write_test_vdb();
  json box = slab_scene({{"sigma_a", {0.5, 1.0, 2.5}}, {"sigma_s", 0}, {"grid", {{"file", path}}}});
  // A box around all the active voxels and tiles.
  box["meshes"][0]["shape"]["size"] = {16.0, 8.0, 16.0};
  box["meshes"][0]["transform"] = {{"translate", {6.0, 3.2, 2.8}}};
  Image img = render_json(box.dump());
  EXPECT_EQ(img.warnings, "");
  expect_channels(img, slab_expected(profile_depth()), "vdb density");
  // The grid is selectable by name.
  json smoke = slab_scene({{"sigma_a", {0.5, 1.0, 2.5}}, {"sigma_s", 0}, {"grid", {{"file", path}, {"name", "smoke"}}}});
  smoke["meshes"][0]["shape"]["size"] = {3.0, 1.2, 3.0};  // the voxels reach from y = -0.5 to 0.4
  expect_channels(render_json(smoke.dump()), slab_expected(0.5 * 0.8), "vdb smoke");
  std::filesystem::remove(path);
}

// A missing file or grid: a warning naming the object (and the file), and the render
// goes on without that medium (the world shows through unattenuated).
TEST(GridMediaRender, MissingVdbWarnsAndRendersWithoutIt) {
  Image img = render_json(slab_scene({{"density", 3.0}, {"grid", {{"file", "/nonexistent/cloud.vdb"}}}}).dump());
  EXPECT_NE(img.warnings.find("'smoke'"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("/nonexistent/cloud.vdb"), std::string::npos) << img.warnings;
  expect_channels(img, {2, 2, 2}, "missing vdb");
  std::string path = write_test_vdb();
  Image wrong = render_json(slab_scene({{"density", 3.0}, {"grid", {{"file", path}, {"name", "heat"}}}}).dump());
  EXPECT_NE(wrong.warnings.find("no grid named 'heat'"), std::string::npos) << wrong.warnings;
  EXPECT_NE(wrong.warnings.find("density, smoke"), std::string::npos) << wrong.warnings;
  expect_channels(wrong, {2, 2, 2}, "missing grid");
  std::filesystem::remove(path);
  // A file that is not a VDB.
  std::string junk = temp_path("junk.vdb");
  { std::ofstream(junk) << "not a vdb"; }
  Image bad = render_json(slab_scene({{"density", 3.0}, {"grid", {{"file", junk}}}}).dump());
  EXPECT_NE(bad.warnings.find("cannot read VDB file"), std::string::npos) << bad.warnings;
  expect_channels(bad, {2, 2, 2}, "unreadable vdb");
  std::filesystem::remove(junk);
}

// A non-absorbing chromatic cloud under a uniform world keeps the world's radiance:
// delta tracking (spectral, chromatic) and ratio tracking in NEE conserve energy.
TEST(GridMediaRender, AlbedoOneCloudKeepsUniformWorld) {
  for (const char *integrator : {"path", "bdpt"}) {
    json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}, {"max_bounces", 1000}, {"integrator", integrator}}},
              {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
              {"world", {{"color", {0.7, 0.7, 0.7}}}},
              {"materials", {{{"name", "cloud"}, {"type", "volume"},
                              {"volume", {{"sigma_a", 0}, {"sigma_s", {9.0, 12.0, 5.0}}, {"anisotropy", -0.3},
                                          {"grid", puff_grid(24, {{-1, -1, -1}, {1, 1, 1}})}}}}}},
              {"meshes", {{{"name", "cloud"}, {"shape", {{"type", "box"}, {"size", {2, 2, 2}}}}, {"materials", {"cloud"}}}}}};
    expect_channels(render_json(j.dump()), {0.7, 0.7, 0.7}, std::string("albedo-1 grid cloud, ") + integrator);
  }
}

// Extremes stay finite and bounded in time: density 1e-6 .. 1e5, albedo 0 and 1,
// g = +-0.99, both methods, and a grid of one voxel, a spot in the scene.
TEST(GridMediaRender, ExtremesStayFinite) {
  auto t0 = std::chrono::steady_clock::now();
  for (const char *method : {"tracking", "ray_marching"})
    for (double density : {1e-6, 1.0, 1e5})
      for (double g : {-0.99, 0.99})
        for (double albedo : {0.0, 1.0})
          for (bool one_voxel : {false, true}) {
            json grid = one_voxel ? json{{"resolution", {1, 1, 1}}, {"values", {0.7}}}
                                  : puff_grid(12, {{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}});
            if (one_voxel) grid["bounds"] = {{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}};
            json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 4}, {"max_bounces", 64}}},
                      {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 1}}, {"to", {0, 0, 0.5}}}}}}}},
                      {"world", {{"color", {0.1, 0.1, 0.1}}}},
                      {"materials", {{{"name", "grey"}, {"type", "diffuse"}},
                                     {{"name", "smoke"}, {"type", "volume"},
                                      {"volume", {{"density", density}, {"color", albedo}, {"anisotropy", g}, {"method", method},
                                                  {"emission_strength", 0.5}, {"grid", grid}}}}}},
                      {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"grey"}}},
                                  {{"name", "cloud"}, {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}}, {"materials", {"smoke"}},
                                   {"transform", {{"translate", {0, 0, 0.6}}}}}}},
                      {"lights", {{{"type", "spot"}, {"position", {0, 0, 3}}, {"direction", {0, 0, -1}}, {"power", 500}}}}};
            for (const char *integrator : {"path", "bdpt"}) {
              Image img = render_json(j.dump(), json{{"integrator", integrator}}.dump());
              std::string what = std::string(method) + " " + integrator + " density " + std::to_string(density) + " g " +
                                 std::to_string(g) + " albedo " + std::to_string(albedo) + (one_voxel ? " one voxel" : "");
              EXPECT_TRUE(img.all_finite()) << what;
              EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
            }
          }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 120.0) << "the extremes took too long";
  std::printf("[ grid extremes ] 96 renders in %.1f s\n", seconds);
}

}  // namespace test_media_grid_render
