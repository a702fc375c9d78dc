// Directional albedo E(mu, alpha) of single-scattering GGX reflection with a white
// Fresnel, tabulated once (lazily, ~0.1 s) by stratified visible-normal sampling, and
// its cosine-weighted average E_avg(alpha). They drive the Kulla-Conty (2017) energy
// compensation lobe that stands in for Cycles' Multiscatter GGX:
//   f_ms(wo, wi) = F_ms (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg)),
//   F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)),
// so a white rough conductor reflects all the energy (white furnace = 1).
#pragma once

namespace rdv {
// A table coordinate: v clamped to [0, 1], NaN to 0, so an index made from it stays inside
// the table whatever a degenerate direction upstream gave (clampf keeps a NaN).
inline float clamp_unit(float v) { return v > 0 ? (v < 1 ? v : 1.0f) : 0.0f; }
// mu = cos(theta_o) in [0,1]; alpha = GGX alpha (isotropic; sqrt(ax ay) for anisotropic);
// separable: the lobe's shadowing term (GgxDistribution::separable), a table of its own.
float ggx_albedo(float mu, float alpha, bool separable);
float ggx_average_albedo(float alpha, bool separable);
// The same for the Schlick term alone: E1(mu) = albedo with F = (1 - wo.h)^5. A GGX
// lobe with Schlick Fresnel f0 reflects f0 E + (1 - f0) E1 (exact: linear in f0).
float ggx_schlick_albedo(float mu, float alpha, bool separable);
float ggx_schlick_average_albedo(float alpha, bool separable);

// The tables at one alpha: a layer of fixed roughness asks for E and E1 at many
// directions, so the alpha coordinate is found once (the same values as the
// functions above).
struct GgxAlbedoRows {
  const float *e = nullptr, *e1 = nullptr;  // the row below alpha in each table (the one above follows)
  float fr = 0;                             // weight of the row above
  float eavg = 0, e1avg = 0;                // E_avg(alpha), E1_avg(alpha)
  void at(float mu, float &e_mu, float &e1_mu) const;
};
GgxAlbedoRows ggx_albedo_rows(float alpha, bool separable);
}  // namespace rdv
