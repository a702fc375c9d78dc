#include "media/medium.h"

namespace rdv {

Medium Medium::from_params(Params &p, const std::string &name) {
  Medium m;
  m.name = name;
  auto non_negative = [&](Color c, const char *key) {
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(p.what() + ": '" + key + "' must not be negative");
    return c;
  };
  if (p.has("sigma_a") || p.has("sigma_s")) {
    m.sigma_a = non_negative(p.get_vec3("sigma_a", Color(0.0f)), "sigma_a");
    m.sigma_s = non_negative(p.get_vec3("sigma_s", Color(0.0f)), "sigma_s");
    m.emission = non_negative(p.get_vec3("emission", Color(0.0f)), "emission");
  } else {
    // Cycles' Principled Volume: density scales scattering (colour) and absorption
    // (absorption colour: what is NOT absorbed); emission = colour x strength.
    float density = p.get_float("density", 1.0f);
    if (density < 0) fail(p.what() + ": 'density' must not be negative");
    Color color = non_negative(p.get_vec3("color", Color(0.5f)), "color");
    Color absorption = non_negative(p.get_vec3("absorption_color", Color(0.0f)), "absorption_color");
    m.sigma_s = color * density;
    m.sigma_a = vmax(Color(1.0f) - absorption, Color(0.0f)) * vmax(Color(1.0f) - color, Color(0.0f)) * density;
    Color ec = non_negative(p.get_vec3("emission_color", Color(1.0f)), "emission_color");
    float es = p.get_float("emission_strength", 0.0f);
    if (es < 0) fail(p.what() + ": 'emission_strength' must not be negative");
    m.emission = ec * es;
  }
  float g = p.get_float("anisotropy", 0.0f);
  m.phase.g = clampf(g, -0.999f, 0.999f);
  m.sigma_t = m.sigma_a + m.sigma_s;
  if (!is_finite(m.sigma_t)) fail(p.what() + ": coefficients must be finite");
  return m;
}

MediumSample Medium::sample_distance(float tmax, float u_channel, float u_distance) const {
  MediumSample s;
  if (max_component(sigma_s) == 0) {
    // Nothing scatters: attenuate exactly (zero variance) and integrate emission in
    // closed form, epsilon (1 - Tr) / sigma_t per channel (epsilon t where sigma_t = 0).
    s.scattered = false;
    s.t = tmax;
    s.weight = transmittance(tmax);
    if (is_emissive())
      for (int c = 0; c < 3; ++c)
        s.emission[c] = sigma_t[c] > 0 ? emission[c] * (1.0f - s.weight[c]) / sigma_t[c]
                                       : (std::isinf(tmax) ? (emission[c] > 0 ? kInf : 0.0f) : emission[c] * tmax);
    return s;
  }
  int c = std::min(int(u_channel * 3.0f), 2);
  float st = sigma_t[c];
  float t = st > 0 ? -std::log(1.0f - u_distance) / st : kInf;
  // Emission: the expected emitted radiance along the sampled segment is collected with
  // the same estimator as scattering (Le / sigma_t per collision), which is unbiased.
  if (t < tmax) {
    Color tr = transmittance(t);
    Color density = sigma_t * tr;  // per-channel distance densities
    float pdf = average(density);
    if (!(pdf > 0)) return s;
    s.scattered = true;
    s.t = t;
    s.weight = sigma_s * tr / pdf;
    if (is_emissive()) s.emission = emission * tr / pdf;
    return s;
  }
  Color tr = transmittance(tmax);
  float p_surface = average(tr);
  s.scattered = false;
  s.t = tmax;
  s.weight = p_surface > 0 ? tr / p_surface : Color(0.0f);
  return s;
}

}  // namespace rdv
