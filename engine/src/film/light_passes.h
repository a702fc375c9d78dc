// Cycles' light passes (View Layer > Passes > Light): where each contribution to a
// pixel goes, as Cycles 3.4 splits it (kernel/film/light_passes.h, data_passes.h).
//
// A path's contribution is classified by its first scattering vertex seen from the
// camera (transparent layers passed straight through do not count): none (the camera sees
// an emitter: Emission; the world's background: Environment), else that vertex's kind
// (diffuse, glossy, transmission, volume) and whether it was the path's only scattering
// vertex (Direct: light reached from it) or not (Indirect). A surface vertex's share of
// each kind is the share of its lobes of that kind in f toward the path's next vertex
// (Cycles' pass_diffuse_weight / pass_glossy_weight; a delta lobe by the side it scatters
// to). The colour passes (Diffuse / Glossy / Transmission Color) sum each kind's lobe
// colours at the camera's first hits (times the throughput of layers in front), and a
// Direct or Indirect pass reads as its sum divided by its colour's (Cycles'
// safe_divide_even_color), so
//   Combined = Emission + Environment + sum over kinds (Direct + Indirect) x Color
// for an opaque film (volume passes have no colour: theirs is 1).
// The film stores these sums only when the settings ask for them (light_passes): a
// render without them neither stores nor computes anything of this.
#pragma once
#include <array>
#include <cstdint>
#include "core/math.h"

namespace rdv {

// The stored light passes: Emission, Environment, then Direct / Indirect per kind.
enum LightPassSlot : uint8_t {
  kEmissionSlot = 0,
  kEnvironmentSlot = 1,
  // 2 + 2 * kind + indirect, kind: 0 diffuse, 1 glossy, 2 transmission, 3 volume
  kLightPassSlots = 10
};
constexpr int kPassKinds = 4;   // diffuse, glossy, transmission, volume
constexpr int kColorKinds = 3;  // the kinds with a colour pass (volume has none)
inline int light_pass_slot(int kind, bool indirect) { return 2 + 2 * kind + (indirect ? 1 : 0); }

// A scattering vertex's share of each kind (diffuse, glossy, transmission, volume): sums to 1.
struct KindSplit {
  float w[kPassKinds] = {0, 0, 0, 0};
  static KindSplit only(int kind) {
    KindSplit s;
    s.w[kind] = 1;
    return s;
  }
};

// The light passes of one camera sample (an integrator fills it; the tile loop adds it
// to the film). Light tracing's shares are PassSplats.
struct LightPassSample {
  Color light[kLightPassSlots];
  Color color[kColorKinds];

  void clear() {
    for (Color &c : light) c = Color(0.0f);
    for (Color &c : color) c = Color(0.0f);
  }
  // A contribution of a path with `scatterings` scattering vertices whose first one
  // splits as `first` (unused for 0); environment: 0 scatterings, the world's background.
  void add(const Color &c, int scatterings, const KindSplit &first, bool environment = false) {
    if (scatterings <= 0) {
      light[environment ? kEnvironmentSlot : kEmissionSlot] += c;
      return;
    }
    for (int k = 0; k < kPassKinds; ++k)
      if (first.w[k] > 0) light[light_pass_slot(k, scatterings > 1)] += c * first.w[k];
  }
  void scale(float s) {
    for (Color &c : light) c *= s;
  }
};

// A splat's share in one light-pass slot: the Metropolis integrators' splat of a camera
// sample sums paths of several classes, so it carries its split slot by slot.
struct SlotShare {
  Color L;
  uint8_t slot = kEmissionSlot;
};

// The light passes of a splat. A light-tracing splat (a path with >= 1 scattering
// vertices): the split of its first one (from the camera) and whether it was not the
// only one. A splat with `shares` > 0 (Metropolis): its shares are the next `shares`
// SlotShares of its owner's list, in splat order, and first / indirect are unused. The
// film adds the splat's shares over the image splat's own filter footprint.
struct SplatLightPass {
  KindSplit first;
  bool on = false;  // the film keeps light passes
  bool indirect = false;
  uint8_t shares = 0;
};

// A pixel's sums (double, as the film's own: thousands of samples).
struct LightPassSums {
  std::array<std::array<double, 3>, kLightPassSlots> light{};
  std::array<std::array<double, 3>, kColorKinds> color{};

  void add(const LightPassSample &s) {
    for (int i = 0; i < kLightPassSlots; ++i)
      for (int c = 0; c < 3; ++c) light[i][c] += s.light[i][c];
    for (int i = 0; i < kColorKinds; ++i)
      for (int c = 0; c < 3; ++c) color[i][c] += s.color[i][c];
  }
};
// A pixel's light splats, per slot (Emission and Environment never get any, kept for indexing).
using LightSplatSums = std::array<std::array<double, 3>, kLightPassSlots>;

// Cycles' safe_divide_even_color: a / b per channel; a channel with b = 0 takes the
// others' ratio (grey where it can), 0 where all are.
Color safe_divide_even_color(const std::array<double, 3> &a, const std::array<double, 3> &b);

}  // namespace rdv
