// Participating media behind one interface: free-flight distance sampling,
// transmittance, the phase function, absorption / scattering / emission, all RGB.
// Chromatic media sample a distance with one colour channel chosen uniformly and
// weight with the one-sample MIS (balance heuristic) over the channels, so every
// channel stays unbiased. A scene without media never calls any of this.
#pragma once
#include <string>
#include "core/params.h"
#include "media/phase.h"

namespace rdv {

enum class MediumType : uint8_t { Homogeneous };

struct MediumSample {
  bool scattered = false;  // true: a scattering event at t; false: the ray reached tmax
  float t = 0;
  Color weight{1.0f};      // sigma_s Tr / pdf (scattered) or Tr / P(no event) (reached tmax)
  Color emission{0.0f};    // emitted radiance collected along [0, t), already weighted
};

struct Medium {
  std::string name;
  MediumType type = MediumType::Homogeneous;
  Color sigma_a{0.0f}, sigma_s{0.0f}, sigma_t{0.0f};
  Color emission{0.0f};  // emitted radiance per unit length (Cycles' volume emission)
  HenyeyGreenstein phase;

  // From Cycles-style parameters: {"density", "color" (scattering albedo),
  // "absorption_color", "anisotropy", "emission_color", "emission_strength"} or the
  // physical {"sigma_a", "sigma_s", "emission", "anisotropy"}.
  static Medium from_params(Params &p, const std::string &name);

  Color transmittance(float distance) const {
    if (std::isinf(distance)) return {sigma_t.x > 0 ? 0.0f : 1.0f, sigma_t.y > 0 ? 0.0f : 1.0f, sigma_t.z > 0 ? 0.0f : 1.0f};
    return {std::exp(-sigma_t.x * distance), std::exp(-sigma_t.y * distance), std::exp(-sigma_t.z * distance)};
  }
  // u_channel picks the channel, u_distance the distance. tmax may be infinite. A
  // medium that does not scatter is attenuated deterministically instead.
  MediumSample sample_distance(float tmax, float u_channel, float u_distance) const;
  bool is_emissive() const { return !is_black(emission); }
};

}  // namespace rdv
