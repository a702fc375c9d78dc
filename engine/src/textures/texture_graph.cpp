#include "textures/texture_graph.h"
#include "textures/texture_rays.h"
#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include "core/cie_1931.h"
#include "core/error.h"
#include "core/limits.h"
#include "lights/ies_profile.h"
#include "media/blackbody.h"
#include "scene/mesh.h"
#include "textures/ambient_occlusion.h"
#include "textures/bevel.h"
#include "textures/math_nodes.h"
#include "textures/musgrave.h"
#include "textures/noise.h"
#include "textures/pattern_textures.h"
#include "textures/voronoi.h"

namespace rdv {

using nlohmann::json;

namespace {

// Normals between object space and the world: to the world by the inverse transpose of the
// object-to-world matrix (the cofactors' rows, by the sign of the determinant: a direction, its
// length not kept), back by the transpose (the same up to a positive scale).
Vec3 normal_to_world(const ShadingPoint &sp, Vec3 n) {
  if (!sp.has_object_to_world) return n;
  const float *M = sp.object_to_world;
  const Vec3 r0(M[0], M[1], M[2]), r1(M[4], M[5], M[6]), r2(M[8], M[9], M[10]);
  const Vec3 c0 = cross(r1, r2), c1 = cross(r2, r0), c2 = cross(r0, r1);
  return Vec3(dot(c0, n), dot(c1, n), dot(c2, n)) * (dot(r0, c0) < 0 ? -1.0f : 1.0f);
}
// A direction (an offset) from object space to the world: by the object-to-world matrix.
Vec3 direction_to_world(const ShadingPoint &sp, Vec3 d) {
  if (!sp.has_object_to_world) return d;
  const float *M = sp.object_to_world;
  return {M[0] * d.x + M[1] * d.y + M[2] * d.z, M[4] * d.x + M[5] * d.y + M[6] * d.z, M[8] * d.x + M[9] * d.y + M[10] * d.z};
}
Vec3 normal_to_object(const ShadingPoint &sp, Vec3 n) {
  if (!sp.has_object_to_world) return n;
  const float *M = sp.object_to_world;
  return {M[0] * n.x + M[4] * n.y + M[8] * n.z, M[1] * n.x + M[5] * n.y + M[9] * n.z, M[2] * n.x + M[6] * n.y + M[10] * n.z};
}

// A tangent-space normal map as Cycles applies it (svm_node_normal_map) with the mesh's
// per-corner tangents and bitangent signs from Blender's MikkTSpace (the exporter sends them
// as the attribute kTangentAttribute: x, y, z, sign), all in object space: the interpolated,
// unnormalised tangent T and vertex normal n (the geometric normal on a flat mesh), B = sign
// n x T, the map's m over (T, B, n), normalised, then carried to the world as a normal.
// False without the attribute (the caller frames the map by dp/du instead).
bool tangent_space_normal(const ShadingPoint &sp, Vec3 m, Vec3 &out) {
  static const uint32_t kTangent = attribute_id("__rdv_tangent");
  float a[4];
  int components = 0;
  if (!sp.mesh || !sp.attribute(kTangent, a, components) || components != 4) return false;
  const Vec3 n = sp.mesh->normals.empty() ? normal_to_object(sp, sp.ng)
                                          : sp.mesh->normals[sp.v[0]] * sp.b[0] + sp.mesh->normals[sp.v[1]] * sp.b[1] +
                                                sp.mesh->normals[sp.v[2]] * sp.b[2];
  const Vec3 t(a[0], a[1], a[2]);
  const Vec3 b = cross(n, t) * a[3];
  out = normal_to_world(sp, t * m.x + b * m.y + n * m.z);
  return length_squared(out) > 0;
}

// Geometry > Tangent as Cycles makes it for a mesh (primitive_tangent): the direction around
// the object's Z axis through the Generated coordinates' centre, (-(g.y - 0.5), g.x - 0.5, 0)
// carried to the world as a normal is (the inverse transpose), then made perpendicular to the
// shading normal on the side of the reaching ray. On the axis itself: along dp/du.
Vec3 radial_tangent(const ShadingPoint &sp) {
  const Vec3 n = sp.backfacing ? -sp.ns : sp.ns;
  const Vec3 around = normal_to_world(sp, Vec3(-(sp.generated.y - 0.5f), sp.generated.x - 0.5f, 0.0f));
  const Vec3 side = cross(around, n);
  if (!(length_squared(side) > 0)) {
    const float l = length(sp.dpdu);
    return l > 0 ? sp.dpdu / l : Vec3(0.0f);
  }
  return cross(n, normalize(side));
}

// Cycles' Wireframe node (svm_wireframe): 1 where the point lies within half of `size` of
// one of its triangle's edges (the lines through them), in world units, or in pixel widths
// with pixel_size (the ray's footprint on the surface; Cycles projects it onto the plane
// facing the viewer, which a footprint along the surface only approximates). Each edge is
// shared, so its neighbour draws the other half. Blender's triangulation, as Cycles sees it.
float wireframe(const ShadingPoint &sp, float size, bool pixel_size) {
  if (!sp.mesh) return 0.0f;
  Vec3 co[3];
  for (int i = 0; i < 3; ++i) {
    const Vec3 p = sp.mesh->positions[sp.v[i]];
    const float *M = sp.object_to_world;
    co[i] = sp.has_object_to_world ? Vec3(M[0] * p.x + M[1] * p.y + M[2] * p.z + M[3],
                                          M[4] * p.x + M[5] * p.y + M[6] * p.z + M[7],
                                          M[8] * p.x + M[9] * p.y + M[10] * p.z + M[11])
                                   : p;
  }
  float width = 1.0f;
  if (pixel_size) {
    const Vec3 dx = sp.dpdu * sp.dx.x + sp.dpdv * sp.dx.y, dy = sp.dpdu * sp.dy.x + sp.dpdv * sp.dy.y;
    width = 0.5f * (length(dx) + length(dy));
  }
  const float half = 0.5f * size * width, half2 = half * half;
  for (int i = 0; i < 3; ++i) {
    const Vec3 to_point = sp.p - co[i], edge = co[i ? i - 1 : 2] - co[i];
    if (length_squared(cross(to_point, edge)) <= half2 * length_squared(edge)) return 1.0f;
  }
  return 0.0f;
}

// ---- small colour helpers ----------------------------------------------------------
// Cycles' Wavelength node: the CIE 1931 colour matching functions at nm (linear between their
// 5 nm samples from 380 nm, black from 780 nm on and below 375 nm: Cycles truncates toward zero,
// so 375-380 nm extrapolates the first interval) in scene-linear Rec.709, scaled by 1 / 2.52
// (Cycles' scale, which keeps every component at most 1), negative components clipped.
Color wavelength_color(float nm) {
  const float x = (nm - 380.0f) / float(cie::kStepNm);
  if (!(x > -1.0f && x < 80.0f)) return Color(0.0f);
  const int i = int(x), c = cie::index_of(380.0) + i;
  const double t = x - float(i);
  auto at = [&](const double *f) { return f[c] + (f[c + 1] - f[c]) * t; };
  double r, g, b;
  cie::xyz_to_rec709(at(cie::kX), at(cie::kY), at(cie::kZ), r, g, b);
  return Color(float(std::max(r, 0.0) / 2.52), float(std::max(g, 0.0) / 2.52), float(std::max(b, 0.0) / 2.52));
}

Color rgb_to_hsv(Color c) {
  float cmax = max_component(c), cmin = std::min(c.x, std::min(c.y, c.z)), d = cmax - cmin;
  float h = 0, s = cmax != 0 ? d / cmax : 0;
  if (s != 0) {
    Color cc = (Color(cmax) - c) / d;
    if (c.x == cmax) h = cc.z - cc.y;
    else if (c.y == cmax) h = 2.0f + cc.x - cc.z;
    else h = 4.0f + cc.y - cc.x;
    h /= 6.0f;
    if (h < 0) h += 1.0f;
  }
  return {h, s, cmax};
}

// Cycles' rgb_to_hsl / hsl_to_rgb (util/color.h), for Separate / Combine Color in HSL.
Color rgb_to_hsl(Color c) {
  const float cmax = max_component(c), cmin = std::min(c.x, std::min(c.y, c.z));
  const float l = std::min(1.0f, (cmax + cmin) / 2.0f);
  float h = 0, s = 0;
  if (cmax != cmin) {
    const float d = cmax - cmin;
    s = l > 0.5f ? d / (2.0f - cmax - cmin) : d / (cmax + cmin);
    if (cmax == c.x) h = (c.y - c.z) / d + (c.y < c.z ? 6.0f : 0.0f);
    else if (cmax == c.y) h = (c.z - c.x) / d + 2.0f;
    else h = (c.x - c.y) / d + 4.0f;
  }
  return {h / 6.0f, s, l};
}

Color hsl_to_rgb(Color hsl) {
  const float h = hsl.x, s = hsl.y, l = hsl.z;
  const float r = clampf(std::fabs(h * 6.0f - 3.0f) - 1.0f, 0.0f, 1.0f);
  const float g = clampf(2.0f - std::fabs(h * 6.0f - 2.0f), 0.0f, 1.0f);
  const float b = clampf(2.0f - std::fabs(h * 6.0f - 4.0f), 0.0f, 1.0f);
  const float chroma = (1.0f - std::fabs(2.0f * l - 1.0f)) * s;
  return {(r - 0.5f) * chroma + l, (g - 0.5f) * chroma + l, (b - 0.5f) * chroma + l};
}

Color hsv_to_rgb(Color hsv) {
  float h = hsv.x, s = hsv.y, v = hsv.z;
  if (s == 0) return Color(v);
  if (h == 1.0f) h = 0;
  if (!std::isfinite(h)) return Color(0.0f);
  h *= 6.0f;
  float i = std::floor(h), f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (int(i)) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

Color lerp(Color a, Color b, float t) { return a * (1 - t) + b * t; }
Color clamp01(Color c) { return vmin(vmax(c, Color(0.0f)), Color(1.0f)); }

Vec3 euler_rotate(Vec3 v, Vec3 r) {  // XYZ Euler (Blender): R = Rz Ry Rx
  float c, s, y, z, x;
  c = std::cos(r.x); s = std::sin(r.x); y = c * v.y - s * v.z; z = s * v.y + c * v.z; v.y = y; v.z = z;
  c = std::cos(r.y); s = std::sin(r.y); x = c * v.x + s * v.z; z = -s * v.x + c * v.z; v.x = x; v.z = z;
  c = std::cos(r.z); s = std::sin(r.z); x = c * v.x - s * v.y; y = s * v.x + c * v.y; v.x = x; v.y = y;
  return v;
}
Vec3 euler_rotate_inverse(Vec3 v, Vec3 r) {
  float c, s, y, z, x;
  c = std::cos(-r.z); s = std::sin(-r.z); x = c * v.x - s * v.y; y = s * v.x + c * v.y; v.x = x; v.y = y;
  c = std::cos(-r.y); s = std::sin(-r.y); x = c * v.x + s * v.z; z = -s * v.x + c * v.z; v.x = x; v.z = z;
  c = std::cos(-r.x); s = std::sin(-r.x); y = c * v.y - s * v.z; z = s * v.y + c * v.z; v.y = y; v.z = z;
  return v;
}

std::string upper(std::string s) {
  for (char &c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  for (char &c : s) if (c == ' ') c = '_';
  return s;
}

// Mode tables (Blender's enum identifiers; matched case-insensitively).
const std::vector<std::string> kBlendTypes = {"MIX", "ADD", "MULTIPLY", "SUBTRACT", "SCREEN", "DIVIDE", "DIFFERENCE",
                                              "DARKEN", "LIGHTEN", "OVERLAY", "DODGE", "BURN", "HUE", "SATURATION",
                                              "VALUE", "COLOR", "SOFT_LIGHT", "LINEAR_LIGHT"};
const std::vector<std::string> kMathOps = {"ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "POWER", "LOGARITHM",
                                           "SQRT", "INVERSE_SQRT", "ABSOLUTE", "EXPONENT", "MINIMUM", "MAXIMUM",
                                           "LESS_THAN", "GREATER_THAN", "SIGN", "COMPARE", "ROUND", "FLOOR", "CEIL",
                                           "TRUNC", "FRACT", "MODULO", "WRAP", "SNAP", "PINGPONG", "SINE", "COSINE",
                                           "TANGENT", "ARCSINE", "ARCCOSINE", "ARCTANGENT", "ARCTAN2", "SINH", "COSH",
                                           "TANH", "RADIANS", "DEGREES", "SMOOTH_MIN", "SMOOTH_MAX"};
const std::vector<std::string> kDimensions = {"1D", "2D", "3D", "4D"};
const std::vector<std::string> kGradients = {"LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL",
                                             "QUADRATIC_SPHERE", "RADIAL"};
// Texture Coordinate's and Geometry's outputs: normal is the world shading normal (Geometry >
// Normal), object_normal the same in object space (Texture Coordinate > Normal), true_normal
// the triangle's (Geometry > True Normal).
enum Coord : uint8_t { kUv, kGenerated, kObject, kPosition, kNormal, kObjectNormal, kTrueNormal, kParametric, kTangent };

// A JSON number as the engine's float: anything else, or a value float cannot hold
// (1e39), is an error naming `what` (the node and its field).
float finite_float(const json &v, const std::string &what) {
  if (!v.is_number()) fail(what + " must be a number, got " + v.dump());
  float f = static_cast<float>(v.get<double>());
  if (!std::isfinite(f)) fail(what + " is " + v.dump() + ", not a finite number");
  return f;
}

// A baked lookup table: 2 to 4096 entries, each a number (width 1) or `width` numbers (3:
// a colour, 4: a colour and alpha), as ramp stops evenly spaced over [0, 1].
std::vector<RampStop> parse_table(const json &t, const std::string &what, int width) {
  if (!t.is_array() || t.size() < 2 || t.size() > 4096) fail(what + " must be a list of 2 to 4096 entries");
  std::vector<RampStop> out;
  for (size_t i = 0; i < t.size(); ++i) {
    const json &e = t[i];
    RampStop s{float(i) / float(t.size() - 1), Color(0.0f), 1.0f};
    if (width == 1) {
      s.color = Color(finite_float(e, what));
    } else {
      if (!e.is_array() || int(e.size()) != width) fail(what + ": each entry must be " + std::to_string(width) + " numbers");
      s.color = {finite_float(e[0], what), finite_float(e[1], what), finite_float(e[2], what)};
      if (width == 4) s.alpha = finite_float(e[3], what);
    }
    out.push_back(s);
  }
  return out;
}

// Cycles' rgb_ramp_lookup: entry i at f = i / (n - 1), linear between entries (or the
// entry below), clamped to [0, 1] or extrapolated along the end segments.
RampStop ramp_lookup(const std::vector<RampStop> &table, float f, bool interpolate, bool extrapolate) {
  const int n = int(table.size());
  if (extrapolate && (f < 0.0f || f > 1.0f)) {
    const RampStop &t0 = f < 0.0f ? table[0] : table[size_t(n - 1)];
    const RampStop &t1 = f < 0.0f ? table[1] : table[size_t(n - 2)];
    const float d = (f < 0.0f ? -f : f - 1.0f) * float(n - 1);
    return {f, t0.color + (t0.color - t1.color) * d, t0.alpha + (t0.alpha - t1.alpha) * d};
  }
  f = clampf(f, 0.0f, 1.0f) * float(n - 1);
  const int i = std::isnan(f) ? 0 : std::clamp(int(f), 0, n - 1);
  const float t = f - float(i);
  RampStop a = table[size_t(i)];
  if (interpolate && t > 0.0f) {
    const RampStop &b = table[size_t(i + 1)];
    a.color = a.color * (1.0f - t) + b.color * t;
    a.alpha = (1.0f - t) * a.alpha + t * b.alpha;
  }
  return a;
}

// Tracks the keys a node object uses, so unknown keys are reported.
struct NodeReader {
  const json &j;
  std::string what;
  std::set<std::string> used{"node"};
  bool has(const char *k) { used.insert(k); return j.contains(k); }
  std::string str(const char *k, const std::string &fallback) {
    if (!has(k)) return fallback;
    if (!j[k].is_string()) fail(what + ": '" + k + "' must be a string");
    return j[k].get<std::string>();
  }
  float num(const char *k, float fallback) {
    if (!has(k)) return fallback;
    return finite_float(j[k], what + ": '" + k + "'");
  }
  bool flag(const char *k, bool fallback) {
    if (!has(k)) return fallback;
    if (!j[k].is_boolean()) fail(what + ": '" + k + "' must be true or false");
    return j[k].get<bool>();
  }
  Vec3 vec(const char *k, Vec3 fallback) {
    if (!has(k)) return fallback;
    const json &v = j[k];
    std::string field = what + ": '" + k + "'";
    if (v.is_number()) return Vec3(finite_float(v, field));
    if (!v.is_array() || v.size() != 3) fail(field + " must be 3 numbers");
    return {finite_float(v[0], field), finite_float(v[1], field), finite_float(v[2], field)};
  }
  uint8_t choice(const char *k, const std::vector<std::string> &options, const std::string &fallback) {
    std::string v = upper(str(k, fallback));
    for (size_t i = 0; i < options.size(); ++i)
      if (options[i] == v) return uint8_t(i);
    std::string all;
    for (auto &o : options) all += (all.empty() ? "" : ", ") + o;
    fail(what + ": '" + k + "' is '" + v + "'; expected one of " + all);
  }
  void check() const {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!used.count(it.key())) fail(what + ": unknown key '" + it.key() + "'", RDV_ERROR_UNKNOWN_PARAMETER);
  }
};

// Cycles' svm_node_vector_displacement: an offset d in tangent space (mode 0: x along the
// tangent, y along the normal, z along the bitangent; the frame in object space, the tangent
// and its sign Blender's, else dp/du), object space (1) or the world (2), as a world offset.
Vec3 vector_displacement(const ShadingPoint &sp, Vec3 d, uint8_t mode) {
  if (mode == 0) {
    static const uint32_t kTangent = attribute_id("__rdv_tangent");
    Vec3 normal = normal_to_object(sp, sp.ns);
    const float len = length(normal);
    normal = len > 0 && std::isfinite(len) ? normal / len : Vec3(0, 0, 1);
    float a[4];
    int components = 0;
    Vec3 tangent;
    float sign = 1;
    if (sp.mesh && sp.attribute(kTangent, a, components) && components == 4) {
      tangent = Vec3(a[0], a[1], a[2]);
      sign = a[3];
    } else {
      const float l = length(sp.dpdu_object);
      tangent = l > 0 ? sp.dpdu_object / l : Vec3(1, 0, 0);
    }
    Vec3 bitangent = cross(normal, tangent);
    const float lb = length(bitangent);
    bitangent = lb > 0 && std::isfinite(lb) ? bitangent * (sign / lb) : Vec3(0.0f);
    d = tangent * d.x + normal * d.y + bitangent * d.z;
  }
  return mode == 2 ? d : direction_to_world(sp, d);
}

}  // namespace

int TextureGraph::add(const TexNode &n) {
  double evaluations = 1;
  for (int k = 0; k < kTexNodeInputs; ++k) {
    if (n.in[k] < 0) continue;
    bool thrice = k == 0 && ((n.type == TexNodeType::Image && n.interp != TexInterp::Closest) ||
                             n.type == TexNodeType::Bump);  // footprint / finite differences
    evaluations += (thrice ? 3 : 1) * evaluations_[size_t(n.in[k])];
  }
  if (evaluations > kMaxTextureEvaluations) {
    char count[32];
    std::snprintf(count, sizeof count, "%.3g", evaluations);
    fail(parse_root_ + ": its texture nodes would be evaluated " + count +
             " times per shading point (an image node evaluates its vector, a bump node its height, three "
             "times, so chains of them multiply); at most " + std::to_string(int(kMaxTextureEvaluations)) +
             " (a limit: docs/scene-format.md)",
         RDV_ERROR_LIMIT);
  }
  nodes_.push_back(n);
  evaluations_.push_back(evaluations);
  return int(nodes_.size() - 1);
}

int TextureGraph::constant(Color c) {
  TexNode n;
  n.type = TexNodeType::Constant;
  n.value = c;
  return add(n);
}

int TextureGraph::num_images() const {
  std::set<int> ids;
  for (const TexNode &n : nodes_)
    if (n.type == TexNodeType::Image) {
      ids.insert(n.image);
      for (const auto &tile : n.udim) ids.insert(tile.second);
    }
  return int(ids.size());
}

int TextureGraph::parse(const json &j, const std::string &what, std::vector<std::string> &warnings) {
  if (j.is_number()) return constant(Color(finite_float(j, what)));
  if (j.is_array()) {
    if (j.size() != 3 && j.size() != 4) fail(what + ": a colour needs 3 (or 4) numbers");
    for (const json &v : j)
      if (!v.is_number()) fail(what + ": a colour needs 3 (or 4) numbers");
    return constant(Color(finite_float(j[0], what), finite_float(j[1], what), finite_float(j[2], what)));
  }
  if (j.is_object()) return parse_node(j, what, warnings);
  fail(what + ": must be a number, a colour [r,g,b] or a texture node {\"node\": ...}");
}

int TextureGraph::parse_node(const json &j, const std::string &what_in, std::vector<std::string> &warnings) {
  // Parsing and evaluation recurse once per node: the depth is bounded here, once.
  if (parse_depth_ == 0) parse_root_ = what_in;
  if (parse_depth_ >= kMaxTextureDepth)
    fail(parse_root_ + ": texture nodes nest more than " + std::to_string(kMaxTextureDepth) +
             " deep (a limit: docs/scene-format.md)",
         RDV_ERROR_LIMIT);
  struct Nesting {
    int &depth;
    explicit Nesting(int &d) : depth(d) { ++depth; }
    ~Nesting() { --depth; }
  } nesting(parse_depth_);
  if (!j.contains("node") || !j["node"].is_string()) fail(what_in + ": a texture node needs \"node\": \"<type>\"");
  std::string type = j["node"].get<std::string>();
  std::string what = what_in + " (" + type + " node)";
  NodeReader r{j, what};
  TexNode n;
  auto input = [&](const char *key, const json &fallback) {
    return r.has(key) ? parse(j[key], what + " '" + key + "'", warnings) : parse(fallback, what, warnings);
  };
  auto vector_input = [&](const char *key, Coord def) {
    if (r.has(key)) return parse(j[key], what + " '" + key + "'", warnings);
    TexNode c;
    c.type = TexNodeType::TexCoord;
    c.mode = def;
    return add(c);
  };
  auto outputs = [&](const std::vector<std::string> &names) {
    std::string o = r.str("output", names[0]);
    for (size_t i = 0; i < names.size(); ++i)
      if (o == names[i]) return uint8_t(i);
    fail(what + ": unknown output '" + o + "'");
  };

  if (type == "image") {
    n.type = TexNodeType::Image;
    std::string file = r.str("file", "");
    std::string buffer = r.str("buffer", "");
    std::string name = r.str("name", file.empty() ? buffer : file);
    if (!file.empty() && !buffer.empty()) fail(what + ": give a 'file' or a 'buffer', not both");
    std::string cs = r.str("colorspace", "");
    std::string interp = upper(r.str("interpolation", "Linear"));
    if (interp == "LINEAR") n.interp = TexInterp::Linear;
    else if (interp == "CLOSEST") n.interp = TexInterp::Closest;
    else if (interp == "CUBIC" || interp == "SMART") n.interp = TexInterp::Cubic;
    else fail(what + ": 'interpolation' must be Linear, Closest, Cubic or Smart");
    std::string ext = upper(r.str("extension", "REPEAT"));
    if (ext == "REPEAT") n.ext = TexExtension::Repeat;
    else if (ext == "EXTEND") n.ext = TexExtension::Extend;
    else if (ext == "CLIP") n.ext = TexExtension::Clip;
    else if (ext == "MIRROR") n.ext = TexExtension::Mirror;
    else fail(what + ": 'extension' must be REPEAT, EXTEND, CLIP or MIRROR");
    n.output = outputs({"color", "alpha"});
    n.in[0] = vector_input("vector", kUv);
    std::string problem;
    if (!buffer.empty()) {
      if (r.has("colorspace")) fail(what + ": a 'buffer' has its colour space (rdv_scene_add_image), not 'colorspace'");
      const ImageBuffer *b = image_buffers ? find_image_buffer(*image_buffers, buffer) : nullptr;
      if (b) {
        n.memory = b->image;
        n.image = b->image->id;
      } else {
        problem = "no image buffer '" + buffer + "' (add it with rdv_scene_add_image first)";
      }
    } else if (r.has("tiles")) {
      // UDIM tiles: "file" holds <UDIM>, replaced by each tile's number (1001 + u + 10 v).
      const json &tiles = j["tiles"];
      size_t token = file.find("<UDIM>");
      if (token == std::string::npos) fail(what + ": 'tiles' needs a 'file' with <UDIM> in its name");
      if (!tiles.is_array() || tiles.empty()) fail(what + ": 'tiles' must be a list of UDIM tile numbers");
      for (const json &t : tiles) {
        if (!t.is_number_integer() || t.get<int>() < 1001 || t.get<int>() > 2000)
          fail(what + ": 'tiles' must be UDIM tile numbers (1001 to 2000)");
        std::string path = file;
        path.replace(token, 6, std::to_string(t.get<int>()));
        std::string tile_problem;
        int id = ImageTextures::instance().load(path, cs, tile_problem);
        if (id >= 0) n.udim.emplace_back(t.get<int>(), id);
        if (!tile_problem.empty()) problem += (problem.empty() ? "" : "; ") + tile_problem;
      }
      if (!n.udim.empty()) n.image = n.udim.front().second;
      if (!problem.empty() && n.image >= 0) problem += "; those tiles render magenta (as Blender does)";
    } else if (r.has("frame")) {
      float frame = r.num("frame", 0);
      if (!(frame >= 0) || frame != std::floor(frame)) fail(what + ": 'frame' must be a whole number from 0");
      n.image = file.empty() ? -1 : ImageTextures::instance().load_frame(file, int(frame), cs, problem);
      if (file.empty()) problem = "no 'file' given";
    } else {
      n.image = file.empty() ? -1 : ImageTextures::instance().load(file, cs, problem);
      if (file.empty()) problem = "no 'file' or 'buffer' given";
    }
    if (n.image < 0)
      warnings.push_back("image '" + name + "': " + problem + "; rendering it magenta (as Blender does)");
    else if (!problem.empty())
      warnings.push_back("image '" + name + "': " + problem);
  } else if (type == "checker") {
    n.type = TexNodeType::Checker;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("color1", json::array({0.8, 0.8, 0.8}));
    n.in[2] = input("color2", json::array({0.2, 0.2, 0.2}));
    n.in[3] = input("scale", 5.0);
    n.output = outputs({"color", "fac"});
  } else if (type == "noise") {
    n.type = TexNodeType::Noise;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("scale", 5.0);
    n.in[2] = input("w", 0.0);
    n.in[3] = input("detail", 2.0);
    n.in[4] = input("roughness", 0.5);
    n.in[5] = input("distortion", 0.0);
    n.dims = uint8_t(r.choice("dimensions", kDimensions, "3D") + 1);
    n.output = outputs({"fac", "color"});
  } else if (type == "voronoi") {
    n.type = TexNodeType::Voronoi;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("w", 0.0);
    n.in[2] = input("scale", 5.0);
    n.in[3] = input("smoothness", 1.0);
    n.in[4] = input("exponent", 0.5);
    n.in[5] = input("randomness", 1.0);
    n.dims = uint8_t(r.choice("dimensions", kDimensions, "3D") + 1);
    n.mode = r.choice("feature", {"F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"}, "F1");
    n.mode2 = r.choice("distance", {"EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI"}, "EUCLIDEAN");
    n.output = outputs({"distance", "color", "position", "w", "radius"});
  } else if (type == "musgrave") {
    n.type = TexNodeType::Musgrave;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("w", 0.0);
    n.in[2] = input("scale", 5.0);
    n.in[3] = input("detail", 2.0);
    n.in[4] = input("dimension", 2.0);
    n.in[5] = input("lacunarity", 2.0);
    n.in[6] = input("offset", 0.0);
    n.in[7] = input("gain", 1.0);
    n.dims = uint8_t(r.choice("dimensions", kDimensions, "3D") + 1);
    n.mode = r.choice("musgrave_type", {"MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "FBM",
                                        "HETERO_TERRAIN"}, "FBM");
    n.output = outputs({"fac"});
  } else if (type == "wave") {
    n.type = TexNodeType::Wave;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("scale", 5.0);
    n.in[2] = input("distortion", 0.0);
    n.in[3] = input("detail", 2.0);
    n.in[4] = input("detail_scale", 1.0);
    n.in[5] = input("detail_roughness", 0.5);
    n.in[6] = input("phase", 0.0);
    n.mode = r.choice("wave_type", {"BANDS", "RINGS"}, "BANDS");
    n.mode2 = n.mode == 0 ? r.choice("direction", {"X", "Y", "Z", "DIAGONAL"}, "X")
                          : r.choice("direction", {"X", "Y", "Z", "SPHERICAL"}, "X");
    n.mode3 = r.choice("profile", {"SIN", "SAW", "TRI"}, "SIN");
    n.output = outputs({"fac", "color"});
  } else if (type == "magic") {
    n.type = TexNodeType::Magic;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("scale", 5.0);
    n.in[2] = input("distortion", 1.0);
    float depth = r.num("depth", 2.0f);
    if (!(depth >= 0 && depth <= 10) || depth != std::floor(depth)) fail(what + ": 'depth' must be a whole number from 0 to 10");
    n.depth = int(depth);
    n.output = outputs({"color", "fac"});
  } else if (type == "brick") {
    n.type = TexNodeType::Brick;
    n.in[0] = vector_input("vector", kGenerated);
    n.in[1] = input("color1", json::array({0.8, 0.8, 0.8}));
    n.in[2] = input("color2", json::array({0.2, 0.2, 0.2}));
    n.in[3] = input("mortar", json::array({0.0, 0.0, 0.0}));
    n.in[4] = input("scale", 5.0);
    n.in[5] = input("mortar_size", 0.02);
    n.in[6] = input("mortar_smooth", 0.1);
    n.in[7] = input("bias", 0.0);
    n.in[8] = input("brick_width", 0.5);
    n.in[9] = input("row_height", 0.25);
    n.offset = r.num("offset", 0.5f);
    n.squash = r.num("squash", 1.0f);
    auto frequency = [&](const char *key) {
      float f = r.num(key, 2.0f);
      if (!(f >= 1 && f <= 99) || f != std::floor(f)) fail(what + ": '" + key + "' must be a whole number from 1 to 99");
      return int(f);
    };
    n.offset_frequency = frequency("offset_frequency");
    n.squash_frequency = frequency("squash_frequency");
    n.output = outputs({"color", "fac"});
  } else if (type == "white_noise") {
    n.type = TexNodeType::WhiteNoise;
    n.in[0] = input("vector", json::array({0.0, 0.0, 0.0}));  // unlinked in Blender: the origin, not Generated
    n.in[1] = input("w", 0.0);
    n.dims = uint8_t(r.choice("dimensions", kDimensions, "3D") + 1);
    n.output = outputs({"value", "color"});
  } else if (type == "gradient") {
    n.type = TexNodeType::Gradient;
    n.in[0] = vector_input("vector", kGenerated);
    n.mode = r.choice("gradient_type", kGradients, "LINEAR");
    n.output = outputs({"fac", "color"});
  } else if (type == "mix") {
    n.type = TexNodeType::MixRgb;
    n.mode = r.choice("blend_type", kBlendTypes, "MIX");
    n.in[0] = input("fac", 0.5);
    n.in[1] = input("color1", json::array({0.5, 0.5, 0.5}));
    n.in[2] = input("color2", json::array({0.5, 0.5, 0.5}));
    n.clamp = r.flag("clamp", false);
  } else if (type == "math") {
    n.type = TexNodeType::Math;
    n.mode = r.choice("operation", kMathOps, "ADD");
    n.in[0] = input("value1", 0.5);
    n.in[1] = input("value2", 0.5);
    n.in[2] = input("value3", 0.0);
    n.clamp = r.flag("clamp", false);
  } else if (type == "vector_math") {
    n.type = TexNodeType::VectorMath;
    n.mode = r.choice("operation", kVectorMathOps, "ADD");
    n.in[0] = input("vector1", json::array({0, 0, 0}));
    n.in[1] = input("vector2", json::array({0, 0, 0}));
    n.in[2] = input("vector3", json::array({0, 0, 0}));
    n.in[3] = input("scale", 1.0);
    n.output = outputs({"vector", "value"});
  } else if (type == "color_space") {
    // Separate / Combine Color in HSV or HSL: the colour converted as Cycles converts it.
    n.type = TexNodeType::ColorSpace;
    n.mode = r.choice("convert", {"RGB_TO_HSV", "HSV_TO_RGB", "RGB_TO_HSL", "HSL_TO_RGB"}, "RGB_TO_HSV");
    n.in[0] = input("color", json::array({0.8, 0.8, 0.8}));
  } else if (type == "blackbody") {
    // Blender's Blackbody node: Planck's colour at the temperature, luminance 1 (media/blackbody.h).
    n.type = TexNodeType::Blackbody;
    n.in[0] = input("temperature", 1500.0);
  } else if (type == "wavelength") {
    n.type = TexNodeType::Wavelength;
    n.in[0] = input("wavelength", 500.0);
  } else if (type == "ambient_occlusion") {
    // Blender's Ambient Occlusion node: `color` x AO ("color") or AO ("ao"); samples 1..128,
    // "inside" (toward the inside: the normal flipped), "only_local" (the own object only).
    n.type = TexNodeType::AmbientOcclusion;
    n.in[0] = input("color", json::array({1.0, 1.0, 1.0}));
    n.in[1] = input("distance", 1.0);
    if (r.has("normal")) n.in[2] = input("normal", json::array({0.0, 0.0, 1.0}));
    const float samples = r.num("samples", 16.0f);
    if (!(samples >= 1 && samples <= 128)) fail(what + ": 'samples' must be 1 to 128");
    n.depth = int(samples);
    n.mode = uint8_t((r.flag("inside", false) ? 1 : 0) | (r.flag("only_local", false) ? 2 : 0));
    n.output = outputs({"color", "ao"});
  } else if (type == "bevel") {
    // Blender's Bevel node: the normal averaged over the object's surfaces within `radius`
    // from `samples` (0..128) local rays; `normal` (a normal node) offset by the bevel's turn.
    n.type = TexNodeType::Bevel;
    n.in[0] = input("radius", 0.05);
    if (r.has("normal")) n.in[1] = parse(j["normal"], what + " 'normal'", warnings);
    const float samples = r.num("samples", 4.0f);  // Blender's default
    if (!(samples >= 0 && samples <= 128)) fail(what + ": 'samples' must be 0 to 128");
    n.depth = int(samples);
  } else if (type == "displacement") {
    // Blender's Displacement node (Cycles' svm_node_displacement): the world-space offset
    // (height - midlevel) x scale along `normal` (default: the shading normal); in OBJECT space
    // the normal is taken to the object and the offset back, so the object's scale applies.
    n.type = TexNodeType::Displacement;
    n.mode = r.choice("space", {"OBJECT", "WORLD"}, "OBJECT");
    n.in[0] = input("height", 0.0);
    n.in[1] = input("midlevel", 0.5);
    n.in[2] = input("scale", 1.0);
    if (r.has("normal")) n.in[3] = parse(j["normal"], what + " 'normal'", warnings);
  } else if (type == "vector_displacement") {
    // Blender's Vector Displacement node (Cycles' svm_node_vector_displacement): (vector -
    // midlevel) x scale in TANGENT space (x along the tangent, y the normal, z the bitangent),
    // OBJECT or WORLD space, as a world-space offset.
    n.type = TexNodeType::VectorDisplacement;
    n.mode = r.choice("space", {"TANGENT", "OBJECT", "WORLD"}, "TANGENT");
    n.in[0] = input("vector", json::array({0.0, 0.0, 0.0}));
    n.in[1] = input("midlevel", 0.0);
    n.in[2] = input("scale", 1.0);
  } else if (type == "camera_data") {
    // Blender's Camera Data node (Cycles' svm_node_camera): the point in the camera's space at
    // its frame, z along the view: its direction, its depth z or its distance.
    n.type = TexNodeType::CameraData;
    n.mode = r.choice("output", {"VIEW_VECTOR", "VIEW_Z_DEPTH", "VIEW_DISTANCE"}, "VIEW_VECTOR");
  } else if (type == "ies") {
    // Blender's IES Texture (Cycles' svm_node_ies): `strength` x the profile's intensity along
    // `vector` (default: the normal in object space; on a lamp, the direction light leaves it
    // in the lamp's space). The profile is the .ies file's text ("profile") or its path ("file").
    n.type = TexNodeType::Ies;
    n.in[0] = input("strength", 1.0);
    n.in[1] = vector_input("vector", kObjectNormal);
    const std::string text = r.str("profile", ""), file = r.str("file", "");
    auto profile = std::make_shared<IesProfile>();
    std::string error;
    if (file.empty() ? profile->parse(text, error) : profile->load(file, error)) n.ies = std::move(profile);
    else warnings.push_back(what + ": " + (file.empty() ? "the IES profile" : "IES file '" + file + "'") + " cannot be read (" +
                            error + "); a constant 100 used, as Cycles");
  } else if (type == "light_falloff") {
    // Blender's Light Falloff (Cycles' svm_node_light_falloff): `strength` times the ray's
    // length to the power 0 (QUADRATIC: the physical falloff lamps already have), 1 (LINEAR) or
    // 2 (CONSTANT), times d^2 / (smooth + d^2) when `smooth` > 0.
    n.type = TexNodeType::LightFalloff;
    n.mode = r.choice("output", {"QUADRATIC", "LINEAR", "CONSTANT"}, "QUADRATIC");
    n.in[0] = input("strength", 100.0);
    n.in[1] = input("smooth", 0.0);
  } else if (type == "wireframe") {
    n.type = TexNodeType::Wireframe;
    n.in[0] = input("size", 0.01);
    n.mode = r.flag("pixel_size", false);
  } else if (type == "object_info") {
    n.type = TexNodeType::ObjectInfo;
    n.output = outputs({"location", "color", "alpha", "object_index", "material_index", "random"});
  } else if (type == "map_range") {
    n.type = TexNodeType::MapRange;
    n.mode = r.choice("interpolation_type", {"LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP"}, "LINEAR");
    n.mode2 = r.choice("data_type", {"FLOAT", "FLOAT_VECTOR"}, "FLOAT");
    const bool vec = n.mode2 == 1;
    n.in[0] = input("value", vec ? json::array({0, 0, 0}) : json(1.0));
    n.in[1] = input("from_min", vec ? json::array({0, 0, 0}) : json(0.0));
    n.in[2] = input("from_max", vec ? json::array({1, 1, 1}) : json(1.0));
    n.in[3] = input("to_min", vec ? json::array({0, 0, 0}) : json(0.0));
    n.in[4] = input("to_max", vec ? json::array({1, 1, 1}) : json(1.0));
    n.in[5] = input("steps", vec ? json::array({4, 4, 4}) : json(4.0));
    n.clamp = r.flag("clamp", true);
  } else if (type == "color_ramp") {
    n.type = TexNodeType::ColorRamp;
    n.in[0] = input("fac", 0.5);
    n.mode = r.choice("interpolation", {"LINEAR", "CONSTANT", "EASE", "B_SPLINE", "CARDINAL"}, "LINEAR");
    if (n.mode >= 3) {
      warnings.push_back(what + ": B-spline / cardinal interpolation is approximated as linear");
      n.mode = 0;
    }
    if (r.has("table")) {
      // Blender's ramp evaluated as Cycles bakes it: interpolation LINEAR or CONSTANT only.
      n.table = parse_table(j["table"], what + ": 'table'", 4);
      if (n.mode == 2) fail(what + ": a 'table' is looked up LINEAR or CONSTANT");
    }
    if (r.has("elements")) {
      if (!j["elements"].is_array()) fail(what + ": 'elements' must be a list of {position, color}");
      for (const json &e : j["elements"]) {
        if (!e.is_object() || !e.contains("position") || !e.contains("color"))
          fail(what + ": each of 'elements' needs 'position' and 'color'");
        const json &c = e["color"];
        std::string color = what + ": an element's 'color'";
        if (!c.is_array() || c.size() < 3 || c.size() > 4) fail(color + " needs 3 or 4 numbers");
        n.ramp.push_back({finite_float(e["position"], what + ": an element's 'position'"),
                          Color(finite_float(c[0], color), finite_float(c[1], color), finite_float(c[2], color)),
                          c.size() > 3 ? finite_float(c[3], color) : 1.0f});
      }
    }
    if (n.ramp.empty()) n.ramp = {{0, Color(0.0f), 1}, {1, Color(1.0f), 1}};
    std::stable_sort(n.ramp.begin(), n.ramp.end(), [](const RampStop &a, const RampStop &b) { return a.position < b.position; });
    n.output = outputs({"color", "alpha"});
  } else if (type == "rgb_curves" || type == "float_curve") {
    // RGB / Vector Curves and Float Curve: Blender's curves baked into a table over
    // [min_x, max_x] (docs/scene-format.md), looked up per channel as Cycles does.
    n.type = TexNodeType::Curves;
    n.mode = type == "float_curve" ? 1 : 0;
    n.in[0] = input("fac", 1.0);
    n.in[1] = n.mode ? input("value", 0.0) : input("color", json::array({0.5, 0.5, 0.5}));
    if (!r.has("table")) fail(what + ": needs its 'table'");
    n.table = parse_table(j["table"], what + ": 'table'", n.mode ? 1 : 3);
    n.min_x = r.num("min_x", 0.0f);
    n.max_x = r.num("max_x", 1.0f);
    if (!(n.max_x > n.min_x)) fail(what + ": 'max_x' must be above 'min_x'");
    n.clamp = !r.flag("extrapolate", true);  // clamp doubles as "no extrapolation" here
  } else if (type == "invert") {
    n.type = TexNodeType::Invert;
    n.in[0] = input("fac", 1.0);
    n.in[1] = input("color", json::array({0, 0, 0}));
  } else if (type == "hue_saturation") {
    n.type = TexNodeType::HueSat;
    n.in[0] = input("hue", 0.5);
    n.in[1] = input("saturation", 1.0);
    n.in[2] = input("value", 1.0);
    n.in[3] = input("fac", 1.0);
    n.in[4] = input("color", json::array({0.8, 0.8, 0.8}));
  } else if (type == "attribute" || type == "vertex_color" || type == "uv") {
    n.type = TexNodeType::Attribute;
    std::string name = r.str(type == "attribute" ? "name" : "layer", "");
    // Attribute's type: GEOMETRY (the mesh's, interpolated), OBJECT / INSTANCER (the
    // instance's own value, ShadingPoint::object_attribute).
    if (type == "attribute") n.mode = r.choice("attribute_type", {"GEOMETRY", "OBJECT", "INSTANCER"}, "GEOMETRY");
    if (n.mode == 2) name = kInstancerPrefix + name;
    n.default_uv = name.empty() && type != "vertex_color";
    if (name.empty() && type != "uv") fail(what + ": needs the attribute's name ('" + (type == "attribute" ? "name" : "layer") + "')");
    n.attribute = name.empty() ? 0 : attribute_id(name);
    n.output = type == "uv" ? 0 : outputs({"color", "fac", "alpha", "vector"});
    if (n.output == 3) n.output = 0;
  } else if (type == "texture_coordinate") {
    n.type = TexNodeType::TexCoord;
    std::string o = r.str("output", "generated");
    static const std::map<std::string, Coord> outs = {{"uv", kUv}, {"generated", kGenerated}, {"object", kObject},
                                                      {"position", kPosition}, {"normal", kNormal},
                                                      {"object_normal", kObjectNormal}, {"true_normal", kTrueNormal},
                                                      {"parametric", kParametric}, {"tangent", kTangent}};
    auto it = outs.find(o);
    if (it == outs.end())
      fail(what + ": 'output' must be uv, generated, object, position, normal, object_normal, true_normal, parametric "
                  "or tangent");
    n.mode = it->second;
  } else if (type == "mapping") {
    n.type = TexNodeType::Mapping;
    n.mode = r.choice("type", {"POINT", "TEXTURE", "VECTOR", "NORMAL"}, "POINT");
    n.in[0] = vector_input("vector", kGenerated);
    n.loc = r.vec("location", Vec3(0.0f));
    n.rot = r.vec("rotation", Vec3(0.0f));
    n.scale = r.vec("scale", Vec3(1.0f));
  } else if (type == "normal_map") {
    n.type = TexNodeType::NormalMap;
    n.mode = r.choice("space", {"TANGENT", "OBJECT", "WORLD"}, "TANGENT");
    n.in[0] = input("color", json::array({0.5, 0.5, 1.0}));
    n.in[1] = input("strength", 1.0);
    std::string uv_map = r.str("uv_map", "");
    if (!uv_map.empty()) warnings.push_back(what + ": tangents come from the default UV map, not '" + uv_map + "'");
  } else if (type == "bump") {
    n.type = TexNodeType::Bump;
    n.in[0] = input("height", 0.0);
    n.in[1] = input("strength", 1.0);
    n.in[2] = input("distance", 1.0);
    n.clamp = r.flag("invert", false);  // clamp doubles as "invert" here
    // OBJECT: the differences taken in object space (Cycles' bump of a Displacement and Bump)
    n.mode = r.choice("space", {"WORLD", "OBJECT"}, "WORLD");
    if (r.has("normal")) n.in[3] = parse(j["normal"], what + " 'normal'", warnings);
  } else if (type == "separate_rgb" || type == "separate_color") {
    n.type = TexNodeType::SeparateRgb;
    n.in[0] = input("color", json::array({0.8, 0.8, 0.8}));
    n.output = outputs({"r", "g", "b"});
  } else if (type == "combine_rgb" || type == "combine_color") {
    n.type = TexNodeType::CombineRgb;
    n.in[0] = input("r", 0.0);
    n.in[1] = input("g", 0.0);
    n.in[2] = input("b", 0.0);
  } else if (type == "rgb_to_bw") {
    n.type = TexNodeType::RgbToBw;
    n.in[0] = input("color", json::array({0.5, 0.5, 0.5}));
  } else if (type == "bright_contrast") {
    n.type = TexNodeType::BrightContrast;
    n.in[0] = input("color", json::array({1, 1, 1}));
    n.in[1] = input("bright", 0.0);
    n.in[2] = input("contrast", 0.0);
  } else if (type == "gamma") {
    n.type = TexNodeType::Gamma;
    n.in[0] = input("color", json::array({1, 1, 1}));
    n.in[1] = input("gamma", 1.0);
  } else if (type == "fresnel" || type == "layer_weight" || type == "backfacing") {
    fail(what_in + ": a '" + type + "' node depends on the viewing direction: it is supported as a mix's 'fac' "
                   "only (docs/scene-format.md)");
  } else {
    fail(what_in + ": unknown texture node '" + type +
         "' (image, checker, noise, voronoi, musgrave, wave, magic, brick, white_noise, gradient, mix, math, color_ramp, rgb_curves, float_curve, vector_math, map_range, object_info, color_space, blackbody, wavelength, wireframe, ambient_occlusion, bevel, displacement, vector_displacement, camera_data, ies, invert, hue_saturation, attribute, vertex_color, "
         "uv, texture_coordinate, mapping, normal_map, bump, separate_rgb, combine_rgb, rgb_to_bw, bright_contrast, gamma)");
  }
  r.used.insert("output");
  r.check();
  return add(n);
}

template <typename Leaf>
bool TextureGraph::any_in_subgraph(int node, const Leaf &leaf) const {
  // Inputs refer to nodes parsed before them: the recursion ends.
  const TexNode &n = nodes_[size_t(node)];
  if (leaf(n)) return true;
  // An IES Texture without a profile is Cycles' 100 in every direction: its vector unused.
  if (n.type == TexNodeType::Ies && !n.ies) return any_in_subgraph(n.in[0], leaf);
  for (int i : n.in)
    if (i >= 0 && any_in_subgraph(i, leaf)) return true;
  return false;
}

bool TextureGraph::depends_on_normal(int node) const {
  return any_in_subgraph(node, [](const TexNode &n) {
    return (n.type == TexNodeType::TexCoord && (n.mode == kNormal || n.mode == kObjectNormal || n.mode == kTrueNormal)) ||
           n.type == TexNodeType::NormalMap || n.type == TexNodeType::Bump || n.type == TexNodeType::Bevel;
  });
}

bool TextureGraph::depends_on_ray_length(int node) const {
  return any_in_subgraph(node, [](const TexNode &n) { return n.type == TexNodeType::LightFalloff; });
}

bool TextureGraph::depends_on_point(int node) const {
  // Every texture reads its coordinates through an input (the parser fills the defaults in).
  return any_in_subgraph(node, [](const TexNode &n) {
    switch (n.type) {
      case TexNodeType::TexCoord: return n.mode != kNormal && n.mode != kObjectNormal && n.mode != kTrueNormal;
      case TexNodeType::Attribute:
      case TexNodeType::CameraData:
      case TexNodeType::Wireframe:
      case TexNodeType::AmbientOcclusion: return true;
      default: return false;
    }
  });
}

// ---- evaluation ------------------------------------------------------------------------
namespace {

// Cycles 3.4's svm_node_light_falloff. A ray of infinite length (a sun, the world) leaves
// Strength as it is: Cycles 3.4 multiplies by FLT_MAX there, later Cycles skip the node.
float light_falloff(int output, float strength, float smooth, float d) {
  if (!std::isfinite(d)) return strength;
  if (output == 1) strength *= d;
  if (output == 2) strength *= d * d;
  if (smooth > 0) strength *= d * d / (smooth + d * d);
  return std::isfinite(strength) ? strength : 0.0f;
}

float math_op(int op, float a, float b, float c) {
  switch (op) {
    case 0: return a + b;
    case 1: return a - b;
    case 2: return a * b;
    case 3: return b != 0 ? a / b : 0.0f;
    case 4: return a * b + c;
    case 5: {  // Cycles' safe power
      if (a < 0 && b != std::floor(b)) return 0.0f;
      return std::pow(a, b);
    }
    case 6: return (a > 0 && b > 0 && b != 1) ? std::log(a) / std::log(b) : 0.0f;
    case 7: return a > 0 ? std::sqrt(a) : 0.0f;
    case 8: return a > 0 ? 1.0f / std::sqrt(a) : 0.0f;
    case 9: return std::fabs(a);
    case 10: return std::exp(a);
    case 11: return std::min(a, b);
    case 12: return std::max(a, b);
    case 13: return a < b ? 1.0f : 0.0f;
    case 14: return a > b ? 1.0f : 0.0f;
    case 15: return a > 0 ? 1.0f : (a < 0 ? -1.0f : 0.0f);
    case 16: return std::fabs(a - b) <= std::max(c, 1e-5f) ? 1.0f : 0.0f;
    case 17: return std::floor(a + 0.5f);
    case 18: return std::floor(a);
    case 19: return std::ceil(a);
    case 20: return std::trunc(a);
    case 21: return a - std::floor(a);
    case 22: return b != 0 ? std::fmod(a, b) : 0.0f;
    case 23: {  // wrap(a, max=b, min=c)
      float range = b - c;
      return range != 0 ? a - range * std::floor((a - c) / range) : c;
    }
    case 24: return b != 0 ? std::floor(a / b) * b : 0.0f;
    case 25: {  // pingpong
      if (b == 0) return 0.0f;
      float t = (a - b) / (b * 2);
      return std::fabs((t - std::floor(t)) * b * 2 - b);
    }
    case 26: return std::sin(a);
    case 27: return std::cos(a);
    case 28: return std::tan(a);
    case 29: return std::asin(clampf(a, -1, 1));
    case 30: return std::acos(clampf(a, -1, 1));
    case 31: return std::atan(a);
    case 32: return std::atan2(a, b);
    case 33: return std::sinh(a);
    case 34: return std::cosh(a);
    case 35: return std::tanh(a);
    case 36: return a * (kPi / 180.0f);
    case 37: return a * (180.0f / kPi);
    case 38: case 39: {  // smooth min / max with distance c
      float s = op == 39 ? -1.0f : 1.0f;
      a *= s; b *= s;
      float r = c != 0 ? std::min(a, b) - sqr(std::max(c - std::fabs(a - b), 0.0f)) / (4 * c) : std::min(a, b);
      return r * s;
    }
  }
  return 0.0f;
}

Color blend(int type, float t, Color a, Color b) {
  float tm = 1 - t;
  switch (type) {
    case 0: return lerp(a, b, t);
    case 1: return a + b * t;
    case 2: return a * (Color(tm) + b * t);
    case 3: return a - b * t;
    case 4: return Color(1.0f) - (Color(tm) + (Color(1.0f) - b) * t) * (Color(1.0f) - a);
    case 5: {
      Color r = a;
      for (int i = 0; i < 3; ++i)
        if (b[i] != 0) r[i] = tm * a[i] + t * a[i] / b[i];
      return r;
    }
    case 6: return {tm * a.x + t * std::fabs(a.x - b.x), tm * a.y + t * std::fabs(a.y - b.y), tm * a.z + t * std::fabs(a.z - b.z)};
    case 7: return lerp(a, vmin(a, b), t);
    case 8: return lerp(a, vmax(a, b), t);
    case 9: {
      Color r;
      for (int i = 0; i < 3; ++i)
        r[i] = a[i] < 0.5f ? a[i] * (tm + 2 * t * b[i]) : 1 - (tm + 2 * t * (1 - b[i])) * (1 - a[i]);
      return r;
    }
    case 10: {  // dodge
      Color r = a;
      for (int i = 0; i < 3; ++i)
        if (a[i] != 0) {
          float tmp = 1 - t * b[i];
          r[i] = tmp <= 0 ? 1.0f : std::min(1.0f, a[i] / tmp);
        }
      return r;
    }
    case 11: {  // burn
      Color r;
      for (int i = 0; i < 3; ++i) {
        float tmp = tm + t * b[i];
        r[i] = tmp <= 0 ? 0.0f : clampf(1 - (1 - a[i]) / tmp, 0, 1);
      }
      return r;
    }
    case 12: case 13: case 14: case 15: {  // hue, saturation, value, color
      Color ha = rgb_to_hsv(a), hb = rgb_to_hsv(b);
      if (type == 12) { if (hb.y == 0) return a; ha.x = hb.x; return lerp(a, hsv_to_rgb(ha), t); }
      if (type == 13) { if (ha.y == 0) return a; ha.y = tm * ha.y + t * hb.y; return hsv_to_rgb(ha); }
      if (type == 14) { ha.z = tm * ha.z + t * hb.z; return hsv_to_rgb(ha); }
      if (hb.y == 0) return a;
      ha.x = hb.x; ha.y = hb.y;
      return lerp(a, hsv_to_rgb(ha), t);
    }
    case 16: {  // soft light
      Color scr = Color(1.0f) - (Color(1.0f) - b) * (Color(1.0f) - a);
      return a * tm + ((Color(1.0f) - a) * b * a + a * scr) * t;
    }
    case 17: return a + (b * 2.0f - Color(1.0f)) * t;  // linear light
  }
  return lerp(a, b, t);
}

float gradient(int type, Vec3 p) {
  switch (type) {
    case 0: return p.x;
    case 1: { float r = std::max(p.x, 0.0f); return r * r; }
    case 2: { float r = clampf(p.x, 0, 1), t = r * r; return 3 * t - 2 * t * r; }
    case 3: return (p.x + p.y) * 0.5f;
    case 4: return std::max(0.999999f - length(p), 0.0f);
    case 5: { float r = std::max(0.999999f - length(p), 0.0f); return r * r; }
    case 6: return std::atan2(p.y, p.x) / (2 * kPi) + 0.5f;
  }
  return 0;
}

}  // namespace

Color TextureGraph::eval_node(const TexNode &n, int idx, const ShadingPoint &sp) const {
  auto in = [&](int k) { return eval(n.in[k], sp); };
  auto inf = [&](int k) { return eval_float(n.in[k], sp); };
  switch (n.type) {
    case TexNodeType::Constant: return n.value;
    case TexNodeType::Image: {
      if (n.image < 0) return n.output == 1 ? Color(1.0f) : Color(1, 0, 1);
      Vec3 uv = in(0);
      // The footprint in texture space (Closest stays unfiltered, as in Blender): the
      // default UV map's is the shading point's own; mapped or other coordinates
      // by finite differences across it.
      Vec2 dx(0.0f, 0.0f), dy(0.0f, 0.0f);
      if (n.interp != TexInterp::Closest && sp.has_footprint()) {
        const TexNode &v = nodes_[size_t(n.in[0])];
        bool default_uv = (v.type == TexNodeType::TexCoord && v.mode == kUv) ||
                          (v.type == TexNodeType::Attribute && v.default_uv);
        if (default_uv) {
          dx = sp.dx;
          dy = sp.dy;
        } else {
          Vec3 ux = eval(n.in[0], sp.shifted(sp.dx)) - uv, uy = eval(n.in[0], sp.shifted(sp.dy)) - uv;
          dx = {ux.x, ux.y};
          dy = {uy.x, uy.y};
        }
      }
      int image = n.image;
      if (!n.udim.empty()) {
        // The tile under (u, v), then (u, v) within it; outside every tile: magenta,
        // as Cycles (which truncates, so (-1, 0) counts as the first column).
        int tx = -1, ty = -1;  // outside every tile; huge or NaN (u, v) are never converted
        if (uv.x > -1 && uv.x < 10 && uv.y > -1 && uv.y < 1000) tx = int(uv.x), ty = int(uv.y);
        image = -1;
        if (tx >= 0 && ty >= 0 && tx < 10)
          for (const auto &[tile, id] : n.udim)
            if (tile == 1001 + 10 * ty + tx) image = id;
        if (image < 0) return n.output == 1 ? Color(1.0f) : Color(1, 0, 1);
        uv.x -= float(tx);
        uv.y -= float(ty);
      }
      float a;
      Color c = ImageTextures::instance().lookup(image, uv.x, uv.y, n.interp, n.ext, &a, dx, dy);
      return n.output == 1 ? Color(a) : c;
    }
    case TexNodeType::Checker: {
      Vec3 p = in(0) * inf(3);
      // The cell's parity in float: a coordinate beyond int's range (a huge Scale) has no
      // int to convert to (every float beyond 2^24 is an even whole number); NaN gives 0.
      auto cell = [](float x) { return std::fmod(std::fabs(std::floor((x + 0.000001f) * 0.999999f)), 2.0f) >= 1.0f; };
      bool first = ((cell(p.x) == cell(p.y)) == bool(cell(p.z)));
      if (n.output == 1) return Color(first ? 1.0f : 0.0f);
      return first ? in(1) : in(2);
    }
    case TexNodeType::Noise: {
      const float scale = inf(1);
      return noise_texture(in(0) * scale, inf(2) * scale, n.dims, inf(3), inf(4), inf(5), n.output == 1);
    }
    case TexNodeType::Voronoi: {
      VoronoiParams v{VoronoiFeature(n.mode), VoronoiMetric(n.mode2), inf(2), inf(3), inf(4), inf(5)};
      const VoronoiResult r = voronoi_texture(in(0), inf(1), n.dims, v);
      switch (n.output) {
        case 0: return Color(r.distance);
        case 1: return r.color;
        case 2: return r.position;
        case 3: return Color(r.w);
        default: return Color(r.radius);
      }
    }
    case TexNodeType::Musgrave: {
      const float scale = inf(2);
      MusgraveParams m{MusgraveType(n.mode), inf(3), inf(4), inf(5), inf(6), inf(7)};
      return Color(musgrave_texture(noise_point(in(0) * scale, inf(1) * scale, n.dims), n.dims, m));
    }
    case TexNodeType::Wave: {
      WaveParams w{WaveType(n.mode), n.mode2, WaveProfile(n.mode3), inf(2), inf(3), inf(4), inf(5), inf(6)};
      return Color(wave_texture(in(0) * inf(1), w));
    }
    case TexNodeType::Magic: {
      const Color c = magic_texture(in(0), inf(1), n.depth, inf(2));
      return n.output == 1 ? Color(average(c)) : c;
    }
    case TexNodeType::Brick: {
      BrickParams b{inf(5), inf(6), inf(7), inf(8), inf(9), n.offset, n.squash, n.offset_frequency, n.squash_frequency};
      const BrickSample s = brick_texture(in(0) * inf(4), b);
      if (n.output == 1) return Color(s.mortar);
      const Color brick = s.mortar != 1.0f ? lerp(in(1), in(2), s.tint) : in(1);
      return brick * (1.0f - s.mortar) + in(3) * s.mortar;
    }
    case TexNodeType::WhiteNoise: return white_noise_texture(in(0), inf(1), n.dims, n.output == 1);
    case TexNodeType::Gradient: return Color(clampf(gradient(n.mode, in(0)), 0, 1));
    case TexNodeType::MixRgb: {
      Color c = blend(n.mode, clampf(inf(0), 0, 1), in(1), in(2));
      return n.clamp ? clamp01(c) : c;
    }
    case TexNodeType::Math: {
      float v = math_op(n.mode, inf(0), inf(1), inf(2));
      if (!std::isfinite(v)) v = 0;
      return Color(n.clamp ? clampf(v, 0, 1) : v);
    }
    case TexNodeType::ColorRamp: {
      float f = inf(0);
      if (!n.table.empty()) {
        const RampStop out = ramp_lookup(n.table, f, n.mode != 1, false);
        return n.output == 1 ? Color(out.alpha) : out.color;
      }
      const auto &s = n.ramp;
      RampStop out = s.front();
      if (f >= s.back().position) out = s.back();
      else if (f > s.front().position) {
        size_t i = 1;
        while (i < s.size() && s[i].position < f) ++i;
        const RampStop &a = s[i - 1], &b = s[i];
        if (n.mode == 1) out = a;  // constant
        else {
          float t = b.position > a.position ? (f - a.position) / (b.position - a.position) : 0.0f;
          if (n.mode == 2) t = t * t * (3 - 2 * t);  // ease
          out = {f, lerp(a.color, b.color, t), a.alpha * (1 - t) + b.alpha * t};
        }
      }
      return n.output == 1 ? Color(out.alpha) : out.color;
    }
    case TexNodeType::Curves: {
      const float fac = inf(0), range = n.max_x - n.min_x;
      const bool extrapolate = !n.clamp;
      if (n.mode == 1) {
        const float v = inf(1);
        return Color((1.0f - fac) * v + fac * ramp_lookup(n.table, (v - n.min_x) / range, true, extrapolate).color.x);
      }
      const Color c = in(1);
      Color mapped;
      for (int k = 0; k < 3; ++k) mapped[k] = ramp_lookup(n.table, (c[k] - n.min_x) / range, true, extrapolate).color[k];
      const Color out = c * (1.0f - fac) + mapped * fac;
      return is_finite(out) ? out : Color(0.0f);
    }
    case TexNodeType::VectorMath: {
      bool value;
      const Vec3 v = vector_math(n.mode, in(0), in(1), in(2), inf(3), value);
      if (!is_finite(v)) return Color(0.0f);
      return n.output == 1 ? Color(value ? v.x : 0.0f) : value ? Vec3(v.x) : v;
    }
    case TexNodeType::MapRange: {
      const MapRangeType type = MapRangeType(n.mode);
      if (n.mode2 == 1) {
        const Vec3 v = map_range(in(0), in(1), in(2), in(3), in(4), in(5), type, n.clamp);
        return is_finite(v) ? v : Vec3(0.0f);
      }
      const float v = map_range(inf(0), inf(1), inf(2), inf(3), inf(4), inf(5), type, n.clamp);
      return Color(std::isfinite(v) ? v : 0.0f);
    }
    case TexNodeType::ColorSpace: {
      const Color c = in(0);
      const Color out = n.mode == 0 ? rgb_to_hsv(c) : n.mode == 1 ? hsv_to_rgb(c) : n.mode == 2 ? rgb_to_hsl(c)
                                                                                                  : hsl_to_rgb(c);
      return is_finite(out) ? out : Color(0.0f);
    }
    case TexNodeType::Blackbody: return blackbody_color(inf(0));
    case TexNodeType::Wavelength: return wavelength_color(inf(0));
    case TexNodeType::Wireframe: return Color(wireframe(sp, inf(0), n.mode != 0));
    case TexNodeType::AmbientOcclusion: {
      Vec3 normal = n.in[2] >= 0 ? Vec3(in(2)) : sp.backfacing ? -sp.ns : sp.ns;
      if (n.mode & 1) normal = -normal;
      const float ao = ambient_occlusion(sp, normal, inf(1), n.depth, (n.mode & 2) != 0);
      return n.output == 1 ? Color(ao) : in(0) * ao;
    }
    case TexNodeType::ObjectInfo:
      switch (n.output) {
        case 0: return sp.has_object_to_world ? Vec3(sp.object_to_world[3], sp.object_to_world[7], sp.object_to_world[11])
                                              : Vec3(0.0f);
        case 1: return sp.object_color;
        case 2: return Color(sp.object_alpha);
        case 3: return Color(sp.object_index);
        case 4: return Color(sp.material_index);
        default: return Color(sp.object_random);
      }
    case TexNodeType::Invert: {
      Color c = in(1);
      return lerp(c, Color(1.0f) - c, inf(0));
    }
    case TexNodeType::HueSat: {
      Color c = in(4);
      Color hsv = rgb_to_hsv(c);
      hsv.x += inf(0) + 0.5f;
      hsv.x -= std::floor(hsv.x);
      hsv.y = clampf(hsv.y * inf(1), 0, 1);
      hsv.z *= inf(2);
      Color r = vmax(hsv_to_rgb(hsv), Color(0.0f));
      return lerp(c, r, inf(3));
    }
    case TexNodeType::Attribute: {
      // Cycles' svm_node_attr: Fac is the average of a colour or vector (a UV's u), Alpha the
      // fourth component (1 without one); nothing found reads 0.
      if (n.default_uv) return {sp.uv.x, sp.uv.y, 0};
      float v[4] = {0, 0, 0, 1};
      int comps = 4;
      if (n.mode != 0 ? !sp.object_attribute(n.attribute, v) : !sp.attribute(n.attribute, v, comps)) return Color(0.0f);
      if (n.output == 2) return Color(comps == 4 ? v[3] : 1.0f);
      Color c(v[0], v[1], comps >= 3 ? v[2] : 0.0f);
      if (n.output != 1) return c;
      return Color(comps == 2 ? v[0] : (c.x + c.y + c.z) / 3.0f);
    }
    case TexNodeType::TexCoord:
      switch (n.mode) {
        case kUv: return {sp.uv.x, sp.uv.y, 0};
        case kGenerated: return sp.generated;
        case kObject: return sp.p_object;
        case kPosition: return sp.p;
        case kTrueNormal: return sp.ng;
        case kParametric: return {sp.b[0], sp.b[1], 0};  // Cycles': (1 - u - v, u, 0)
        case kTangent: return radial_tangent(sp);
        case kObjectNormal: {  // the world normal through the transposed object-to-world (Cycles')
          const Vec3 n = normal_to_object(sp, sp.ns);
          const float l = length(n);
          return l > 0 ? n / l : sp.ns;
        }
        default: return sp.ns;
      }
    case TexNodeType::Mapping: {
      Vec3 v = in(0);
      switch (n.mode) {
        case 0: return euler_rotate(v * n.scale, n.rot) + n.loc;
        case 1: return euler_rotate_inverse(v - n.loc, n.rot) / vmax(n.scale, Vec3(1e-8f));
        case 2: return euler_rotate(v * n.scale, n.rot);
        default: {
          Vec3 r = euler_rotate(v / vmax(n.scale, Vec3(1e-8f)), n.rot);
          float l = length(r);
          return l > 0 ? r / l : r;
        }
      }
    }
    case TexNodeType::NormalMap:
    case TexNodeType::Bump:
    case TexNodeType::Bevel: return eval_normal(idx, sp);
    case TexNodeType::CameraData: {
      // Cycles' camera space looks down +z; the engine's (Blender's) down -z. No scene: the
      // camera at the origin.
      Vec3 c = sp.rays ? sp.rays->texture_camera_space(sp.p) : sp.p;
      c.z = -c.z;
      if (n.mode == 1) return Color(c.z);
      if (n.mode == 2) return Color(length(c));
      const float len = length(c);
      return len > 0 ? c / len : Vec3(0.0f);
    }
    case TexNodeType::Ies: return Color(inf(0) * (n.ies ? n.ies->eval(in(1)) : 100.0f));
    case TexNodeType::LightFalloff: return Color(light_falloff(n.mode, inf(0), inf(1), sp.ray_length));
    case TexNodeType::VectorDisplacement: return vector_displacement(sp, (in(0) - Vec3(inf(1))) * inf(2), n.mode);
    case TexNodeType::Displacement: {
      const Vec3 normal = n.in[3] >= 0 ? Vec3(in(3)) : sp.ns;
      const float offset = (inf(0) - inf(1)) * inf(2);
      if (n.mode == 1 || !sp.has_object_to_world) return normal * offset;
      const Vec3 o = normal_to_object(sp, normal);
      const float len = length(o);
      if (!(len > 0) || !std::isfinite(len)) return Vec3(0.0f);
      return direction_to_world(sp, o * (offset / len));
    }
    case TexNodeType::SeparateRgb: return Color(in(0)[n.output]);
    case TexNodeType::CombineRgb: return {inf(0), inf(1), inf(2)};
    case TexNodeType::RgbToBw: return Color(luminance(in(0)));
    case TexNodeType::BrightContrast: {  // Cycles: a = 1 + contrast, b = bright - contrast / 2
      float a = 1 + inf(2), b = inf(1) - inf(2) * 0.5f;
      return vmax(in(0) * a + Color(b), Color(0.0f));
    }
    case TexNodeType::Gamma: {
      Color c = in(0);
      float g = inf(1);
      for (int i = 0; i < 3; ++i)
        if (c[i] > 0) c[i] = std::pow(c[i], g);
      return c;
    }
  }
  return Color(0.0f);
}

Vec3 TextureGraph::eval_normal(int idx, const ShadingPoint &sp) const {
  const TexNode &n = nodes_[size_t(idx)];
  Vec3 N = sp.ns;
  if (n.type == TexNodeType::NormalMap) {
    Color c = eval(n.in[0], sp);
    Vec3 m = c * 2.0f - Vec3(1.0f);
    Vec3 out;
    if (n.mode == 0 && tangent_space_normal(sp, m, out)) {
      // Blender's tangents (MikkTSpace, the exporter's attribute), as Cycles maps with them.
    } else if (n.mode == 0) {  // tangent space, tangents from the default UV map's dp/du
      Vec3 t = sp.dpdu - N * dot(N, sp.dpdu);
      if (!sp.has_uv_frame || !(length_squared(t) > 0)) return N;
      t = normalize(t);
      Vec3 b = cross(N, t);
      if (dot(b, sp.dpdv) < 0) b = -b;
      out = t * m.x + b * m.y + N * m.z;
    } else if (n.mode == 1) {
      out = direction_to_world(sp, m);
    } else {
      out = m;
    }
    float len = length(out);
    if (!(len > 0)) return N;
    out = out / len;
    float strength = std::max(eval_float(n.in[1], sp), 0.0f);
    if (strength != 1.0f) {
      out = N + (out - N) * strength;
      float l = length(out);
      out = l > 0 ? out / l : N;
    }
    return out;
  }
  if (n.type == TexNodeType::Bevel) {
    const Vec3 bevel = bevel_normal(sp, eval_float(n.in[0], sp), n.depth);
    if (n.in[1] < 0) return bevel;
    // Cycles keeps the input's normal and adds the bevel's turn away from the shading normal.
    const Vec3 input = eval_normal(n.in[1], sp), out = input + (bevel - sp.ns);
    const float len = length(out);
    return len > 0 && std::isfinite(len) ? out / len : input;
  }
  if (n.type == TexNodeType::Bump) {
    if (n.in[3] >= 0) N = eval_normal(n.in[3], sp);
    // Finite differences of the height along the surface: fixed steps of 1e-3 in UV
    // (or object units without UVs) where Cycles' bump node steps by its dP
    // differentials; a fixed step keeps a bump the same near and far.
    const float h = 1e-3f;
    ShadingPoint sx = sp.shifted({h, 0}), sy = sp.shifted({0, h});
    float h0 = eval_float(n.in[0], sp), hx = eval_float(n.in[0], sx), hy = eval_float(n.in[0], sy);
    Vec3 dpdx = sp.dpdu * h, dpdy = sp.dpdv * h;
    const Vec3 base = N;
    const bool object_space = n.mode == 1 && sp.has_object_to_world;
    if (object_space) {  // the same heights over object-space steps, the normal back to the world
      const Vec3 o = normal_to_object(sp, N);
      const float len = length(o);
      if (!(len > 0) || !std::isfinite(len)) return base;
      N = o / len;
      dpdx = sp.dpdu_object * h;
      dpdy = sp.dpdv_object * h;
    }
    Vec3 rx = cross(dpdy, N), ry = cross(N, dpdx);
    float det = dot(dpdx, rx);
    Vec3 surfgrad = rx * (hx - h0) + ry * (hy - h0);
    float strength = std::max(eval_float(n.in[1], sp), 0.0f);
    float distance = eval_float(n.in[2], sp) * (n.clamp ? -1.0f : 1.0f);
    Vec3 out = N * std::fabs(det) - surfgrad * (distance * (det < 0 ? -1.0f : 1.0f));
    float len = length(out);
    if (!(len > 0) || !std::isfinite(len)) return base;
    out = out / len;
    out = out * strength + N * (1 - strength);
    if (object_space) out = normal_to_world(sp, out);
    len = length(out);
    return len > 0 && std::isfinite(len) ? out / len : base;
  }
  return N;
}

}  // namespace rdv
