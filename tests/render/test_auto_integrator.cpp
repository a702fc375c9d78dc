// `--integrator auto` (engine/tools/auto_integrator.cpp): the pick follows the pilots'
// efficiency, is the same for the same seed, and a missing time limit or an unknown
// candidate is refused naming it.
#include <gtest/gtest.h>
#include <string>
#include "auto_integrator.h"
#include "equal_time.h"

using nlohmann::json;

namespace {

const std::string kScenes = std::string(RDV_SOURCE_DIR) + "/scenes/";

}  // namespace

// The door gap: BDPT's error x time is ~4.5x lower than path tracing's (docs/trade.md), so
// its pilot wins unless the pilots' error estimates (from 32x24x3 values, relative spread
// ~10%) are off by that factor: false-alarm rate far below 1e-6 per pick.
TEST(AutoIntegrator, PicksTheEfficientIntegratorTheSameWayForTheSameSeed) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "door_gap.json", 32);
  rdv_tools::EngineScene loaded(scene);
  const json settings = rdv_tools::render_settings(scene, {{"time_limit", 8.0}, {"seed", 5}});
  std::string first;
  for (int run = 0; run < 2; ++run) {
    rdv_tools::AutoChoice c = rdv_tools::choose_integrator(loaded.get(), settings, {"path", "bdpt"});
    ASSERT_EQ(c.pilots.size(), 2u);
    EXPECT_EQ(c.pilots[0].integrator, "path");
    EXPECT_EQ(c.pilots[1].integrator, "bdpt");
    for (const rdv_tools::Pilot &p : c.pilots) {
      EXPECT_TRUE(std::isfinite(p.rel_mse) && p.rel_mse > 0) << p.integrator;
      EXPECT_GT(p.spp, 0u) << p.integrator;
    }
    EXPECT_EQ(c.integrator, "bdpt") << c.to_json().dump();
    if (run == 0) first = c.integrator;
    EXPECT_EQ(c.integrator, first);
    EXPECT_EQ(c.to_json()["integrator"], c.integrator);
  }
}

TEST(AutoIntegrator, RefusesWithoutATimeLimitOrWithAnUnknownCandidate) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 8);
  rdv_tools::EngineScene loaded(scene);
  try {
    rdv_tools::choose_integrator(loaded.get(), rdv_tools::render_settings(scene, {{"samples", 4}}));
    ADD_FAILURE() << "no time limit accepted";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("needs a time limit"), std::string::npos) << e.what();
  }
  try {
    rdv_tools::choose_integrator(loaded.get(), rdv_tools::render_settings(scene, {{"time_limit", 0.2}}),
                                 {"path", "warp"});
    ADD_FAILURE() << "unknown candidate accepted";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("pilot of warp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown integrator 'warp'"), std::string::npos) << e.what();
  }
}
