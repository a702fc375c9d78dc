// A material as the scene stores it, and the Bsdf it yields at a surface point.
// Only the lobes a material needs are built: a diffuse material runs no
// microfacet code.
#pragma once
#include <string>
#include "bsdfs/bsdf.h"
#include "core/params.h"

namespace rdv {

enum class MaterialType : uint8_t { Diffuse, Emission, Glossy, Glass };

struct Material {
  std::string name;
  MaterialType type = MaterialType::Diffuse;
  Color color{0.8f};
  Color emission{0.0f};  // radiance, both faces (Cycles' Emission shader)
  float roughness = 0.5f;
  float ior = 1.45f;
  bool use_conductor_fresnel = false;
  Color eta{1.0f}, k{0.0f};

  static Material from_params(Params &p, const std::string &name);
  // The magenta stand-in Blender shows for a material it cannot use.
  static Material error_material(const std::string &name);
  bool emits() const { return !is_black(emission); }
  const char *type_name() const;
  Bsdf make_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const;
};

}  // namespace rdv
