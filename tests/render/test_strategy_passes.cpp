// BDPT's strategy passes (film/strategy_passes.h):
// - per pixel, all passes (every strategy of depth 0 .. D and the rest) sum to Combined
//   to float rounding, with the lamps, emissive meshes, glass and fog of the shipped scenes;
// - each depth's passes sum to that depth's image: Combined at max_bounces d less Combined
//   at d - 1 (the same samples: a path's random numbers do not depend on max_bounces);
// - a pass is its strategy's image: the same seed rendered with "strategy": [s, t] (the
//   CLI's --strategy) gives the same numbers bit for bit (the same sample stream: every
//   strategy draws at dimensions of its own);
// - Combined is bit-identical with the passes on and off; a clamp scales them as Combined;
// - other integrators and depths out of range are refused with a message naming them.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include "film/strategy_passes.h"
#include "render_helpers.h"

namespace test_strategy_passes {

using namespace rdv::test;
using nlohmann::json;

namespace {

json small_scene(const std::string &name, int size = 24, int samples = 8) {
  json scene = load_scene(name);
  scene["settings"].update({{"width", size}, {"height", size}, {"samples", samples}, {"integrator", "bdpt"},
                            {"seed", 7}, {"threads", 2}});
  scene["settings"].erase("time_limit");
  return scene;
}

Image render_with(const json &scene, const json &settings) { return render_json(scene.dump(), settings.dump()); }

// Sum of passes [first, last) at pixel (x, y), in double.
void pass_sum(const Image &img, int first, int last, int x, int y, double out[3]) {
  out[0] = out[1] = out[2] = 0;
  for (int k = first; k < last; ++k)
    for (int c = 0; c < 3; ++c) out[c] += img.strategy_pass(k, x, y)[c];
}

void expect_sum_is_combined(const std::string &name, const json &settings = json::object()) {
  const json scene = small_scene(name);
  json with = {{"strategy_passes", true}};
  with.update(settings);
  const Image img = render_with(scene, with);
  const rdv::StrategyPasses layout{3};
  ASSERT_EQ(img.strategy_passes.size(), size_t(RDV_PASS_STRATEGY_LAST - RDV_PASS_STRATEGY_FIRST + 1));
  double combined_total = 0, rest_total = 0;
  int worse = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double sum[3];
      pass_sum(img, 0, layout.count(), x, y, sum);
      for (int c = 0; c < 3; ++c) {
        const double combined = img.rgba[(size_t(y) * img.width + x) * 4 + c];
        combined_total += combined;
        rest_total += img.strategy_pass(layout.rest(), x, y)[c];
        // 14 floats summed: a few float steps of the largest.
        if (std::abs(sum[c] - combined) > 1e-5 * std::abs(combined) + 1e-7) ++worse;
        for (int k = layout.count(); k < int(img.strategy_passes.size()); ++k)
          ASSERT_EQ(img.strategy_pass(k, x, y)[c], 0.0f) << "pass " << k << " beyond the session's";
      }
    }
  EXPECT_EQ(worse, 0) << name << ": channels whose passes do not sum to Combined";
  EXPECT_GT(combined_total, 0) << name;
  EXPECT_GT(rest_total, 0) << name << ": its paths longer than 3 bounces carry light";
}

TEST(StrategyPasses, SumIsCombinedCornellBox) { expect_sum_is_combined("cornell_box.json"); }
TEST(StrategyPasses, SumIsCombinedCausticUnderGlass) { expect_sum_is_combined("caustic.json"); }
TEST(StrategyPasses, SumIsCombinedFogSpot) { expect_sum_is_combined("fog_spot.json"); }
// A clamped sample's passes are scaled as its Combined is.
TEST(StrategyPasses, SumIsCombinedClamped) { expect_sum_is_combined("caustic.json", {{"clamp", 0.5}}); }

TEST(StrategyPasses, EachDepthIsItsShareOfCombined) {
  const json scene = small_scene("cornell_box.json");
  const rdv::StrategyPasses layout{3};
  const Image img = render_with(scene, {{"strategy_passes", true}});
  std::vector<Image> by_bounces;  // Combined at max_bounces 0 .. 3
  for (int d = 0; d <= 3; ++d) by_bounces.push_back(render_with(scene, {{"max_bounces", d}}));
  for (int d = 0; d <= 3; ++d) {
    const int first = rdv::StrategyPasses::strategies_through(d - 1), last = rdv::StrategyPasses::strategies_through(d);
    int worse = 0;
    double depth_total = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        double sum[3];
        pass_sum(img, first, last, x, y, sum);
        for (int c = 0; c < 3; ++c) {
          const size_t i = (size_t(y) * img.width + x) * 4 + c;
          const double share = double(by_bounces[d].rgba[i]) - (d > 0 ? double(by_bounces[d - 1].rgba[i]) : 0.0);
          depth_total += sum[c];
          if (std::abs(sum[c] - share) > 1e-5 * by_bounces[d].rgba[i] + 1e-7) ++worse;
        }
      }
    EXPECT_EQ(worse, 0) << "depth " << d << ": its passes against Combined(max_bounces " << d << ") - Combined("
                        << d - 1 << ")";
    EXPECT_GT(depth_total, 0) << "depth " << d;
  }
}

