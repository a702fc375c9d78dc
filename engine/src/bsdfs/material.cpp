#include "bsdfs/material.h"
#include "film/data_passes.h"
#include "bsdfs/layering.h"
#include "bsdfs/lobe_merge.h"
#include "core/limits.h"

namespace rdv {

namespace {

using nlohmann::json;
using Factor = Closure::Factor;

struct Parser {
  Material &m;

  // A colour / float parameter: constant (validated non-negative when asked) or texture graph.
  int value(Params &p, const char *key, Color fallback, bool non_negative = true) {
    const json *j = p.get_json(key);
    if (!j) return m.graph.constant(fallback);
    int node = m.graph.parse(*j, p.what() + " '" + key + "'", m.warnings);
    if (non_negative && m.graph.is_constant(node)) {
      Color c = m.graph.node(node).value;
      if (c.x < 0 || c.y < 0 || c.z < 0) fail(p.what() + ": '" + key + "' must not be negative");
    }
    return node;
  }
  // The first of several spellings (Blender 3.4 and 4.x socket names) that is present.
  int value_any(Params &p, std::initializer_list<const char *> keys, Color fallback, const char **used = nullptr) {
    const char *chosen = *keys.begin();
    for (const char *k : keys)
      if (p.has(k)) { chosen = k; break; }
    for (const char *k : keys)
      if (k != chosen && p.has(k)) fail(p.what() + ": give '" + chosen + "' or '" + k + "', not both");
    for (const char *k : keys) (void)p.get_json(k);  // mark the spellings as known
    if (used) *used = chosen;
    return p.has(chosen) ? m.graph.parse(*p.get_json(chosen), p.what() + " '" + chosen + "'", m.warnings)
                         : m.graph.constant(fallback);
  }
  int normal(Params &p, const char *key) {
    const json *j = p.get_json(key);
    if (!j) return -1;
    int node = m.graph.parse(*j, p.what() + " '" + key + "'", m.warnings);
    TexNodeType t = m.graph.node(node).type;
    if (t != TexNodeType::NormalMap && t != TexNodeType::Bump && t != TexNodeType::Bevel)
      fail(p.what() + ": '" + key + "' must be a normal_map, bump or bevel node");
    return node;
  }
  // Emission: colour x strength x the Mix Shader factors. Constant terms fold into
  // Material::emission; textured ones are kept and evaluated at each point.
  void emission(Params &p, const std::vector<Factor> &w, const char *color_key, const char *strength_key,
                Color color_default, float strength_default, std::initializer_list<const char *> aliases = {}) {
    Material::EmissionTerm e;
    e.color = aliases.size() ? value_any(p, aliases, color_default) : value(p, color_key, color_default);
    e.strength = value(p, strength_key, Color(strength_default));
    e.weight = w;
    auto zero = [&](int node) { return m.graph.is_constant(node) && is_black(m.graph.node(node).value); };
    if (zero(e.color) || zero(e.strength)) return;
    // Emitted radiance by the direction it leaves in is not modelled: a view factor over an
    // emission is its mean (the closures beside it keep theirs exact).
    for (Factor &f : e.weight)
      if (f.view >= 0) f = constant_view_factor(f, p.what() + ": emission under a view-dependent factor (Fresnel, Layer Weight, Backfacing)");
    bool constant = m.graph.is_constant(e.color) && m.graph.is_constant(e.strength);
    for (const Factor &f : e.weight) constant = constant && m.graph.is_constant(f.node);
    if (constant) m.emission += m.emission_of(e, ShadingPoint{});
    else m.textured_emission.push_back(e);
  }

  void shader(Params &p, const std::string &type, const std::vector<Factor> &w, int depth = 0) {
    Closure c;
    c.weight = w;
    if (type == "mix" || type == "add") {
      if (depth >= kMaxShaderNesting)
        fail("material '" + m.name + "': Mix / Add shaders nest more than " + std::to_string(kMaxShaderNesting) +
                 " deep (a limit: docs/scene-format.md)",
             RDV_ERROR_LIMIT);
      const Factor fac = type == "mix" ? mix_factor(p) : Factor{-1, false};
      const char *keys[2] = {"shader1", "shader2"};
      for (int i = 0; i < 2; ++i) {
        const json *j = p.get_json(keys[i]);
        if (!j) continue;  // an unconnected shader socket contributes nothing (black)
        if (!j->is_object()) fail(p.what() + ": '" + keys[i] + "' must be a material object");
        Params child(j->dump(), p.what() + " " + keys[i]);
        std::vector<Factor> cw = w;
        if (fac.node >= 0 || fac.view >= 0) cw.push_back({fac.node, i == 0, fac.view});
        shader(child, child.get_string("type", "diffuse"), cw, depth + 1);
        child.check_all_used();
      }
      return;
    }
    if (type == "emission") {
      emission(p, w, "color", "strength", Color(1.0f), 1.0f);
      return;
    }
    if (type == "diffuse") {
      c.type = MaterialType::Diffuse;
      c.in[kBaseColor] = value(p, "color", Color(0.8f));
      c.in[kRoughness] = value(p, "roughness", Color(0.0f));
      emission(p, w, "emission", "emission_strength", Color(0.0f), 1.0f);
    } else if (type == "glossy") {
      c.type = MaterialType::Glossy;
      c.in[kBaseColor] = value(p, "color", Color(0.8f));
      c.in[kRoughness] = value(p, "roughness", Color(0.5f));
      c.in[kAnisotropic] = value(p, "anisotropy", Color(0.0f), false);
      c.in[kAnisoRotation] = value(p, "rotation", Color(0.0f), false);
      if (p.has("eta") || p.has("k")) {
        c.fresnel = FresnelMode::Conductor;
        c.eta = p.get_vec3("eta", Color(1.0f));
        c.k = p.get_vec3("k", Color(0.0f));
        if (c.eta.x < 0 || c.eta.y < 0 || c.eta.z < 0 || c.k.x < 0 || c.k.y < 0 || c.k.z < 0)
          fail(p.what() + ": 'eta' and 'k' must not be negative");
      }
      distribution(p, c, "GGX");
      emission(p, w, "emission", "emission_strength", Color(0.0f), 1.0f);
    } else if (type == "glass" || type == "refraction") {
      c.type = type == "glass" ? MaterialType::Glass : MaterialType::Refraction;
      c.in[kBaseColor] = value(p, "color", Color(1.0f));
      c.in[kRoughness] = value(p, "roughness", Color(0.0f));
      c.in[kIor] = value(p, "ior", Color(1.45f));
      distribution(p, c, "GGX");
      if (c.multiscatter)
        m.warnings.push_back(p.what() + ": Multiscatter GGX " + type + " is approximated by single-scattering GGX");
      c.multiscatter = false;
    } else if (type == "transparent") {
      c.type = MaterialType::Transparent;
      c.in[kBaseColor] = value(p, "color", Color(1.0f));
    } else if (type == "holdout") {
      c.type = MaterialType::Holdout;  // scatters nothing: only its weight counts (holdout_at)
    } else if (type == "translucent") {
      c.type = MaterialType::Translucent;
      c.in[kBaseColor] = value(p, "color", Color(0.8f));
    } else if (type == "sheen") {
      c.type = MaterialType::Sheen;
      c.in[kBaseColor] = value(p, "color", Color(0.8f));
    } else if (type == "principled") {
      principled(p, c, w);
    } else {
      fail(p.what() + ": unknown material type '" + type +
           "' (diffuse, emission, glossy, glass, refraction, principled, transparent, translucent, sheen, holdout, "
           "mix, add)");
    }
    c.normal = normal(p, "normal");
    m.closures.push_back(c);
  }

