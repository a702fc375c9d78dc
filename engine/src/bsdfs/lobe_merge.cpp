#include "bsdfs/lobe_merge.h"
#include <cmath>
#include <limits>

namespace rdv {

namespace {

Color abs_diff(Color a, Color b) { return Color(std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)); }

// The lobe's amplitude: what its f is linear in (colour x closure weight).
Color amplitude(const Lobe &l) { return l.color * l.scale; }

// How unlike two lobes are: infinite for different types (never merged), 0 when their
// sum is exactly one lobe, else a distance in their shape parameters.
float merge_cost(const Lobe &a, const Lobe &b) {
  // Lobes weighted by different view factors differ in f by direction: never one lobe.
  if (a.type != b.type || a.view_factors != b.view_factors || a.view_inverted != b.view_inverted)
    return std::numeric_limits<float>::infinity();
  float cost = std::fabs(a.ggx.ax - b.ggx.ax) + std::fabs(a.ggx.ay - b.ggx.ay) + std::fabs(a.ior - b.ior) +
               std::fabs(a.sigma - b.sigma);
  if (a.fresnel_mode != b.fresnel_mode) cost += 4;
  if (a.layers_above != b.layers_above) cost += 2;
  if (a.multiscatter != b.multiscatter || a.refraction_only != b.refraction_only ||
      a.reflection_only != b.reflection_only || a.macro_fresnel != b.macro_fresnel)
    cost += 2;
  if (a.fresnel_mode == FresnelMode::Conductor) cost += max_component(abs_diff(a.eta, b.eta) + abs_diff(a.k, b.k));
  return cost;
}

// a += b, keeping the sum of their f where that is one lobe (see the header).
void merge_into(Lobe &a, const Lobe &b) {
  Color amp_a = amplitude(a), amp_b = amplitude(b), amp = amp_a + amp_b;
  float ea = luminance(amp_a), eb = luminance(amp_b);
  float t = ea + eb > 0 ? eb / (ea + eb) : 0.5f;  // b's share of the energy
  auto blend = [t](float x, float y) { return x + (y - x) * t; };
  if (a.fresnel_mode == FresnelMode::Schlick || a.fresnel_mode == FresnelMode::Interpolated) {
    // F = c (f0 (1 - m^5) + m^5) is linear in c f0 and in c: sum both (Interpolated: FH for m^5).
    Color cf0 = amp_a * a.f0 + amp_b * b.f0;
    for (int k = 0; k < 3; ++k) a.f0[k] = amp[k] > 0 ? cf0[k] / amp[k] : 0.04f;
  }
  a.color = amp;
  a.scale = 1;
  a.ggx.ax = blend(a.ggx.ax, b.ggx.ax);  // the shadowing rule is the material's: a's and b's
  a.ggx.ay = blend(a.ggx.ay, b.ggx.ay);
  a.ior = blend(a.ior, b.ior);
  a.sigma = blend(a.sigma, b.sigma);
  a.eta = a.eta + (b.eta - a.eta) * t;
  a.k = a.k + (b.k - a.k) * t;
  if (t > 0.5f) {  // discrete choices: the stronger lobe's
    a.fresnel_mode = b.fresnel_mode;
    a.layers_above = b.layers_above;
    a.multiscatter = b.multiscatter;
    a.refraction_only = b.refraction_only;
    a.reflection_only = b.reflection_only;
    a.macro_fresnel = b.macro_fresnel;
  }
}

}  // namespace

int make_room_for_lobe(Lobe *lobes, float *weights, int n, const Lobe &incoming, float incoming_weight) {
  // Best partner for incoming, and the best pair already stored.
  int best_in = -1, best_i = -1, best_j = -1;
  float cost_in = std::numeric_limits<float>::infinity(), cost_pair = cost_in;
  for (int i = 0; i < n; ++i) {
    float c = merge_cost(lobes[i], incoming);
    if (c < cost_in) { cost_in = c; best_in = i; }
    for (int j = i + 1; j < n; ++j) {
      float cp = merge_cost(lobes[i], lobes[j]);
      if (cp < cost_pair) { cost_pair = cp; best_i = i; best_j = j; }
    }
  }
  if (best_in >= 0 && cost_in <= cost_pair) {
    merge_into(lobes[best_in], incoming);
    weights[best_in] += incoming_weight;
    return -1;
  }
  if (best_i < 0) {
    // No two lobes share a type (capacity <= number of lobe types): fold incoming into
    // the strongest lobe's weight so the energy is kept, if not the shape.
    int strongest = 0;
    for (int i = 1; i < n; ++i)
      if (weights[i] > weights[strongest]) strongest = i;
    Lobe &s = lobes[strongest];
    float e = luminance(amplitude(s));
    if (e > 0) s.scale *= 1 + luminance(amplitude(incoming)) / e;
    weights[strongest] += incoming_weight;
    return -1;
  }
  merge_into(lobes[best_i], lobes[best_j]);
  weights[best_i] += weights[best_j];
  return best_j;
}

int closest_layer(const LayerAbove *layers, int n, const LayerAbove &incoming) {
  int best = 0;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int i = 0; i < n; ++i) {
    const LayerAbove &l = layers[i];
    float cost = max_component(abs_diff(l.f0, incoming.f0)) + max_component(abs_diff(l.weight, incoming.weight)) +
                 std::fabs(l.rows.eavg - incoming.rows.eavg) + (l.kind != incoming.kind ? 4.0f : 0.0f);
    if (cost < best_cost) { best_cost = cost; best = i; }
  }
  return best;
}

}  // namespace rdv
