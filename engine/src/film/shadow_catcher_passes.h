// Cycles 3.4's shadow catcher on the film (kernel/film/light_passes.h, film/read.h):
// what a camera sample leaves, the pixel sums it adds to, and how the pixels read.
//
// A camera sample whose see-through chain meets a shadow catcher splits there
// (integrators/path/shadow_catcher.h). Per pixel, over its n samples:
// - C, T_C: Combined's sums and transparency (the film's own PixelSum): every
//   contribution of the sample with the catcher an ordinary object;
// - M, T_M (the matte): what the sample added before it met a catcher, or all it added
//   if it met none; at the split the throughput's average joins T_M (the catcher is a
//   hole in the matte);
// - S (the catcher pass): what the sample's copy gathered from the split on, tracing
//   only shadow catchers (the other objects neither seen nor casting shadows);
// - B: the world seen along the camera's ray where the sample met the world or a
//   catcher (Cycles' background pass behind the catcher, for the opaque film);
// - the number of samples that split;
// - BDPT: the light-tracing splats of the matte (t = 1 paths that do not reach the camera
//   straight from a catcher) and of the catcher pass (its copies' light tracing); pssmlt:
//   all of M and S (its samples are splats; the first-hit pass's rays count n and add
//   T_C, T_M, B and splits, integrators/mlt/metropolis.cpp, and so do the splats of
//   split camera samples' copies, CatcherSplat::SplitPass); kept as
//   raw splat sums like the film's own and read with the frame's splat scale; Combined's
//   sums are then the film's samples plus its splats (with_splats).
// The pixels read as Cycles computes them:
// - Shadow Catcher pass = (1 - a) + a (C - M) / S per channel (1 where S is 0, and
//   where no sample split), a = 1 - T_C / n: the catcher's light with the other objects
//   over its light without them (below 1 in their shadows);
// - the matte (Combined with View Layer > Passes > Shadow Catcher on): M / n, alpha
//   1 - T_M / n;
// - Combined otherwise (Cycles' "approximate shadow catcher"): with the film transparent
//   M / n with alpha a_m = (1 - a) (1 - clamp(average(factor))) + a, a = 1 - T_M / n: the
//   shadow as alpha over black; with an opaque film M / n + B / n (1 - a_m), alpha 1: the
//   world behind the catcher darkened by the shadow.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include "core/math.h"

namespace rdv {

// What one camera sample leaves (the path tracer fills it; integrators/path/shadow_catcher.h).
struct CatcherSample {
  Color matte{0.0f};
  float matte_transparency = 0;
  Color catcher{0.0f};
  Color background{0.0f};
  bool split = false;
  // Finite and not negative, as the film takes samples.
  bool valid() const {
    for (const Color &c : {matte, catcher, background})
      if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0) return false;
    return std::isfinite(matte_transparency);
  }
};

// A pixel's sums over its samples.
struct CatcherSums {
  std::array<double, 3> matte{}, catcher{}, background{};
  // BDPT's splats of the matte and of the catcher pass (raw, as the film's splat sums).
  std::array<double, 3> matte_splats{}, catcher_splats{};
  float matte_transparent = 0;
  uint32_t splits = 0;
  // A split that a splat's footprint reached (CatcherSplat::SplitPass): only whether the
  // count is 0 matters, so it stops short of overflowing.
  void add_split() { splits += splits < UINT32_MAX; }
  void add(const CatcherSample &s) {
    for (int c = 0; c < 3; ++c) {
      matte[c] += s.matte[c];
      catcher[c] += s.catcher[c];
      background[c] += s.background[c];
    }
    matte_transparent += s.matte_transparency;
    splits += s.split;
  }
};

