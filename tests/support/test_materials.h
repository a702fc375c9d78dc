// Materials and shading points for tests that build a Bsdf directly (no scene): a material
// from its scene-format JSON, and a point on the z = 0 plane with a uv frame.
#pragma once
#include <string>
#include "bsdfs/material.h"

namespace rdv::test {

inline Material material_from_json(const std::string &json) {
  Params p(json, "material 'test'");
  return Material::from_params(p, "test");
}

// The plane z = 0, normal up (ns: a shading normal other than the geometric one).
inline ShadingPoint flat_point(Vec3 ns = Vec3(0, 0, 1)) {
  ShadingPoint sp;
  sp.ng = Vec3(0, 0, 1);
  sp.ns = normalize(ns);
  sp.dpdu = {1, 0, 0};
  sp.dpdv = {0, 1, 0};
  sp.has_uv_frame = true;
  sp.uv = {0.3f, 0.6f};
  sp.generated = {0.3f, 0.6f, 0.5f};
  return sp;
}

}  // namespace rdv::test
