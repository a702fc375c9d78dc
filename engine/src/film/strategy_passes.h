// BDPT's strategy passes (Veach 1997, fig. 10.3; pbrt-v3's visualizeStrategies): each
// strategy (s light vertices, t camera vertices) of the paths of depth d = s + t - 2
// bounces (d + 1 edges) up to a limit, MIS-weighted as it enters the image, in a pass of
// its own; one more pass, "rest", holds every longer path. So per pixel the passes of one
// depth sum to that depth's share of Combined, and all of them sum to Combined.
//
// The passes are numbered depth-major: depth 0 has only s = 0, t = 2 (an emitter seen
// directly: s = 1, t = 1 is no strategy), depth d >= 1 has s = 0 .. d + 1 (t = d + 2 - s),
// then the rest: with max depth D, 1 + sum_{d=1..D} (d + 2) + 1 passes (D = 3: 14).
// t = 1 strategies (light tracing) reach the image as splats: the film keeps splat sums
// only for them (one per depth, and the rest's).
//
// The film stores them only when the settings ask for them (strategy_passes): a render
// without them neither stores nor computes anything of this.
#pragma once
#include <array>
#include <string>

namespace rdv {

struct StrategyPasses {
  static constexpr int kMaxDepth = 6;  // 35 passes: the rdv_pass range RDV_PASS_STRATEGY_FIRST ..
  int max_depth = -1;                  // -1: no strategy passes

  // Strategies of the paths of depth 0 .. d: 1 + sum_{i=1..d} (i + 2).
  static constexpr int strategies_through(int d) { return d < 0 ? 0 : 1 + d * (d + 5) / 2; }
  static constexpr int count_for(int max_depth) { return max_depth < 0 ? 0 : strategies_through(max_depth) + 1; }
  bool enabled() const { return max_depth >= 0; }
  int count() const { return count_for(max_depth); }
  int rest() const { return count() - 1; }
  // The pass of strategy (s, t) (s + t >= 2, t >= 1, not s = t = 1).
  int index(int s, int t) const {
    const int depth = s + t - 2;
    return depth > max_depth ? rest() : strategies_through(depth - 1) + s;
  }
  // Passes with splats (t = 1): one per depth 1 .. max_depth, then the rest's.
  int splat_count() const { return max_depth < 0 ? 0 : max_depth + 1; }
  // The splat slot of pass k, -1 for a pass no t = 1 strategy reaches.
  int splat_slot(int k) const {
    if (k == rest()) return max_depth;
    int s, t;
    strategy(k, s, t);
    return t == 1 ? s - 2 : -1;  // t = 1: depth s - 1, slot depth - 1
  }
  // The strategy of pass k < rest().
  void strategy(int k, int &s, int &t) const {
    int depth = 0;
    while (strategies_through(depth) <= k) ++depth;
    s = k - strategies_through(depth - 1);
    t = depth + 2 - s;
  }
  // The pass's name (EXR layer, Blender pass): "Strategy_s1t2", and "Strategy_rest".
  std::string name(int k) const {
    if (k == rest()) return "Strategy_rest";
    int s, t;
    strategy(k, s, t);
    return "Strategy_s" + std::to_string(s) + "t" + std::to_string(t);
  }
};

// A pixel's sums of one pass (double, as the film's own: thousands of samples).
using StrategySums = std::array<double, 3>;

}  // namespace rdv