// Which sums a splat (BDPT's light tracing) adds to in a scene with a shadow catcher:
// Combined's only (a path past the split), Combined's and the matte's, the catcher pass's
// only (a copy's), or the matte's only (pssmlt's camera sample, whose Combined is a splat
// of its own). Without catcher sums every splat is Combined's and Matte's are dropped.
// SplitPass: the catcher pass's splat of a camera sample that split (pssmlt, mmlt): it
// also counts a split in every pixel its footprint reaches, where a tile integrator's
// samples of the pixel split given enough of them. A pixel whose filter reaches a catcher
// reads the catcher's ratio, not 1, once one of its samples split: its pass depends on the
// sample count at an object's edge over a catcher (the Blender scene's ball over its
// shadow, 8x8 block means: BDPT 0.683 at 4 spp, 0.668 at 64, 0.649 at 256, 0.646 at 2048,
// 0.616 with every pixel its filter reaches counted). pssmlt's and mmlt's splits came from
// their first-hit pass's 4 rays a pixel alone, BDPT's at 4 spp at any mutation count
// (0.684 at 256 to 4096); counted by these splats they read the limit (0.624).
enum class CatcherSplat : uint8_t { Combined, CombinedAndMatte, Pass, Matte, SplitPass };

// How Combined reads in a scene with a shadow catcher (session settings).
struct CatcherDisplay {
  bool pass = false;              // View Layer > Passes > Shadow Catcher: Combined is the matte
  bool film_transparent = false;  // Film > Transparent
};

namespace shadow_catcher {

// A pixel's sums read with its splats (BDPT's light tracing): its n samples' sums plus n
// times the splats' mean (splat sums times the frame's splat scale), for Combined's sums
// (`combined`, the film's samples, and `splats`, its splat sums) and the matte's. Without
// splats (the path tracer) both are the samples' sums unchanged.
inline std::array<double, 3> with_splats(const std::array<double, 3> &sums, const std::array<double, 3> &splats,
                                         double n, double splat_scale) {
  std::array<double, 3> out = sums;
  for (int c = 0; c < 3; ++c)
    if (splats[c] != 0) out[c] += splats[c] * splat_scale * n;
  return out;
}
inline CatcherSums with_splats(const CatcherSums &s, double n, double splat_scale) {
  CatcherSums out = s;
  out.matte = with_splats(s.matte, s.matte_splats, n, splat_scale);
  out.catcher = with_splats(s.catcher, s.catcher_splats, n, splat_scale);
  return out;
}

inline double saturate(double v) { return std::clamp(v, 0.0, 1.0); }

// The Shadow Catcher pass of a pixel: combined's sums, transparency and sample count
// (the film's PixelSum) with its catcher sums.
inline std::array<double, 3> factor(const std::array<double, 3> &combined, double combined_transparent, double n,
                                    const CatcherSums &s) {
  if (s.splits == 0 || !(n > 0)) return {1.0, 1.0, 1.0};
  // Sums, not means: the same samples make all three, so n cancels.
  const double alpha = saturate(1.0 - combined_transparent / n);
  std::array<double, 3> out;
  for (int c = 0; c < 3; ++c) {
    const double ratio = s.catcher[c] != 0 ? (combined[c] - s.matte[c]) / s.catcher[c] : 1.0;
    out[c] = (1.0 - alpha) + alpha * ratio;
  }
  return out;
}

// The matte (RGBA): the other objects over a transparent catcher.
inline std::array<double, 4> matte(double n, const CatcherSums &s) {
  if (!(n > 0)) return {0.0, 0.0, 0.0, 1.0};
  return {s.matte[0] / n, s.matte[1] / n, s.matte[2] / n, saturate(1.0 - s.matte_transparent / n)};
}

// Combined as Blender shows it without the Shadow Catcher pass (RGBA).
inline std::array<double, 4> matte_with_shadow(const std::array<double, 3> &combined, double combined_transparent,
                                               double n, const CatcherSums &s, bool film_transparent) {
  std::array<double, 4> m = matte(n, s);
  if (!(n > 0)) return m;
  const std::array<double, 3> f = factor(combined, combined_transparent, n, s);
  const double shadow = 1.0 - saturate((f[0] + f[1] + f[2]) / 3.0);
  const double alpha = m[3];
  const double alpha_matte = (1.0 - alpha) * shadow + alpha;
  if (film_transparent) return {m[0], m[1], m[2], alpha_matte};
  return {m[0] + s.background[0] / n * (1.0 - alpha_matte), m[1] + s.background[1] / n * (1.0 - alpha_matte),
          m[2] + s.background[2] / n * (1.0 - alpha_matte), 1.0};
}

}  // namespace shadow_catcher
}  // namespace rdv
