// Texture graphs: any colour or float parameter of a material may be a constant or a
// small graph of texture nodes evaluated at the shading point (docs/scene-format.md,
// "Textures"). Nodes live in one vector per material; inputs refer to other nodes by
// index, so evaluation is a recursive switch without allocation.
//
// Values are RGB triples; a float is stored as (v, v, v), and a colour used as a float
// is reduced to its Rec.709 luminance (as Cycles converts colour to float).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "core/math.h"
#include "textures/image_buffers.h"
#include "textures/image_texture.h"
#include "textures/shading_point.h"

namespace rdv { class IesProfile; }

namespace rdv {

enum class TexNodeType : uint8_t {
  Constant, Image, Checker, Noise, Gradient, MixRgb, Math, ColorRamp, Invert, HueSat,
  Attribute,  // named UV map or vertex colour
  TexCoord,   // uv / generated / object / world position / normal
  Mapping, NormalMap, Bump, SeparateRgb, CombineRgb, RgbToBw, BrightContrast, Gamma,
  Voronoi, Musgrave, Wave, Magic, Brick, WhiteNoise,  // Blender's procedural textures, as Cycles 3.4
  Curves,  // RGB / Vector Curves (mode 0) and Float Curve (mode 1): a baked table, as Cycles
  VectorMath, MapRange,  // math_nodes.h
  ObjectInfo,  // the instance's location, colour, alpha, pass index, random; the material's index
  ColorSpace,  // RGB <-> HSV / HSL (Separate and Combine Color)
  Blackbody,   // Planck's colour at a temperature (media/blackbody.h)
  Wavelength,  // a spectral colour (Cycles' Wavelength node)
  Wireframe,   // 1 within half a width of the triangle's edges (Cycles' Wireframe node)
  AmbientOcclusion,  // the unoccluded share of directions around the normal (textures/ambient_occlusion.h)
  Bevel,             // a normal averaged over the object's nearby surfaces (textures/bevel.h)
  Displacement,       // Blender's Displacement node: an offset along the normal, in the world
  VectorDisplacement,  // Blender's Vector Displacement node: an offset in tangent / object / world space
  CameraData,          // the point in the camera's space: view vector, z depth, distance
  Ies,                 // an IES profile's intensity along a direction (lights/ies_profile.h)
  LightFalloff         // Blender's Light Falloff: Strength by the ray's length (ShadingPoint::ray_length)
};

constexpr int kTexNodeInputs = 10;  // the most any node has (Brick)

struct RampStop { float position; Color color; float alpha; };

struct TexNode {
  TexNodeType type = TexNodeType::Constant;
  uint8_t mode = 0;     // node-specific enum (blend type, math op, gradient type, Voronoi feature, ...)
  uint8_t output = 0;   // which output: 0 = color / value / vector, 1 = alpha / fac, 2.. per node
  bool clamp = false;
  Color value{0.0f};    // Constant
  int in[kTexNodeInputs] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1};  // input nodes (-1: unused)
  // Image
  int image = -1;       // ImageTextures id; -1: missing (magenta)
  std::shared_ptr<const MemoryImage> memory;  // keeps an image from memory alive
  std::vector<std::pair<int, int>> udim;  // UDIM (tile number, ImageTextures id); empty: one image
  TexInterp interp = TexInterp::Linear;
  TexExtension ext = TexExtension::Repeat;
  // Attribute
  uint32_t attribute = 0;
  bool default_uv = false;
  // Mapping: location, rotation (radians, XYZ Euler), scale
  Vec3 loc{0.0f}, rot{0.0f}, scale{1.0f};
  // Procedural textures (noise.h, voronoi.h, musgrave.h, pattern_textures.h)
  uint8_t dims = 3;   // Noise, Voronoi, Musgrave, White Noise: 1 to 4 dimensions
  uint8_t mode2 = 0;  // Voronoi: distance metric; Wave: bands / rings direction; Map Range: vector
  uint8_t mode3 = 0;  // Wave: profile
  int depth = 2;      // Magic: nested turns
  float offset = 0.5f, squash = 1.0f;           // Brick
  int offset_frequency = 2, squash_frequency = 2;
  std::vector<RampStop> ramp;  // ColorRamp
  // ColorRamp baked as Cycles bakes it (Blender's evaluation at i / (n - 1), alpha in the
  // stop's alpha), and Curves (x from min_x to max_x): looked up by ramp_lookup.
  std::vector<RampStop> table;
  float min_x = 0, max_x = 1;
  // Ies: the profile (null: none could be read, Cycles' constant 100)
  std::shared_ptr<const IesProfile> ies;
};

class TextureGraph {
 public:
  // Parses a parameter value: a number, [r,g,b] / [r,g,b,a], or a node object.
  // Returns a node index. Problems that do not stop rendering (missing image) are
  // appended to warnings; malformed input throws (fail()) naming `what`.
  // Image nodes naming a "buffer" find it in image_buffers (set while parsing; null: none).
  int parse(const nlohmann::json &j, const std::string &what, std::vector<std::string> &warnings);
  const ImageBuffers *image_buffers = nullptr;
  int constant(Color c);
  Color eval(int node, const ShadingPoint &sp) const {  // constants inline: most inputs are
    const TexNode &n = nodes_[size_t(node)];
    return n.type == TexNodeType::Constant ? n.value : eval_node(n, node, sp);
  }
  float eval_float(int node, const ShadingPoint &sp) const { return luminance(eval(node, sp)); }
  // Whether the node's value depends on the shading point's normal (Texture Coordinate's
  // normals, or nodes fed by them): a lamp's tree then varies with the direction it emits in.
  bool depends_on_normal(int node) const;
  // Whether it depends on the length of the ray the emitted light travels (Light Falloff):
  // an emitter's radiance then depends on the point it lights.
  bool depends_on_ray_length(int node) const;
  // Whether it depends on where the shading point is (its position, texture coordinates
  // other than normals, attributes): a lamp's tree then varies over the lamp.
  bool depends_on_point(int node) const;
  bool is_constant(int node) const { return node >= 0 && nodes_[size_t(node)].type == TexNodeType::Constant; }
  const TexNode &node(int i) const { return nodes_[size_t(i)]; }
  size_t size() const { return nodes_.size(); }
  int num_images() const;
  // A normal-perturbing node (normal_map / bump / bevel) evaluated to a world-space unit normal.
  Vec3 eval_normal(int node, const ShadingPoint &sp) const;

 private:
  template <typename Leaf>
  bool any_in_subgraph(int node, const Leaf &leaf) const;  // leaf(n) for a node feeding `node`
  int add(const TexNode &n);  // bounds the evaluations per shading point (kMaxTextureEvaluations)
  Color eval_node(const TexNode &n, int idx, const ShadingPoint &sp) const;
  int parse_node(const nlohmann::json &j, const std::string &what, std::vector<std::string> &warnings);
  std::vector<TexNode> nodes_;
  std::vector<double> evaluations_;  // per node: its subgraph's node evaluations per shading point
  int parse_depth_ = 0;     // texture nodes above the one being parsed (kMaxTextureDepth)
  std::string parse_root_;  // the material input being parsed, for the limit's message
};

}  // namespace rdv
