// Path-space Metropolis ("mlt", integrators/mlt/path_space.h) through the C ABI: what it
// cannot sample yet is refused naming the problem, and its stats. (Its images against
// BDPT, determinism and the no-light warning are in test_mlt.cpp, with pssmlt's and mmlt's;
// its densities in test_path_mlt_densities.cpp.)
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include "integrators/mlt/image_strata.h"
#include "render_helpers.h"

using namespace rdv::test;
using nlohmann::json;

// What mlt does not sample yet is refused with a message naming it, never rendered wrong:
// emission in the world's volume (no light source: BDPT's camera paths alone gather it).
// smoke_spot's smoke (a grid medium) renders since.
TEST(PathMltRobustness, UnsupportedSceneIsRefusedNamingTheProblem) {
  SceneHandle scene;
  json smoke = load_scene("smoke_spot.json");
  smoke["world"] = {{"color", {0, 0, 0}},  // a black world: no light at infinity
                    {"volume", {{"density", 0.01}, {"emission_strength", 0.1}}}};
  rdv_tools::load_scene_json(smoke.dump(), source_path("scenes"), scene.s);
  ASSERT_EQ(rdv_scene_commit(scene.s), RDV_OK);
  rdv_session *session = nullptr;
  rdv_status r = rdv_session_create(scene.s, R"({"integrator": "mlt", "width": 8, "height": 8})", &session);
  if (r == RDV_OK) {
    r = rdv_session_start(session);
    rdv_session_destroy(session);
  }
  EXPECT_NE(r, RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("emits light outside any mesh"), std::string::npos) << rdv_last_error();
}

// An orthographic camera with depth of field (its x_0 would be a lens offset from x_1's
// foot, a density mlt does not have) is refused naming it; without, and thin lenses, render.
TEST(PathMltRobustness, OrthographicDepthOfFieldIsRefusedNamingTheCamera) {
  json scene = load_scene("cornell_box.json");
  scene["camera"].update({{"type", "orthographic"}, {"ortho_scale", 2.4}, {"aperture_radius", 0.05}});
  json s = {{"width", 8}, {"height", 8}, {"integrator", "mlt"}, {"samples", 1}, {"mlt_chains", 4}};
  try {
    render_json(scene.dump(), s.dump());
    ADD_FAILURE() << "mlt rendered an orthographic camera with depth of field";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("orthographic with depth of field"), std::string::npos) << e.what();
  }
  scene["camera"]["aperture_radius"] = 0;
  EXPECT_TRUE(render_json(scene.dump(), s.dump()).all_finite());
  scene["camera"].update({{"type", "perspective"}, {"aperture_radius", 0.05}});
  EXPECT_TRUE(render_json(scene.dump(), s.dump()).all_finite());
}

// Stats: acceptance per mutation type, b and its error; samples = mutations per pixel.
TEST(PathMltStats, ReportedThroughTheCAbi) {
  json s = {{"width", 24}, {"height", 16}, {"integrator", "mlt"}, {"samples", 8}, {"mlt_chains", 32}};
  Image img = render_json(load_scene("cornell_box.json").dump(), s.dump());
  json stats = json::parse(img.stats);
  EXPECT_EQ(stats["integrator"], "mlt");
  EXPECT_EQ(stats["chains"], 32);
  EXPECT_EQ(stats["mutations"].get<uint64_t>(), 8u * 24 * 16);
  EXPECT_EQ(img.progress.samples_done, 8u);
  EXPECT_GT(stats["b"].get<double>(), 0.0);
  EXPECT_LT(stats["b_standard_error"].get<double>(), stats["b"].get<double>());
  EXPECT_GT(stats["bidirectional_acceptance"].get<double>(), 0.0);
  EXPECT_GT(stats["large_step_acceptance"].get<double>(), 0.0);
  // The Cornell box has no specular vertex: the caustic and multi-chain perturbations get
  // weight 0; the lens subpath mutation applies to every path E D ...
  EXPECT_GT(stats["lens_subpath_acceptance"].get<double>(), 0.0);
  EXPECT_EQ(stats["mutation_types"]["multi_chain"]["proposals"].get<uint64_t>(), 0u);
  // Every mutation is of one type: the per-type proposals sum to the mutations (they were
  // summed again on every pass: 3.6e9 bidirectional proposals in a 1.3e7-mutation render).
  uint64_t proposals = 0;
  for (auto &type : stats["mutation_types"].items()) proposals += type.value()["proposals"].get<uint64_t>();
  EXPECT_EQ(proposals, stats["mutations"].get<uint64_t>());
}

// The lens subpath mutation's image positions (integrators/mlt/image_strata.h): every cell
// of the region once per cycle, in another order each cycle, each point inside its cell.
TEST(PathMltImageStrata, EveryPixelOncePerCycle) {
  const rdv::Vec2 origin{-1.5f, -1.5f}, size{10.0f, 7.5f};  // 10 x 8 cells, the last row half outside
  rdv::mlt::ImageStrata strata(origin, size, 1234);
  rdv::Pcg32 rng(5, 6);
  std::vector<int> order[2];
  for (int cycle = 0; cycle < 2; ++cycle) {
    std::set<int> seen;
    for (int i = 0; i < 80; ++i) {
      const rdv::Vec2 p = strata.next(rng);
      const int cx = int(std::floor(p.x - origin.x)), cy = int(std::floor(p.y - origin.y));
      ASSERT_TRUE(cx >= 0 && cx < 10 && cy >= 0 && cy < 8) << p.x << ", " << p.y;
      seen.insert(cy * 10 + cx);
      order[cycle].push_back(cy * 10 + cx);
    }
    EXPECT_EQ(seen.size(), 80u) << "cycle " << cycle;
  }
  EXPECT_NE(order[0], order[1]);
}
