// A material as the scene stores it, and the Bsdf it yields at a surface point.
//
// A material is a flat list of closures (diffuse, glossy, glass, principled, ...), each
// with a weight that is a product of Mix Shader factors (fac or 1 - fac, possibly
// textured): "mix" and "add" nodes of any depth flatten into that list when the
// material is parsed. Every colour / float parameter of a closure is a node of the
// material's TextureGraph (a constant or a texture graph), evaluated at the shading
// point. Only the lobes a material needs are built: a diffuse material runs no
// microfacet code. docs/scene-format.md lists the JSON keys.
#pragma once
#include <cstdint>
#include <string>
#include <vector>
#include "bsdfs/bsdf.h"
#include "core/params.h"
#include "film/shader_aovs.h"
#include "textures/texture_graph.h"

namespace rdv {

enum class MaterialType : uint8_t {
  Diffuse, Emission, Glossy, Glass, Refraction, Principled, Transparent, Translucent, Sheen, Holdout, Mix, Add
};

// Inputs of a closure (index into Closure::in). Not every closure uses every input.
enum ClosureInput : uint8_t {
  kBaseColor, kRoughness, kIor, kMetallic, kSpecular, kSpecularTint, kAnisotropic, kAnisoRotation, kSheen,
  kSheenTint, kClearcoat, kClearcoatRoughness, kTransmission, kTransmissionRoughness, kAlpha, kSubsurface,
  kSubsurfaceColor, kNumClosureInputs
};

struct Closure {
  MaterialType type = MaterialType::Diffuse;
  int in[kNumClosureInputs];  // texture-graph node per input (-1: unused)
  int normal = -1;            // normal_map / bump node, or -1 (the interpolated normal)
  // Mix Shader factors along the path from the root: weight = prod (invert ? 1 - f : f).
  // view >= 0: the factor is Material::view_factors[view] (node unused), which depends on
  // the direction and is applied by the Bsdf per pair of directions (view_factor.h).
  struct Factor { int node; bool invert; int view = -1; };
  std::vector<Factor> weight;
  // Glossy: conductor Fresnel from a complex IOR (constant), multiscatter flag.
  FresnelMode fresnel = FresnelMode::Tint;
  Color eta{1.0f}, k{0.0f};
  bool multiscatter = false;
  bool specular_tint_is_color = false, sheen_tint_is_color = false;  // Blender 4.x sockets
  bool additive_layers = false;  // Principled "layering": "additive" (Cycles 3.4 exactly)
  // Inputs' values where they are constant (textured: bit set in `textured`), so a
  // textured material evaluates only its textured inputs per hit.
  uint32_t textured = 0;
  Color value[kNumClosureInputs];
  float scalar[kNumClosureInputs] = {};  // luminance(value): the input read as a float
  // Principled layers (energy-conserving) whose inputs are all constant, made once when
  // parsed: a textured base colour then costs no albedo-table setup per hit.
  bool fixed_specular_layer = false, fixed_coat_layer = false;
  LayerAbove specular_layer, coat_layer;
  Closure() { for (int &i : in) i = -1; }
};

struct Material {
  std::string name;
  MaterialType type = MaterialType::Diffuse;  // of the root node (for summaries)
  // Emitted radiance, both faces (Cycles' Emission / Principled Emission): the constant
  // part here, textured terms (colour, strength or mix factor from textures) apart.
  Color emission{0.0f};
  struct EmissionTerm {
    int color = -1, strength = -1;  // texture-graph nodes
    std::vector<Closure::Factor> weight;
  };
  std::vector<EmissionTerm> textured_emission;
  Color emission_average{0.0f};  // emission + the textured terms' mean over the UV square
  std::vector<Closure> closures;
  // The Fresnel / Layer Weight nodes that are Mix Shader factors (at most
  // Bsdf::kMaxViewFactors; others are their cosine-weighted mean, with a warning): kind and
  // the graph node of its IOR or blend. A material with any is shaded per hit (not resolved).
  struct ViewFactorSpec {
    ViewFactorKind kind;
    int param;
    std::vector<float> table;  // ViewFactor::table (empty: none)
    ViewFactor at(float param_value) const {
      return {kind, param_value, table.empty() ? nullptr : table.data(), int(table.size())};
    }
  };
  std::vector<ViewFactorSpec> view_factors;
  TextureGraph graph;
  std::vector<std::string> warnings;  // for Scene::warn (missing images, approximations)
  bool transparent = false;  // may let shadow rays through (Transparent BSDF, Principled alpha)
  bool holdout = false;      // has a Holdout closure (integrators/film_alpha.h)
  float pass_index = 0;      // Material > Settings > Pass Index (film/data_passes.h)
  // Cryptomatte (film/cryptomatte.h): the name its Material pass shows ("cryptomatte",
  // default the material's own: the exporter names each look copy after its Blender material).
  std::string crypto_name;
  float crypto_id = 0;
  // "microfacets": "cycles_3.4" (Blender 3.x scenes): every GGX lobe shadowed by the separable
  // G1 G1 (microfacet.h) and rough glass split by the Fresnel at the shading normal
  // (dielectric.h), as Cycles 3.4; "physical" (default): height-correlated, Fresnel per facet.
  bool cycles34_microfacets = false;
  // "surface_normal": a normal node (the add-on's bump from the Material Output's Displacement)
  // that replaces the shading normal for all the material evaluates, as Cycles' SetNormal sets
  // sd->N: closures without a normal of their own, the base of Bump nodes, Geometry > Normal,
  // view factors, and the reference of the diffuse lobes' bump shadowing. -1: none.
  int surface_normal = -1;
  // "displacement": a vector node (world-space offset, the add-on's Displacement output) that
  // moves the vertices of the meshes using the material (scene/displacement.cpp), as Cycles'
  // true displacement; "displacement_method": "true" recomputes the smooth normals from the
  // moved faces, "both" keeps them (its bump is the surface_normal). -1: none.
  int displacement = -1;
  bool displacement_keeps_normals = false;
  // "aovs": {"name": {"color": node, "value": node}}: the material's AOV Output nodes
  // (film/shader_aovs.h), written where the camera first sees it. Their nodes follow the
  // shading nodes (shading_nodes), so a plain material stays constant.
  struct Aov {
    uint32_t id = 0;  // attribute_id of the name
    int color = -1, value = -1;
  };
  std::vector<Aov> aovs;
  // Adds this material's AOV Outputs at sp to the sample's passes of their names.
  void write_aovs(const ShadingPoint &sp, AovSample &sample) const;
  // The graph's nodes that shading reads: those before the displacement's, which only
  // the mesh's vertices see (a displaced material may still be resolved as constant).
  size_t shading_nodes = SIZE_MAX;
  // A constant material (no texture, normal map or anisotropy) has its lobes resolved
  // once, when parsed: shading a hit then copies them, and needs no ShadingPoint.
  struct ResolvedLobes {
    int n = -1;  // -1: not constant
    Lobe lobe[Bsdf::kMaxLobes];
    float weight[Bsdf::kMaxLobes];
    int num_layers = 0;
    LayerAbove layer[Bsdf::kMaxLayers];
    // The same rules as Bsdf::add_lobe / add_layer (lobe_merge.h past the capacity).
    void add_lobe(const Lobe &l, float w);
    uint16_t add_layer(const LayerAbove &l);
  };
  ResolvedLobes resolved;

