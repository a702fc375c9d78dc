// Cycles' light passes for the Metropolis integrators (film/light_passes.h): every splat a
// state makes carries its split by slot, which the chains weigh as they weigh the splat,
// so the passes add up to the image. pssmlt's and mmlt's paths are BDPT strategies,
// classified as BDPT classifies them (bdpt/light_passes.cpp); a camera sample's splat sums
// strategies of several classes, so it carries its shares slot by slot. A path-space
// path x0 (camera) .. x(n-1) (light) goes by its first scattering vertex from the camera.
// The colour passes come from the first-hit pass (metropolis.cpp).
#include "integrators/mlt/metropolis.h"

namespace rdv::mlt {

void Metropolis::add_shares(State &state, size_t i, const LightPassSample &passes, float scale) {
  uint8_t n = 0;
  for (int k = 0; k < kLightPassSlots; ++k)
    if (!is_black(passes.light[k])) {
      state.shares.push_back({passes.light[k] * scale, uint8_t(k)});
      ++n;
    }
  Splat &sp = state.splats[i];
  sp.light_pass.on = n > 0;
  sp.light_pass.shares = n;
}

void Metropolis::classify_path(const ExplicitPath &path, State &state) {
  // x1 .. x(n-2) scatter, but for a surface passed straight through (Transparent BSDF).
  int scatterings = 0, first = -1;
  for (int i = 1; i + 1 < path.n; ++i) {
    const bdpt::PathVertex &v = path.x[size_t(i)].v;
    if (v.type == bdpt::VertexType::Surface && v.delta &&
        v.bsdf.passes_straight_through(v.wo, normalize(path.x[size_t(i + 1)].v.p - v.p)))
      continue;
    ++scatterings;
    if (first < 0) first = i;
  }
  Splat &sp = state.splats.back();
  if (scatterings == 0) {  // the camera sees the light (path space has no world light)
    state.shares.push_back({sp.L, kEmissionSlot});
    sp.light_pass.on = true;
    sp.light_pass.shares = 1;
    return;
  }
  const bdpt::PathVertex &v = path.x[size_t(first)].v;
  sp.light_pass.first =
      bdpt::Bdpt::split_at(v, v.wo, normalize(path.x[size_t(first + 1)].v.p - v.p), v.delta);
  sp.light_pass.on = true;
  sp.light_pass.indirect = scatterings > 1;
}

}  // namespace rdv::mlt