  // A Mix Shader's factor: a texture-graph value, or a view factor (view_factor.h):
  // {"node": "fresnel", "ior": ...}, {"node": "layer_weight", "blend": ..., "output": "fresnel" |
  // "facing"} or {"node": "backfacing"}.
  Factor mix_factor(Params &p) {
    const json *j = p.get_json("fac");
    const std::string node = j && j->is_object() ? j->value("node", std::string()) : std::string();
    if (node != "fresnel" && node != "layer_weight" && node != "backfacing") return {value(p, "fac", Color(0.5f)), false};
    Params f(j->dump(), p.what() + " 'fac'");
    (void)f.get_json("node");
    Material::ViewFactorSpec spec;
    if (node == "fresnel") {
      spec.kind = ViewFactorKind::Fresnel;
      spec.param = value(f, "ior", Color(1.45f));
    } else if (node == "backfacing") {
      spec.kind = ViewFactorKind::Backfacing;
      spec.param = m.graph.constant(Color(0.0f));
    } else {
      const std::string output = f.get_string("output", "fresnel");
      if (output != "fresnel" && output != "facing")
        fail(f.what() + ": 'output' must be fresnel or facing, got '" + output + "'");
      spec.kind = output == "fresnel" ? ViewFactorKind::LayerFresnel : ViewFactorKind::LayerFacing;
      spec.param = value(f, "blend", Color(0.5f), false);
    }
    if (f.get_json("normal"))
      m.warnings.push_back(f.what() + ": its Normal input is approximated by the interpolated normal");
    if (const json *t = f.get_json("table")) {
      const size_t kMaxTable = 4096;
      if (!t->is_array() || t->size() < 2 || t->size() > kMaxTable)
        fail(f.what() + ": 'table' must be an array of 2 to " + std::to_string(kMaxTable) + " numbers");
      for (const json &v : *t) {
        if (!v.is_number() || !std::isfinite(v.get<double>()))
          fail(f.what() + ": 'table' must hold finite numbers");
        spec.table.push_back(v.get<float>());
      }
    }
    f.check_all_used();
    m.view_factors.push_back(spec);
    const Factor factor{-1, false, int(m.view_factors.size()) - 1};
    if (m.view_factors.size() <= size_t(Bsdf::kMaxViewFactors)) return factor;
    const Factor mean = constant_view_factor(factor, f.what() + ": more than " + std::to_string(Bsdf::kMaxViewFactors) +
                                                         " view-dependent factors (Fresnel, Layer Weight, Backfacing) in one material");
    m.view_factors.pop_back();
    return mean;
  }
  // A view factor replaced by its cosine-weighted mean (a textured IOR or blend: the mean at
  // the graph's default for it), with a warning saying why.
  Factor constant_view_factor(const Factor &f, const std::string &why) {
    const Material::ViewFactorSpec &spec = m.view_factors[size_t(f.view)];
    const TexNode &param = m.graph.node(spec.param);
    const float fallback = spec.kind == ViewFactorKind::Fresnel ? 1.45f : spec.kind == ViewFactorKind::Backfacing ? 0.0f : 0.5f;
    const float mean = spec.at(param.type == TexNodeType::Constant ? param.value.x : fallback).cosine_weighted_mean();
    if (!why.empty()) m.warnings.push_back(why + ": the factor is its mean over directions, " + std::to_string(mean));
    return {m.graph.constant(Color(mean)), f.invert};
  }

  void distribution(Params &p, Closure &c, const char *fallback) {
    std::string d = p.get_string("distribution", fallback);
    for (char &ch : d) ch = char(std::toupper(static_cast<unsigned char>(ch)));
    if (d == "MULTI_GGX" || d == "MULTISCATTER_GGX") c.multiscatter = true;
    else if (d == "SHARP") c.in[kRoughness] = m.graph.constant(Color(0.0f));
    else if (d == "BECKMANN" || d == "ASHIKHMIN_SHIRLEY")
      m.warnings.push_back(p.what() + ": distribution " + d + " is approximated by GGX");
    else if (d != "GGX") fail(p.what() + ": 'distribution' must be GGX, MULTI_GGX, SHARP, BECKMANN or ASHIKHMIN_SHIRLEY");
  }

