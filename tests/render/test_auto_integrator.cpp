// Integrator auto (engine/src/integrators/auto/): the pick follows the pilots'
// efficiency, is the same for the same seed, is reported in the stats, renders the rest
// of the budget into the session's film, stops on a cancel during its pilots, and a
// missing time limit or an unknown candidate is refused naming it.
#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include "equal_time.h"

namespace test_auto_integrator {

using nlohmann::json;

namespace {

const std::string kScenes = std::string(RDV_SOURCE_DIR) + "/scenes/";

struct AutoRun {
  json choice;           // stats["auto"]
  rdv_progress progress{};
};

// Starts an auto render; once the pick is known, cancels it if cancel_after_pick (only
// the pilots run), else lets it finish. cancel_at_once: cancels before the pilots end.
AutoRun run_auto(rdv_scene *scene, const json &settings, bool cancel_after_pick, bool cancel_at_once = false) {
  rdv_session *session = nullptr;
  EXPECT_EQ(rdv_session_create(scene, settings.dump().c_str(), &session), RDV_OK) << rdv_last_error();
  AutoRun run;
  if (!session) return run;
  EXPECT_EQ(rdv_session_start(session), RDV_OK);
  if (cancel_at_once) rdv_session_cancel(session);
  const char *text = nullptr;
  while (true) {
    rdv_session_progress(session, &run.progress);
    if (run.progress.finished) break;
    if (cancel_after_pick && rdv_session_stats(session, &text) == RDV_OK &&
        json::parse(text)["auto"]["integrator"].is_string())
      rdv_session_cancel(session);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(rdv_session_wait(session), RDV_OK) << rdv_last_error();
  rdv_session_progress(session, &run.progress);
  EXPECT_EQ(rdv_session_stats(session, &text), RDV_OK);
  run.choice = json::parse(text)["auto"];
  rdv_session_destroy(session);
  return run;
}

}  // namespace

// The door gap: BDPT's error x time is ~4.5x lower than path tracing's (docs/trade.md), so
// its pilot wins unless the pilots' error estimates (from 32x24x3 values, relative spread
// ~10%) are off by that factor: false-alarm rate far below 1e-6 per pick.
TEST(AutoIntegrator, PicksTheEfficientIntegratorTheSameWayForTheSameSeed) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "door_gap.json", 32);
  rdv_tools::EngineScene loaded(scene);
  const json settings = rdv_tools::render_settings(
      scene, {{"integrator", "auto"}, {"auto_candidates", {"path", "bdpt"}}, {"time_limit", 8.0}, {"seed", 5}});
  std::string first;
  for (int run = 0; run < 2; ++run) {
    const json c = run_auto(loaded.get(), settings, true).choice;
    ASSERT_EQ(c["pilots"].size(), 2u) << c.dump();
    EXPECT_EQ(c["pilots"][0]["integrator"], "path");
    EXPECT_EQ(c["pilots"][1]["integrator"], "bdpt");
    for (const json &p : c["pilots"]) {
      EXPECT_TRUE(std::isfinite(p["rel_mse"].get<double>()) && p["rel_mse"].get<double>() > 0) << p.dump();
      EXPECT_GT(p["spp"].get<unsigned>(), 0u) << p.dump();
    }
    std::printf("[ auto ] run %d: pilots %.2f s of 8 s, pick %s\n", run, c["pilot_seconds"].get<double>(),
                c["integrator"].dump().c_str());  // timing is printed, not asserted
    EXPECT_EQ(c["integrator"], "bdpt") << c.dump();
    if (run == 0) first = c["integrator"];
    EXPECT_EQ(c["integrator"], first);
  }
}

// After its pilots the pick renders into the session's film: samples come in and the
// render halts on its own (not cancelled). A cancel during the pilots ends the render
// with no pick.
TEST(AutoIntegrator, ThePickRendersTheRestAndACancelStopsThePilots) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 16);
  rdv_tools::EngineScene loaded(scene);
  const json settings = rdv_tools::render_settings(
      scene, {{"integrator", "auto"}, {"auto_candidates", {"path", "bdpt"}}, {"time_limit", 1.0}, {"samples", 0}});
  AutoRun whole = run_auto(loaded.get(), settings, false);
  EXPECT_TRUE(whole.choice["integrator"].is_string()) << whole.choice.dump();
  EXPECT_GT(whole.progress.samples_done, 0u);
  EXPECT_EQ(whole.progress.cancelled, 0);

  AutoRun cancelled = run_auto(loaded.get(), settings, false, true);
  EXPECT_TRUE(cancelled.choice["integrator"].is_null()) << cancelled.choice.dump();
  EXPECT_EQ(cancelled.progress.cancelled, 1);
}