  // Image texture nodes naming a "buffer" find it in `images` (rdv_scene_add_image).
  static Material from_params(Params &p, const std::string &name, const ImageBuffers *images = nullptr);
  // The magenta stand-in Blender shows for a material it cannot use.
  static Material error_material(const std::string &name);
  bool emits() const { return !is_black(emission) || !textured_emission.empty(); }
  // Radiance emitted at sp (textures evaluated there).
  Color emission_at(const ShadingPoint &sp) const;
  Color emission_of(const EmissionTerm &e, const ShadingPoint &sp) const;
  // Whether the emission depends on how far its light travels (a Light Falloff: sp.ray_length).
  bool emission_by_distance() const;
  // The product of the Mix Shader factors on a closure's path at sp, but for view factors
  // (which the Bsdf applies per direction).
  float mix_weight(const std::vector<Closure::Factor> &factors, const ShadingPoint &sp) const;
  bool has_textures() const;
  bool is_constant() const { return resolved.n >= 0; }
  const char *type_name() const;
  // Bsdf at a surface point (textures, normal maps, bump, named attributes).
  Bsdf make_bsdf(const ShadingPoint &sp, Vec3 wo) const;
  // What passes straight through at sp (the Transparent lobes' weight): for shadow rays.
  Color shadow_transmission(const ShadingPoint &sp) const;
  // What of the surface at sp is held out (the Holdout closures' weight, at most 1): it
  // scatters nothing, and camera paths that see it leave that much alpha.
  float holdout_at(const ShadingPoint &sp) const;
  // Without surface information (textures see uv = 0): for callers that have none,
  // and for constant materials, which need none.
  Bsdf make_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const;

 private:
  // Constant closure inputs to values; all constant: the lobes too (ResolvedLobes).
  void resolve_constants();
  void average_textured_emission();
  // A warning when the closures may make more lobes or layers than a Bsdf holds.
  void warn_if_lobes_merge();
  Bsdf resolved_bsdf(Vec3 ng, Vec3 ns, Vec3 wo) const;
  Bsdf shaded_bsdf(const ShadingPoint &sp, Vec3 wo) const;
  Bsdf shaded_bsdf_at(const ShadingPoint &sp, Vec3 wo, bool surface_normal_set) const;
};

}  // namespace rdv