TEST(StrategyPasses, EachPassIsItsStrategyRender) {
  const json scene = small_scene("cornell_box.json", 20, 4);
  const rdv::StrategyPasses layout{3};
  const Image img = render_with(scene, {{"strategy_passes", true}});
  for (int k = 0; k < layout.rest(); ++k) {
    int s, t;
    layout.strategy(k, s, t);
    ASSERT_EQ(layout.index(s, t), k);
    const Image one = render_with(scene, {{"strategy", {s, t}}});
    int differ = 0;
    double total = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 3; ++c) {
          const float pass = img.strategy_pass(k, x, y)[c];
          total += pass;
          differ += pass != one.rgba[(size_t(y) * img.width + x) * 4 + c];
        }
    EXPECT_EQ(differ, 0) << layout.name(k) << ": channels that differ from --strategy " << s << "," << t;
    std::printf("%s: mean %.5f\n", layout.name(k).c_str(), total / (3.0 * img.width * img.height));
    EXPECT_GT(total, 0) << layout.name(k) << ": every strategy of the Cornell box's paths carries light";
  }
}

TEST(StrategyPasses, CombinedUnchangedByPasses) {
  const json scene = small_scene("caustic.json");
  const Image off = render_with(scene, json::object());
  const Image on = render_with(scene, {{"strategy_passes", true}, {"strategy_passes_max_depth", 2}});
  EXPECT_TRUE(off.strategy_passes.empty());
  ASSERT_EQ(off.rgba.size(), on.rgba.size());
  size_t differ = 0;
  for (size_t i = 0; i < off.rgba.size(); ++i) differ += off.rgba[i] != on.rgba[i];
  EXPECT_EQ(differ, 0u);
}

TEST(StrategyPasses, LayoutNamesAndNumbers) {
  const rdv::StrategyPasses d3{3};
  EXPECT_EQ(d3.count(), 14);
  EXPECT_EQ(d3.name(0), "Strategy_s0t2");
  EXPECT_EQ(d3.name(1), "Strategy_s0t3");
  EXPECT_EQ(d3.name(3), "Strategy_s2t1");
  EXPECT_EQ(d3.name(12), "Strategy_s4t1");
  EXPECT_EQ(d3.name(13), "Strategy_rest");
  EXPECT_EQ(d3.index(3, 3), d3.rest());  // depth 4
  EXPECT_EQ(d3.splat_count(), 4);
  EXPECT_EQ(d3.splat_slot(3), 0);
  EXPECT_EQ(d3.splat_slot(12), 2);
  EXPECT_EQ(d3.splat_slot(13), 3);
  EXPECT_EQ(d3.splat_slot(2), -1);  // s1t2
  EXPECT_EQ(rdv::StrategyPasses{0}.count(), 2);
  EXPECT_EQ(rdv::StrategyPasses{-1}.count(), 0);
}

TEST(StrategyPasses, RefusedWhereThereAreNoStrategies) {
  const json scene = small_scene("cornell_box.json", 8, 1);
  for (const char *integrator : {"path", "pssmlt", "mmlt"}) {
    SceneHandle h;
    auto loaded = rdv_tools::load_scene_json(scene.dump(), ".", h.s);
    json settings = json::parse(loaded.settings_json);
    settings.update({{"integrator", integrator}, {"strategy_passes", true}});
    EXPECT_NE(session_status(h.s, settings.dump()), RDV_OK) << integrator;
    EXPECT_NE(std::string(rdv_last_error()).find("strategy_passes"), std::string::npos) << rdv_last_error();
  }
  SceneHandle h;
  auto loaded = rdv_tools::load_scene_json(scene.dump(), ".", h.s);
  json settings = json::parse(loaded.settings_json);
  settings.update({{"strategy_passes", true}, {"strategy_passes_max_depth", 7}});
  EXPECT_NE(session_status(h.s, settings.dump()), RDV_OK);
  EXPECT_NE(std::string(rdv_last_error()).find("strategy_passes_max_depth"), std::string::npos) << rdv_last_error();
}

}  // namespace

}  // namespace test_strategy_passes