// Path-space mlt is a candidate (a default one since the study measured it, docs/trade.md):
// its pilot makes mutations and estimates its own error from its odd and even chains, as
// pssmlt's. A render mlt refuses (Light Paths clamps, which cap one sample's estimate) leaves it out
// with the reason (a warning when the user named it, else in the choice's "left_out"), and
// the others choose.
TEST(AutoIntegrator, PathSpaceMltIsACandidateWhereItCanRender) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "door_gap.json", 32);
  rdv_tools::EngineScene loaded(scene);
  const json settings = rdv_tools::render_settings(
      scene, {{"integrator", "auto"}, {"auto_candidates", {"bdpt", "mlt"}}, {"time_limit", 6.0}, {"seed", 5}});
  const json c = run_auto(loaded.get(), settings, true).choice;
  ASSERT_EQ(c["pilots"].size(), 2u) << c.dump();
  const json &mlt = c["pilots"][1];
  EXPECT_EQ(mlt["integrator"], "mlt");
  EXPECT_GT(mlt["spp"].get<unsigned>(), 0u) << mlt.dump();
  EXPECT_TRUE(std::isfinite(mlt["rel_mse_own"].get<double>()) && mlt["rel_mse_own"].get<double>() > 0) << mlt.dump();
  std::printf("[ auto ] bdpt and mlt pilots: rel_mse %.3g / %.3g, pick %s\n", c["pilots"][0]["rel_mse"].get<double>(),
              mlt["rel_mse"].get<double>(), c["integrator"].dump().c_str());

  rdv_tools::EqualTimeScene clamped = rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 16);
  rdv_tools::EngineScene refused(clamped);
  const json both = rdv_tools::render_settings(
      clamped,
      {{"integrator", "auto"}, {"auto_candidates", {"path", "mlt"}}, {"time_limit", 0.5}, {"clamp_indirect", 10.0}});
  const json d = run_auto(refused.get(), both, true).choice;
  ASSERT_EQ(d["pilots"].size(), 1u) << d.dump();
  EXPECT_EQ(d["integrator"], "path");
  const json defaults =
      rdv_tools::render_settings(clamped, {{"integrator", "auto"}, {"time_limit", 0.5}, {"clamp_indirect", 10.0}});
  const json e = run_auto(refused.get(), defaults, true).choice;
  EXPECT_EQ(e["pilots"].size(), 4u) << e.dump();
  ASSERT_TRUE(e.contains("left_out") && e["left_out"].size() == 1u) << e.dump();
  EXPECT_NE(e["left_out"][0].get<std::string>().find("mlt: Light Paths clamps"),
            std::string::npos)
      << e.dump();
  const json only_mlt = rdv_tools::render_settings(
      clamped, {{"integrator", "auto"}, {"auto_candidates", {"mlt"}}, {"time_limit", 0.5}, {"clamp_indirect", 10.0}});
  rdv_session *session = nullptr;
  EXPECT_NE(rdv_session_create(refused.get(), only_mlt.dump().c_str(), &session), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("no candidate can render this scene"), std::string::npos)
      << rdv_last_error();
}

TEST(AutoIntegrator, RefusesWithoutATimeLimitOrWithAnUnknownCandidate) {
  rdv_tools::EqualTimeScene scene = rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 8);
  rdv_tools::EngineScene loaded(scene);
  const std::pair<json, const char *> cases[] = {
      {{{"integrator", "auto"}, {"samples", 4}}, "needs a time limit"},
      {{{"integrator", "auto"}, {"time_limit", 0.2}, {"auto_candidates", {"path", "warp"}}},
       "'auto_candidates': unknown integrator 'warp'"},
      {{{"integrator", "auto"}, {"time_limit", 0.2}, {"auto_candidates", json::array()}}, "non-empty list"},
      {{{"integrator", "auto"}, {"time_limit", 0.2}, {"sample_offset", 4}}, "cannot render a part"},
  };
  for (const auto &[overrides, message] : cases) {
    json settings = rdv_tools::render_settings(scene, overrides);
    if (!overrides.contains("time_limit")) settings.erase("time_limit");
    rdv_session *session = nullptr;
    EXPECT_NE(rdv_session_create(loaded.get(), settings.dump().c_str(), &session), RDV_OK) << overrides.dump();
    EXPECT_EQ(session, nullptr);
    EXPECT_NE(std::string(rdv_last_error()).find(message), std::string::npos) << rdv_last_error();
  }
}

}  // namespace test_auto_integrator