  void principled(Params &p, Closure &c, const std::vector<Factor> &w) {
    c.type = MaterialType::Principled;
    c.in[kBaseColor] = value(p, "base_color", Color(0.8f));
    c.in[kSubsurface] = value_any(p, {"subsurface", "subsurface_weight"}, Color(0.0f));
    c.in[kSubsurfaceColor] = value(p, "subsurface_color", Color(0.8f));
    for (const char *ignored : {"subsurface_radius", "subsurface_ior", "subsurface_anisotropy", "subsurface_scale",
                                "subsurface_method", "sheen_roughness", "coat_ior", "coat_tint"})
      (void)p.get_json(ignored);
    if (!m.graph.is_constant(c.in[kSubsurface]) || m.graph.node(c.in[kSubsurface]).value.x > 0)
      m.warnings.push_back(p.what() + ": subsurface scattering is approximated as diffuse reflection of the subsurface colour");
    c.in[kMetallic] = value(p, "metallic", Color(0.0f));
    c.in[kSpecular] = value_any(p, {"specular", "specular_ior_level"}, Color(0.5f));
    const char *tint_key;
    c.in[kSpecularTint] = value_any(p, {"specular_tint"}, Color(0.0f), &tint_key);
    c.specular_tint_is_color = p.has("specular_tint") && p.get_json("specular_tint")->is_array();
    c.in[kRoughness] = value(p, "roughness", Color(0.5f));
    c.in[kAnisotropic] = value(p, "anisotropic", Color(0.0f));
    c.in[kAnisoRotation] = value(p, "anisotropic_rotation", Color(0.0f), false);
    c.in[kSheen] = value_any(p, {"sheen", "sheen_weight"}, Color(0.0f));
    c.in[kSheenTint] = value(p, "sheen_tint", Color(0.5f));
    c.sheen_tint_is_color = p.has("sheen_tint") && p.get_json("sheen_tint")->is_array();
    c.in[kClearcoat] = value_any(p, {"clearcoat", "coat_weight"}, Color(0.0f));
    c.in[kClearcoatRoughness] = value_any(p, {"clearcoat_roughness", "coat_roughness"}, Color(0.03f));
    c.in[kIor] = value(p, "ior", Color(1.45f));
    c.in[kTransmission] = value_any(p, {"transmission", "transmission_weight"}, Color(0.0f));
    c.in[kTransmissionRoughness] = value(p, "transmission_roughness", Color(0.0f));
    c.in[kAlpha] = value(p, "alpha", Color(1.0f));
    emission(p, w, "emission", "emission_strength", Color(0.0f), 1.0f, {"emission", "emission_color"});
    for (const char *k : {"clearcoat_normal", "coat_normal"})
      if (p.get_json(k)) m.warnings.push_back(p.what() + ": '" + k + "' is approximated by the main normal");
    if (p.get_json("tangent")) m.warnings.push_back(p.what() + ": 'tangent' is ignored; anisotropy follows the default UV map");
    distribution(p, c, "GGX");
    std::string layering = p.get_string("layering", "energy_conserving");
    if (layering == "additive") c.additive_layers = true;
    else if (layering != "energy_conserving")
      fail(p.what() + ": 'layering' must be energy_conserving or additive, got '" + layering + "'");
  }
};

}  // namespace

Material Material::from_params(Params &p, const std::string &name, const ImageBuffers *images) {
  Material m;
  m.name = name;
  m.graph.image_buffers = images;
  std::string type = p.get_string("type", "diffuse");
  m.pass_index = float(pass_index_of(p, "material '" + name + "'"));
  m.crypto_name = p.get_string("cryptomatte", name);
  m.crypto_id = cryptomatte::id_of(m.crypto_name);
  const std::string microfacets = p.get_string("microfacets", "physical");
  if (microfacets == "cycles_3.4") m.cycles34_microfacets = true;
  else if (microfacets != "physical")
    fail("material '" + name + "': 'microfacets' must be physical or cycles_3.4, got '" + microfacets + "'");
  static const std::pair<const char *, MaterialType> kTypes[] = {
      {"diffuse", MaterialType::Diffuse}, {"emission", MaterialType::Emission}, {"glossy", MaterialType::Glossy},
      {"glass", MaterialType::Glass}, {"refraction", MaterialType::Refraction}, {"principled", MaterialType::Principled},
      {"transparent", MaterialType::Transparent}, {"translucent", MaterialType::Translucent},
      {"sheen", MaterialType::Sheen}, {"holdout", MaterialType::Holdout}, {"mix", MaterialType::Mix},
      {"add", MaterialType::Add}};
  for (auto &[n, t] : kTypes)
    if (type == n) m.type = t;
  Parser{m}.shader(p, type, {});
  m.surface_normal = Parser{m}.normal(p, "surface_normal");
  if (const json *d = p.get_json("displacement")) {
    m.shading_nodes = m.graph.size();
    m.displacement = m.graph.parse(*d, p.what() + " 'displacement'", m.warnings);
    const std::string method = p.get_string("displacement_method", "true");
    if (method != "true" && method != "both")
      fail(p.what() + ": 'displacement_method' must be true or both, got '" + method + "'");
    m.displacement_keeps_normals = method == "both";
  }
  if (const json *a = p.get_json("aovs")) {
    if (!a->is_object()) fail(p.what() + ": 'aovs' must be an object of AOV names and their outputs");
    m.shading_nodes = std::min(m.shading_nodes, m.graph.size());
    for (auto it = a->begin(); it != a->end(); ++it) {
      const std::string what = p.what() + " AOV '" + it.key() + "'";
      if (!it.value().is_object()) fail(what + ": must be an object with 'color' and / or 'value'");
      Aov aov;
      aov.id = attribute_id(it.key());
      for (auto out = it.value().begin(); out != it.value().end(); ++out) {
        if (out.key() != "color" && out.key() != "value")
          fail(what + ": unknown output '" + out.key() + "' (color, value)", RDV_ERROR_UNKNOWN_PARAMETER);
        (out.key() == "color" ? aov.color : aov.value) = m.graph.parse(out.value(), what + " " + out.key(), m.warnings);
      }
      m.aovs.push_back(aov);
    }
  }
  m.graph.image_buffers = nullptr;  // only while parsing: the scene's buffers may change later
  p.check_all_used();
  for (const Closure &c : m.closures) {
    if (c.type == MaterialType::Transparent) m.transparent = true;
    if (c.type == MaterialType::Holdout) m.holdout = true;
    if (c.type == MaterialType::Principled &&
        (!m.graph.is_constant(c.in[kAlpha]) || m.graph.node(c.in[kAlpha]).value.x < 1.0f))
      m.transparent = true;
  }
  // A view factor over a transparency or a holdout would make shadow rays and alpha depend on
  // the direction too (not modelled): those closures take the factors' means. (Transparency
  // beside a view factor, as a leaf's alpha around a two-sided mix, stays exact.)
  {
    Parser parser{m};
    bool warned = false, any_left = false;
    for (Closure &c : m.closures) {
      const bool passes = c.type == MaterialType::Transparent || c.type == MaterialType::Holdout ||
                          (c.type == MaterialType::Principled &&
                           (!m.graph.is_constant(c.in[kAlpha]) || m.graph.node(c.in[kAlpha]).value.x < 1.0f));
      for (Factor &f : c.weight) {
        if (f.view < 0) continue;
        if (!passes) { any_left = true; continue; }
        f = parser.constant_view_factor(f, warned ? "" : "a view-dependent factor (Fresnel, Layer Weight, "
                                                         "Backfacing) over transparency or a holdout");
        warned = true;
      }
    }
    if (!any_left) m.view_factors.clear();  // none left: the material may be resolved once
  }
  m.warn_if_lobes_merge();
  for (std::string &w : m.warnings)
    if (w.rfind("material", 0) != 0 && w.rfind("image", 0) != 0) w = "material '" + name + "': " + w;
  for (std::string &w : m.warnings)
    if (w.rfind("image", 0) == 0) w = "material '" + name + "': " + w;
  m.resolve_constants();
  m.average_textured_emission();
  return m;
}

// The most lobes and layers a closure can add at one point (Principled: pass-through,
// diffuse, sheen, specular, transmission, clearcoat; layers: sheen, specular, coat),
// leaving out those a constant input turns off; Cycles 3.4's microfacets: transmission is
// two lobes.
static void closure_capacity(const Closure &c, const TextureGraph &graph, bool cycles34, int &lobes, int &layers) {
  if (c.type != MaterialType::Principled) {
    lobes += 1;
    return;
  }
  auto may_be = [&](ClosureInput i, bool (*on)(float)) {
    return !graph.is_constant(c.in[i]) || on(graph.node(c.in[i]).value.x);
  };
  auto positive = [](float v) { return v > 0; };
  bool sheen = may_be(kSheen, positive), coat = may_be(kClearcoat, positive);
  lobes += 2 + may_be(kAlpha, [](float v) { return v < 1; }) + sheen + may_be(kTransmission, positive) * (cycles34 ? 2 : 1) +
           coat;
  if (!c.additive_layers) layers += 1 + sheen + coat;
}

void Material::warn_if_lobes_merge() {
  int lobes = 0, layers = 0;
  for (const Closure &c : closures) closure_capacity(c, graph, cycles34_microfacets, lobes, layers);
  if (lobes <= Bsdf::kMaxLobes && layers <= Bsdf::kMaxLayers) return;
  warnings.push_back("up to " + std::to_string(lobes) + " BSDF lobes and " + std::to_string(layers) +
                     " layers at a point, more than the " + std::to_string(Bsdf::kMaxLobes) + " and " +
                     std::to_string(Bsdf::kMaxLayers) +
                     " a point holds: lobes of one kind are merged (energy kept; their roughness and IOR averaged "
                     "where they differ)");
}

void Material::ResolvedLobes::add_lobe(const Lobe &l, float w) {
  if (!(w > 0)) return;
  int slot = n < Bsdf::kMaxLobes ? n++ : make_room_for_lobe(lobe, weight, n, l, w);
  if (slot >= 0) { lobe[slot] = l; weight[slot] = w; }
}

uint16_t Material::ResolvedLobes::add_layer(const LayerAbove &l) {
  if (num_layers == Bsdf::kMaxLayers) return uint16_t(1u << closest_layer(layer, num_layers, l));
  layer[num_layers] = l;
  return uint16_t(1u << num_layers++);
}

Material Material::error_material(const std::string &name) {
  Material m;
  m.name = m.crypto_name = name;
  m.crypto_id = cryptomatte::id_of(name);
  m.type = MaterialType::Diffuse;
  Closure c;
  c.type = MaterialType::Diffuse;
  c.in[kBaseColor] = m.graph.constant(Color(1.0f, 0.0f, 1.0f));
  c.in[kRoughness] = m.graph.constant(Color(0.0f));
  m.closures.push_back(c);
  m.resolve_constants();
  m.average_textured_emission();
  return m;
}

float Material::mix_weight(const std::vector<Closure::Factor> &factors, const ShadingPoint &sp) const {
  float w = 1;
  for (const Closure::Factor &f : factors) {
    if (f.view >= 0) continue;
    const float v = clampf(graph.eval_float(f.node, sp), 0.0f, 1.0f);
    w *= f.invert ? 1 - v : v;
  }
  return w;
}

Color Material::emission_of(const EmissionTerm &e, const ShadingPoint &sp) const {
  const float w = mix_weight(e.weight, sp);
  if (!(w > 0)) return Color(0.0f);
  return vmax(graph.eval(e.color, sp), Color(0.0f)) * (std::max(graph.eval_float(e.strength, sp), 0.0f) * w);
}

Color Material::emission_at(const ShadingPoint &sp) const {
  Color e = emission;
  for (const EmissionTerm &t : textured_emission) e += emission_of(t, sp);
  return e;
}

bool Material::emission_by_distance() const {
  for (const EmissionTerm &t : textured_emission) {
    if (graph.depends_on_ray_length(t.color) || graph.depends_on_ray_length(t.strength)) return true;
    for (const Closure::Factor &f : t.weight)
      if (f.node >= 0 && graph.depends_on_ray_length(f.node)) return true;
  }
  return false;
}

// The mean of the textured emission over the unit UV square (and the same square of
// generated coordinates), 32 x 32 points: the power emissive triangles are chosen by.
void Material::average_textured_emission() {
  emission_average = emission;
  if (textured_emission.empty()) return;
  const int n = 32;
  Color sum(0.0f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      ShadingPoint sp;
      sp.uv = {(i + 0.5f) / n, (j + 0.5f) / n};
      sp.generated = sp.p_object = sp.p = Vec3(sp.uv.x, sp.uv.y, 0.5f);
      for (const EmissionTerm &t : textured_emission) sum += emission_of(t, sp);
    }
  emission_average += sum / float(n * n);
}

bool Material::has_textures() const {
  for (size_t i = 0; i < std::min(graph.size(), shading_nodes); ++i)
    if (graph.node(int(i)).type != TexNodeType::Constant) return true;
  return false;
}

const char *Material::type_name() const {
  switch (type) {
    case MaterialType::Diffuse: return "diffuse";
    case MaterialType::Emission: return "emission";
    case MaterialType::Glossy: return "glossy";
    case MaterialType::Glass: return "glass";
    case MaterialType::Refraction: return "refraction";
    case MaterialType::Principled: return "principled";
    case MaterialType::Transparent: return "transparent";
    case MaterialType::Translucent: return "translucent";
    case MaterialType::Sheen: return "sheen";
    case MaterialType::Holdout: return "holdout";
    case MaterialType::Mix: return "mix";
    case MaterialType::Add: return "add";
  }
  return "?";
}

namespace {

Lobe ggx_lobe(float roughness, float anisotropic, bool separable) {
  Lobe l;
  l.ggx.separable = separable;
  float a = sqr(clampf(roughness, 0.0f, 1.0f));
  float aniso = clampf(anisotropic, -1.0f, 1.0f);
  if (aniso != 0) {  // Cycles 3.4: aspect = sqrt(1 - 0.9 anisotropic)
    float aspect = std::sqrt(1.0f - std::max(aniso, 0.0f) * 0.9f);
    if (aniso < 0) aspect = 1.0f / std::sqrt(1.0f + aniso * 0.9f);
    l.ggx.ax = std::min(a / aspect, 1.0f);
    l.ggx.ay = a * aspect;
  } else {
    l.ggx.ax = l.ggx.ay = a;
  }
  l.type = l.ggx.is_smooth() ? LobeType::SpecularConductor : LobeType::GgxConductor;
  return l;
}

Lobe dielectric_lobe(float roughness, float ior, Color color, bool separable) {
  Lobe l;
  float a = sqr(clampf(roughness, 0.0f, 1.0f));
  l.ggx = {a, a, separable};
  l.type = l.ggx.is_smooth() ? LobeType::SmoothDielectric : LobeType::GgxDielectric;
  l.ior = clampf(ior, 1.0001f, 4.0f);
  l.color = color;
  return l;
}

// How often a lobe is sampled: its weight's average, as Cycles 3.4 picks a closure (its
// sample_weight), so which closure a path follows, and whether it passes through a coloured
// transparent layer to write the passes behind it, matches Cycles' (by luminance a green card
// 70% transparent let 73% of samples through, Cycles 78%).
float sample_weight(Color c) { return std::max(average(c), 1e-3f); }

// Pieces of the Principled BSDF shared by shading (textured inputs read at the point
// through col / num) and by resolve_constants (constant inputs).
// The base colour, with the subsurface colour mixed in (subsurface approximated as diffuse).
template <class Col, class Num>
Color principled_base(const Col &col, const Num &num) {
  Color base = vmax(col(kBaseColor), Color(0.0f));
  float sss = clampf(num(kSubsurface), 0.0f, 1.0f);
  if (sss > 0) base = base * (1 - sss) + vmax(col(kSubsurfaceColor), Color(0.0f)) * sss;
  return base;
}
Color hue_of(Color base) {
  float lum = luminance(base);
  return lum > 0 ? base / lum : Color(1.0f);
}
// The dielectric specular's reflectance at normal incidence (specular x its tint).
template <class Col, class Num>
Color principled_specular_f0(const Closure &c, Color tint, const Col &col, const Num &num) {
  float specular = std::max(num(kSpecular), 0.0f);
  Color spec_tint = c.specular_tint_is_color ? vmax(col(kSpecularTint), Color(0.0f))
                                             : Color(1.0f) * (1 - num(kSpecularTint)) + tint * num(kSpecularTint);
  return vmin(spec_tint * (specular * 0.08f), Color(1.0f));
}
// The dielectric specular as a layer above the diffuse and sheen lobes.
LayerAbove principled_specular_layer(Color f0, const GgxDistribution &ggx, bool multiscatter) {
  return schlick_ggx_layer(f0, std::max(std::sqrt(ggx.ax * ggx.ay), 1e-4f), ggx.separable, multiscatter, Color(1.0f));
}
// The clearcoat (f0 0.04) as a layer above every other lobe.
LayerAbove principled_coat_layer(float clearcoat, float coat_roughness, bool separable) {
  return schlick_ggx_layer(Color(0.04f), std::max(sqr(coat_roughness), 1e-4f), separable, false,
                           Color(0.25f * clearcoat));
}

}  // namespace

Color Material::shadow_transmission(const ShadingPoint &sp) const {
  Color t(0.0f);
  for (const Closure &c : closures) {
    if (c.type != MaterialType::Transparent && c.type != MaterialType::Principled) continue;
    const float w = mix_weight(c.weight, sp);
    if (!(w > 0)) continue;
    if (c.type == MaterialType::Transparent) t += vmax(graph.eval(c.in[kBaseColor], sp), Color(0.0f)) * w;
    else t += Color(w * (1.0f - clampf(graph.eval_float(c.in[kAlpha], sp), 0.0f, 1.0f)));
  }
  return vmin(t, Color(1.0f));
}

void Material::write_aovs(const ShadingPoint &sp, AovSample &sample) const {
  for (const Aov &aov : aovs) {
    const ShaderAovs::Pass *pass = sample.layout->find(aov.id);
    if (!pass) continue;  // a name the view layer has no pass for
    float *dst = sample.values + pass->offset;
    if (pass->color) {
      if (aov.color < 0) continue;
      const Color c = graph.eval(aov.color, sp);
      if (!is_finite(c)) continue;
      dst[0] += c.x, dst[1] += c.y, dst[2] += c.z, dst[3] += 1.0f;
    } else if (aov.value >= 0) {
      const float v = graph.eval_float(aov.value, sp);
      if (std::isfinite(v)) dst[0] += v;
    }
  }
}

float Material::holdout_at(const ShadingPoint &sp) const {
  float h = 0;
  for (const Closure &c : closures) {
    if (c.type != MaterialType::Holdout) continue;
    h += mix_weight(c.weight, sp);
  }
  return std::min(h, 1.0f);
}

namespace {

// A sink that marks each lobe with the view factors of the closure it comes from.
template <class Sink>
struct ViewWeightedLobes {
  Sink &sink;
  uint8_t factors, inverted;
  void add_lobe(Lobe l, float sample_weight) {
    l.view_factors = factors;
    l.view_inverted = inverted;
    sink.add_lobe(l, sample_weight);
  }
  uint16_t add_layer(const LayerAbove &layer) { return sink.add_layer(layer); }
};

// The lobes of closure c at sp (w: its mix weight), handed to sink.add_lobe(lobe,
// sample_weight): a Bsdf, or a Material's ResolvedLobes.
template <class Sink>
void add_lobes_of(const Material &m, const Closure &c, float w, const ShadingPoint &sp, Sink &bsdf) {
  const TextureGraph &graph = m.graph;
  const bool cycles34 = m.cycles34_microfacets;  // Cycles 3.4's microfacets (material.h)
  {
    auto col = [&](ClosureInput i) { return c.textured >> i & 1 ? graph.eval(c.in[i], sp) : c.value[i]; };
    auto num = [&](ClosureInput i) { return c.textured >> i & 1 ? graph.eval_float(c.in[i], sp) : c.scalar[i]; };
    switch (c.type) {
      case MaterialType::Diffuse: {
        Lobe l;
        float sigma = clampf(num(kRoughness), 0.0f, 1.0f);
        l.type = sigma > 0 ? LobeType::OrenNayar : LobeType::Lambert;
        l.sigma = sigma;
        l.color = vmax(col(kBaseColor), Color(0.0f)) * w;
        bsdf.add_lobe(l, sample_weight(l.color));
        break;
      }
      case MaterialType::Glossy: {
        Lobe l = ggx_lobe(num(kRoughness), num(kAnisotropic), cycles34);
        l.color = vmax(col(kBaseColor), Color(0.0f));
        l.scale = w;
        l.fresnel_mode = c.fresnel;
        l.eta = c.eta;
        l.k = c.k;
        l.multiscatter = c.multiscatter;
        bsdf.add_lobe(l, sample_weight(l.color * l.scale));
        break;
      }
      case MaterialType::Glass:
      case MaterialType::Refraction: {
        Lobe l = dielectric_lobe(num(kRoughness), num(kIor), vmax(col(kBaseColor), Color(0.0f)) * w, cycles34);
        l.refraction_only = c.type == MaterialType::Refraction;
        l.macro_fresnel = cycles34 && !l.refraction_only;  // Cycles 3.4's glass
        bsdf.add_lobe(l, sample_weight(l.color));
        break;
      }
      case MaterialType::Transparent:
      case MaterialType::Translucent:
      case MaterialType::Sheen: {
        Lobe l;
        l.type = c.type == MaterialType::Transparent ? LobeType::Transparent
                 : c.type == MaterialType::Translucent ? LobeType::Translucent : LobeType::Sheen;
        l.color = vmax(col(kBaseColor), Color(0.0f)) * w;
        bsdf.add_lobe(l, sample_weight(l.color) * (c.type == MaterialType::Sheen ? 0.2f : 1.0f));
        break;
      }
      case MaterialType::Principled: {
        // Blender 3.4's Principled BSDF (intern/cycles/kernel/svm/closure.h) from the lobes.
        Color base = principled_base(col, num);
        float metallic = clampf(num(kMetallic), 0.0f, 1.0f);
        float transmission = clampf(num(kTransmission), 0.0f, 1.0f);
        float alpha = clampf(num(kAlpha), 0.0f, 1.0f);
        float diffuse_w = (1 - metallic) * (1 - transmission);
        float trans_w = transmission * (1 - metallic);
        float spec_w = 1 - trans_w;
        float ww = w * alpha;
        if (alpha < 1) {
          Lobe t;
          t.type = LobeType::Transparent;
          t.color = Color(w * (1 - alpha));
          bsdf.add_lobe(t, w * (1 - alpha));
        }
        if (!(ww > 0)) break;
        Color tint = hue_of(base);
        float roughness = clampf(num(kRoughness), 0.0f, 1.0f);
        // Energy-conserving layering (default): each lobe is scaled by the albedo of the
        // layers above it (coat over everything, specular over diffuse and sheen, sheen
        // over diffuse; layering.cpp), with a Lambertian base. "additive": Cycles 3.4
        // exactly (Disney diffuse, layers simply added), brighter than 1 at grazing angles.
        const bool layered = !c.additive_layers;
        float clearcoat = std::max(num(kClearcoat), 0.0f);
        float coat_rough = clampf(num(kClearcoatRoughness), 0.0f, 1.0f);
        const bool coated = layered && clearcoat > 0;
        Color f0_dielectric = principled_specular_f0(c, tint, col, num);
        Lobe s = ggx_lobe(roughness, num(kAnisotropic), cycles34);
        float sheen = std::max(num(kSheen), 0.0f);
        Color sheen_color = (c.sheen_tint_is_color ? vmax(col(kSheenTint), Color(0.0f))
                                                   : Color(1.0f) * (1 - num(kSheenTint)) + tint * num(kSheenTint)) * sheen;
        // The layers go into the Bsdf once; each lobe names those above it.
        uint16_t sheen_bit = 0, spec_bit = 0, coat_bit = 0;
        if (layered && diffuse_w > 0) {
          if (sheen > 0 && max_component(sheen_color) > 0) sheen_bit = bsdf.add_layer(sheen_layer(sheen_color));
          spec_bit = bsdf.add_layer(c.fixed_specular_layer ? c.specular_layer
                                                           : principled_specular_layer(f0_dielectric, s.ggx, c.multiscatter));
        }
        if (coated)
          coat_bit = bsdf.add_layer(c.fixed_coat_layer ? c.coat_layer
                                                       : principled_coat_layer(clearcoat, coat_rough, cycles34));
        if (diffuse_w > 0) {
          Lobe d;
          d.type = layered ? LobeType::Lambert : LobeType::PrincipledDiffuse;  // Cycles 3.4's Disney diffuse
          d.sigma = roughness;
          d.color = base * (diffuse_w * ww);
          d.layers_above = sheen_bit | spec_bit | coat_bit;
          bsdf.add_lobe(d, sample_weight(d.color));
          if (sheen > 0) {
            Lobe sh;
            sh.type = LobeType::Sheen;
            sh.color = sheen_color * (diffuse_w * ww);
            sh.layers_above = spec_bit | coat_bit;
            bsdf.add_lobe(sh, 0.2f * sample_weight(sh.color));
          }
        }
        // Additive (Cycles 3.4): the specular's Fresnel runs from f0 to white as a dielectric's
        // of the IOR Specular stands for (2 / (1 - sqrt(0.08 specular)) - 1: 1.5 at 0.5, and 1
        // at 0, where nothing but the metallic part reflects); energy-conserving: Schlick's.
        const float spec_ior = 2.0f / (1.0f - std::sqrt(0.08f * clampf(num(kSpecular), 0.0f, 12.0f))) - 1.0f;
        Color f0 = vmin(f0_dielectric * (1 - metallic) + base * metallic, Color(1.0f));
        if (spec_w > 0 && (layered || max_component(f0) > 0 || spec_ior > 1)) {
          s.fresnel_mode = layered ? FresnelMode::Schlick : FresnelMode::Interpolated;
          s.ior = spec_ior;
          s.f0 = f0;
          s.color = Color(1.0f);
          s.scale = spec_w * ww;
          s.multiscatter = c.multiscatter;
          s.layers_above = coat_bit;
          bsdf.add_lobe(s, sample_weight((s.f0 + (Color(1.0f) - s.f0) * 0.1f) * s.scale));
        }
        if (trans_w > 0) {
          float tr = clampf(num(kTransmissionRoughness), 0.0f, 1.0f);
          float r = 1 - (1 - roughness) * (1 - tr);
          Lobe g = dielectric_lobe(r, num(kIor), base * (trans_w * ww), cycles34);
          g.layers_above = coat_bit;
          if (cycles34) {
            // Cycles 3.4: two closures split by the Fresnel at the shading normal, the reflection
            // at the surface's roughness, the refraction tinted at the combined one. The
            // reflection's colour runs from base x Specular Tint + (1 - Specular Tint) at normal
            // incidence to white at grazing (its interpolate_fresnel_color; white at tint 0).
            Lobe reflection = dielectric_lobe(roughness, num(kIor), Color(trans_w * ww), true);
            reflection.macro_fresnel = reflection.reflection_only = true;
            const float glass_tint = clampf(num(kSpecularTint), 0.0f, 1.0f);
            if (glass_tint > 0 && !c.specular_tint_is_color) {
              reflection.fresnel_mode = FresnelMode::Interpolated;
              reflection.f0 = vmin(vmax(base * glass_tint + Color(1.0f - glass_tint), Color(0.0f)), Color(1.0f));
            }
            reflection.layers_above = coat_bit;
            bsdf.add_lobe(reflection, 0.1f * sample_weight(reflection.color));
            g.macro_fresnel = g.refraction_only = true;
          }
          bsdf.add_lobe(g, sample_weight(g.color));
        }
        if (clearcoat > 0) {
          Lobe cc = ggx_lobe(coat_rough, 0.0f, cycles34);
          // Additive (Cycles 3.4): Cycles 3.4's own lobe (GTR1, clearcoat.h) where it is not a
          // mirror, with the dielectric Fresnel of IOR 1.5 (f0 0.04, interpolated).
          if (!layered && cc.type == LobeType::GgxConductor) cc.type = LobeType::Clearcoat;
          cc.fresnel_mode = layered ? FresnelMode::Schlick : FresnelMode::Dielectric;
          cc.ior = 1.5f;
          cc.f0 = Color(0.04f);
          cc.scale = 0.25f * clearcoat * ww;
          bsdf.add_lobe(cc, sample_weight(Color(cc.scale * 0.2f)));
        }
        break;
      }
      case MaterialType::Emission:
      case MaterialType::Holdout:  // no lobe: what is held out scatters nothing
      case MaterialType::Mix:
      case MaterialType::Add: break;
    }
  }
}

// The lobes of every closure at sp. A Bsdf first gets the material's view factors at sp
// (their bits are their indices); a closure under some has its lobes marked with them.
template <class Sink>
void add_closure_lobes(const Material &m, const ShadingPoint &sp, Sink &bsdf) {
  if constexpr (std::is_same_v<Sink, Bsdf>)
    for (const Material::ViewFactorSpec &v : m.view_factors)
      bsdf.add_view_factor(v.at(m.graph.eval_float(v.param, sp)), sp.ns);
  for (const Closure &c : m.closures) {
    const float w = m.mix_weight(c.weight, sp);
    if (!(w > 0)) continue;
    uint8_t factors = 0, inverted = 0;
    for (const Closure::Factor &f : c.weight)
      if (f.view >= 0) {
        factors |= uint8_t(1u << f.view);
        if (f.invert) inverted |= uint8_t(1u << f.view);
      }
    if constexpr (std::is_same_v<Sink, Bsdf>) {
      if (factors) {
        ViewWeightedLobes<Bsdf> marked{bsdf, factors, inverted};
        add_lobes_of(m, c, w, sp, marked);
        continue;
      }
    }
    add_lobes_of(m, c, w, sp, bsdf);  // ResolvedLobes: a material with view factors is never resolved
  }
}

}  // namespace

// One named result and one return: the Bsdf (kilobytes) is built in place, not copied.
Bsdf Material::resolved_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const {
  Bsdf bsdf(ng, ns, wo);
  for (int i = 0; i < resolved.num_layers; ++i) bsdf.add_layer(resolved.layer[i]);  // the same bits again
  for (int i = 0; i < resolved.n; ++i) bsdf.add_lobe(resolved.lobe[i], resolved.weight[i]);
  return bsdf;
}

// Principled layers whose every input is constant are made here, once.
static void fix_constant_layers(Closure &c, bool separable) {
  auto col = [&](ClosureInput i) { return c.value[i]; };
  auto num = [&](ClosureInput i) { return c.scalar[i]; };
  auto constant = [&](std::initializer_list<ClosureInput> inputs) {
    for (ClosureInput i : inputs)
      if (c.textured >> i & 1) return false;
    return true;
  };
  // A scalar specular tint mixes in the base colour's hue.
  bool tint_from_base = !c.specular_tint_is_color && !(constant({kSpecularTint}) && c.scalar[kSpecularTint] == 0);
  c.fixed_specular_layer = constant({kRoughness, kAnisotropic, kSpecular, kSpecularTint}) &&
                           (!tint_from_base || constant({kBaseColor, kSubsurface, kSubsurfaceColor}));
  if (c.fixed_specular_layer) {
    Color f0 = principled_specular_f0(c, hue_of(principled_base(col, num)), col, num);
    c.specular_layer = principled_specular_layer(
        f0, ggx_lobe(clampf(num(kRoughness), 0.0f, 1.0f), num(kAnisotropic), separable).ggx, c.multiscatter);
  }
  c.fixed_coat_layer = constant({kClearcoat, kClearcoatRoughness});
  if (c.fixed_coat_layer)
    c.coat_layer = principled_coat_layer(std::max(num(kClearcoat), 0.0f), clampf(num(kClearcoatRoughness), 0.0f, 1.0f),
                                         separable);
}

void Material::resolve_constants() {
  for (Closure &c : closures) {
    c.textured = 0;
    for (int i = 0; i < kNumClosureInputs; ++i) {
      if (c.in[i] < 0) continue;
      if (!graph.is_constant(c.in[i])) c.textured |= 1u << i;
      else c.scalar[i] = luminance(c.value[i] = graph.node(c.in[i]).value);
    }
    if (c.type == MaterialType::Principled && !c.additive_layers) fix_constant_layers(c, cycles34_microfacets);
  }
  resolved.n = -1;
  if (has_textures() || !view_factors.empty()) return;  // normal maps and bump are texture nodes too
  for (const Closure &c : closures)
    if (c.in[kAnisotropic] >= 0 && graph.node(c.in[kAnisotropic]).value.x != 0) return;  // needs the UV tangent
  resolved.n = 0;
  add_closure_lobes(*this, ShadingPoint{}, resolved);
}

Bsdf Material::make_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const {
  if (is_constant()) return resolved_bsdf(ng, ns, wo);
  ShadingPoint sp;
  sp.ng = ng;
  sp.ns = ns;
  sp.p_object = sp.generated = Vec3(0.0f);
  return make_bsdf(sp, wo);
}

Bsdf Material::make_bsdf(const ShadingPoint &sp, Vec3 wo) const {
  return is_constant() ? resolved_bsdf(sp.ng, sp.ns, wo) : shaded_bsdf(sp, wo);
}

// Textures, normal maps and anisotropy evaluated at sp (one named result: built in place).
Bsdf Material::shaded_bsdf(const ShadingPoint &sp, Vec3 wo) const {
  if (surface_normal < 0) return shaded_bsdf_at(sp, wo, false);
  ShadingPoint moved = sp;  // evaluated at the unmoved normal, as Cycles evaluates the bump first
  moved.ns = graph.eval_normal(surface_normal, sp);
  return shaded_bsdf_at(moved, wo, true);
}

Bsdf Material::shaded_bsdf_at(const ShadingPoint &sp, Vec3 wo, bool surface_normal_set) const {
  // One shading frame per Bsdf: the first closure with a normal input sets it.
  Vec3 ns = sp.ns;
  bool mapped = surface_normal_set;
  for (const Closure &c : closures)
    if (c.normal >= 0) { ns = graph.eval_normal(c.normal, sp); mapped = true; break; }
  // Anisotropy follows the default UV map's u direction, rotated about the normal.
  Vec3 tangent(0.0f);
  for (const Closure &c : closures) {
    if (c.in[kAnisotropic] < 0 || !sp.has_uv_frame) continue;
    if ((c.textured >> kAnisotropic & 1 ? graph.eval_float(c.in[kAnisotropic], sp) : c.scalar[kAnisotropic]) == 0)
      continue;
    float rot = graph.eval_float(c.in[kAnisoRotation], sp) * 2.0f * kPi;
    Vec3 t = sp.dpdu - ns * dot(ns, sp.dpdu);
    if (!(length_squared(t) > 0)) break;
    t = normalize(t);
    Vec3 b = cross(ns, t);
    tangent = t * std::cos(rot) + b * std::sin(rot);
    break;
  }
  Bsdf bsdf(sp.ng, ns, wo, tangent);
  // A mapped normal that would reflect a viewer below the surface is bent (as Cycles),
  // for each direction that sees it: not only toward wo (light paths build toward the light).
  // The diffuse lobes' bump shadowing measures against sp.ns, which a surface normal has set
  // (Cycles' sd->N): under that normal alone there is none.
  if (mapped) bsdf.bend_for_each_viewer(sp.ns);
  add_closure_lobes(*this, sp, bsdf);
  return bsdf;
}

}  // namespace rdv
