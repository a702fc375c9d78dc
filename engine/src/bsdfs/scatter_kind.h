// The kind of one scattering event, as Cycles labels it for its per-kind bounce limits
// and caustics switches (integrators/light_path_limits.h): by the two directions at the
// vertex and which lobes dominate the BSDF (Bsdf::scatter_kind).
#pragma once
#include <cstdint>

namespace rdv {

enum class ScatterKind : uint8_t {
  Diffuse,      // diffuse reflection
  Glossy,       // glossy or mirror reflection
  Transmission, // refraction (glass, rough glass, Refraction BSDF)
  Translucent,  // diffuse transmission: counts as transmission, is diffuse for caustics
  Volume,       // a scattering in a medium
  Transparent   // straight through (Transparent BSDF, alpha): no bounce of any kind
};

}  // namespace rdv
