#include "bsdfs/material.h"

namespace rdv {

static Color non_negative_color(Params &p, const char *key, Color fallback) {
  Color c = p.get_vec3(key, fallback);
  if (c.x < 0 || c.y < 0 || c.z < 0) fail(p.what() + ": '" + key + "' must not be negative");
  return c;
}

Material Material::from_params(Params &p, const std::string &name) {
  Material m;
  m.name = name;
  std::string type = p.get_string("type", "diffuse");
  if (type == "diffuse") {
    m.type = MaterialType::Diffuse;
    m.color = non_negative_color(p, "color", Color(0.8f));
  } else if (type == "emission") {
    m.type = MaterialType::Emission;
    Color c = non_negative_color(p, "color", Color(1.0f));
    float strength = p.get_float("strength", 1.0f);
    if (strength < 0) fail(p.what() + ": 'strength' must not be negative");
    m.emission = c * strength;
    m.color = Color(0.0f);
  } else if (type == "glossy") {
    m.type = MaterialType::Glossy;
    m.color = non_negative_color(p, "color", Color(0.8f));
    m.roughness = clampf(p.get_float("roughness", 0.5f), 0.0f, 1.0f);
    if (p.has("eta") || p.has("k")) {
      m.use_conductor_fresnel = true;
      m.eta = non_negative_color(p, "eta", Color(1.0f));
      m.k = non_negative_color(p, "k", Color(0.0f));
    }
  } else if (type == "glass") {
    m.type = MaterialType::Glass;
    m.color = non_negative_color(p, "color", Color(1.0f));
    m.roughness = clampf(p.get_float("roughness", 0.0f), 0.0f, 1.0f);
    m.ior = clampf(p.get_float("ior", 1.45f), 1.0001f, 4.0f);
  } else {
    fail(p.what() + ": unknown material type '" + type + "' (diffuse, emission, glossy, glass)");
  }
  if (m.type != MaterialType::Emission) {  // a surface may scatter and emit (Principled's Emission)
    Color e = non_negative_color(p, "emission", Color(0.0f));
    float strength = p.get_float("emission_strength", 1.0f);
    if (strength < 0) fail(p.what() + ": 'emission_strength' must not be negative");
    m.emission = e * strength;
  }
  p.check_all_used();
  return m;
}

Material Material::error_material(const std::string &name) {
  Material m;
  m.name = name;
  m.type = MaterialType::Diffuse;
  m.color = Color(1.0f, 0.0f, 1.0f);
  return m;
}

const char *Material::type_name() const {
  switch (type) {
    case MaterialType::Diffuse: return "diffuse";
    case MaterialType::Emission: return "emission";
    case MaterialType::Glossy: return "glossy";
    case MaterialType::Glass: return "glass";
  }
  return "?";
}

Bsdf Material::make_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const {
  Bsdf bsdf(ng, ns, wo);
  switch (type) {
    case MaterialType::Diffuse: {
      Lobe l;
      l.type = LobeType::Lambert;
      l.color = color;
      bsdf.add_lobe(l, 1.0f);
      break;
    }
    case MaterialType::Glossy: {
      Lobe l;
      float alpha = roughness * roughness;  // Blender's roughness convention
      l.ggx = {alpha, alpha};
      l.type = l.ggx.is_smooth() ? LobeType::SpecularConductor : LobeType::GgxConductor;
      l.color = color;
      l.fresnel_mode = use_conductor_fresnel ? FresnelMode::Conductor : FresnelMode::Tint;
      l.eta = eta;
      l.k = k;
      bsdf.add_lobe(l, 1.0f);
      break;
    }
    case MaterialType::Glass: {
      Lobe l;
      float alpha = roughness * roughness;
      l.ggx = {alpha, alpha};
      l.type = l.ggx.is_smooth() ? LobeType::SmoothDielectric : LobeType::GgxDielectric;
      l.color = color;
      l.ior = ior;
      bsdf.add_lobe(l, 1.0f);
      break;
    }
    case MaterialType::Emission: break;  // emits only; no scattering
  }
  return bsdf;
}

}  // namespace rdv
