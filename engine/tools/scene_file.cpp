#include "scene_file.h"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include "core/limits.h"
#include "core/params.h"

namespace rdv_tools {

using nlohmann::json;

namespace {

struct MeshArrays {
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> slots;  // per triangle
};

constexpr float kPi = 3.14159265358979f;

// The file's values are read through these: a value of the wrong type is an error naming
// the object and the key (std::runtime_error), not a JSON library exception.
std::string text_of(const json &j, const char *key, const std::string &fallback, const std::string &what) {
  if (!j.is_object() || !j.contains(key)) return fallback;
  if (!j[key].is_string()) throw std::runtime_error(what + ": '" + key + "' must be a string");
  return j[key].get<std::string>();
}
float float_of(const json &j, const char *key, float fallback, const std::string &what) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) throw std::runtime_error(what + ": '" + key + "' must be a number");
  return float(j[key].get<double>());
}
bool flag_of(const json &j, const char *key, bool fallback, const std::string &what) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_boolean()) throw std::runtime_error(what + ": '" + key + "' must be true or false");
  return j[key].get<bool>();
}
// A count or byte offset: a whole number from 0 up to `most`.
uint64_t count_of(const json &j, const char *key, uint64_t fallback, uint64_t most, const std::string &what) {
  if (!j.contains(key)) return fallback;
  const json &v = j[key];  // JSON's non-negative integers parse as unsigned
  if (v.is_number_unsigned() && v.get<uint64_t>() <= most) return v.get<uint64_t>();
  throw std::runtime_error(what + ": '" + key + "' must be a whole number from 0 to " + std::to_string(most) +
                           ", got " + v.dump());
}
// A top-level list ("materials", ...): absent is empty; each entry must be an object.
const json &list_of(const json &doc, const char *key) {
  static const json kEmpty = json::array();
  if (!doc.contains(key)) return kEmpty;
  const json &list = doc[key];
  if (!list.is_array()) throw std::runtime_error(std::string("'") + key + "' must be a list of objects");
  for (size_t i = 0; i < list.size(); ++i)
    if (!list[i].is_object())
      throw std::runtime_error(std::string(key) + "[" + std::to_string(i) + "] must be a JSON object, got " +
                               list[i].type_name());
  return list;
}

void make_sphere(MeshArrays &m, float radius, int segments) {
  int rings = std::max(segments / 2, 2);
  segments = std::max(segments, 3);
  for (int r = 0; r <= rings; ++r) {
    float theta = kPi * r / rings;
    for (int s = 0; s <= segments; ++s) {
      float phi = 2 * kPi * s / segments;
      float n[3] = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      for (float c : n) { m.positions.push_back(c * radius); m.normals.push_back(c); }
      m.uvs.push_back(float(s) / segments);
      m.uvs.push_back(1.0f - float(r) / rings);
    }
  }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      uint32_t a = r * (segments + 1) + s, b = a + segments + 1;
      if (r > 0) m.indices.insert(m.indices.end(), {a, b, a + 1});            // skip the degenerate pole triangles
      if (r < rings - 1) m.indices.insert(m.indices.end(), {a + 1, b, b + 1});
    }
}

void make_quad(MeshArrays &m, float sx, float sy) {
  m.positions = {-sx / 2, -sy / 2, 0, sx / 2, -sy / 2, 0, sx / 2, sy / 2, 0, -sx / 2, sy / 2, 0};
  m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  m.indices = {0, 1, 2, 0, 2, 3};
}

void make_disk(MeshArrays &m, float radius, int segments) {
  segments = std::max(segments, 3);
  m.positions = {0, 0, 0};
  m.normals = {0, 0, 1};
  m.uvs = {0.5f, 0.5f};
  for (int s = 0; s < segments; ++s) {
    float phi = 2 * kPi * s / segments;
    m.positions.insert(m.positions.end(), {radius * std::cos(phi), radius * std::sin(phi), 0});
    m.normals.insert(m.normals.end(), {0, 0, 1});
    m.uvs.insert(m.uvs.end(), {0.5f + 0.5f * std::cos(phi), 0.5f + 0.5f * std::sin(phi)});
    m.indices.insert(m.indices.end(), {0u, uint32_t(1 + s), uint32_t(1 + (s + 1) % segments)});
  }
}

void make_box(MeshArrays &m, float sx, float sy, float sz) {
  // Six faces with their own vertices (flat shading), normals pointing out.
  const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    float nx = n[f][0], ny = n[f][1], nz = n[f][2];
    // Two tangents u, v with u x v = n.
    float u[3], v[3];
    if (nx != 0) { u[0] = 0; u[1] = nx; u[2] = 0; v[0] = 0; v[1] = 0; v[2] = 1; }
    else if (ny != 0) { u[0] = 0; u[1] = 0; u[2] = ny; v[0] = 1; v[1] = 0; v[2] = 0; }
    else { u[0] = nz; u[1] = 0; u[2] = 0; v[0] = 0; v[1] = 1; v[2] = 0; }
    uint32_t base = uint32_t(m.positions.size() / 3);
    const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (auto &c : corners) {
      float p[3];
      for (int k = 0; k < 3; ++k) p[k] = n[f][k] + c[0] * u[k] + c[1] * v[k];
      m.positions.insert(m.positions.end(), {p[0] * sx / 2, p[1] * sy / 2, p[2] * sz / 2});
      m.normals.insert(m.normals.end(), {nx, ny, nz});
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
}

template <class T>
std::vector<T> numbers(const json &j, const std::string &what) {
  if (!j.is_array()) throw std::runtime_error(what + " must be an array of numbers");
  std::vector<T> v;
  v.reserve(j.size());
  for (const auto &e : j) {
    if constexpr (std::is_integral_v<T>) {  // indices: whole numbers in T's range (1e30 would not convert)
      bool whole = e.is_number_unsigned() ? e.get<uint64_t>() <= std::numeric_limits<T>::max()
                                          : e.is_number_integer() && e.get<int64_t>() >= 0;
      if (!whole) throw std::runtime_error(what + " must be whole numbers from 0 to " +
                                           std::to_string(std::numeric_limits<T>::max()) + ", got " + e.dump());
      v.push_back(T(e.get<uint64_t>()));
    } else if (e.is_number()) v.push_back(e.get<T>());
    else if (e.is_null() && std::is_floating_point_v<T>) v.push_back(T(NAN));  // JSON has no NaN literal
    else throw std::runtime_error(what + " must be an array of numbers");
  }
  return v;
}

// Reads count values at offset; the file's size is checked first, so a header that
// claims 1e12 vertices is an error, not a terabyte allocation.
template <class T>
std::vector<T> read_binary(std::ifstream &f, uint64_t file_size, uint64_t offset, uint64_t count,
                           const std::string &what) {
  if (offset > file_size || count > (file_size - offset) / sizeof(T))
    throw std::runtime_error(what + ": side file is too short (" + std::to_string(file_size) + " bytes; " +
                             std::to_string(count) + " values at byte " + std::to_string(offset) + ")");
  std::vector<T> v(count);
  f.seekg(std::streamoff(offset));
  f.read(reinterpret_cast<char *>(v.data()), std::streamsize(count * sizeof(T)));
  if (!f) throw std::runtime_error(what + ": side file is too short");
  return v;
}

// A shape's "segments", checked before anything is generated: a sphere of n segments
// makes about n^2 triangles, a disk n (kMaxGeneratedTriangles bounds both).
int shape_segments(const json &s, const std::string &what, const std::string &type, int fallback) {
  if (!s.contains("segments")) return fallback;
  const json &v = s["segments"];
  if (!v.is_number()) throw std::runtime_error(what + ": " + type + " 'segments' must be a number");
  double n = v.get<double>();
  if (!(n >= 3)) n = 3;  // fewer than 3 make no shape: 3, as always
  double triangles = type == "sphere" ? n * std::max(std::floor(n / 2), 2.0) * 2 : n;
  if (triangles > double(rdv::kMaxGeneratedTriangles)) {
    int most = type == "sphere" ? int(std::sqrt(double(rdv::kMaxGeneratedTriangles))) : int(rdv::kMaxGeneratedTriangles);
    char text[512];
    std::snprintf(text, sizeof text,
                  "%s: a %s of %.6g segments makes %.3g triangles; generated shapes are limited to %llu triangles "
                  "(%s: at most %d segments)",
                  what.c_str(), type.c_str(), n, triangles, (unsigned long long)rdv::kMaxGeneratedTriangles,
                  type.c_str(), most);
    throw rdv::Error(RDV_ERROR_LIMIT, text);
  }
  return int(n);
}

MeshArrays mesh_arrays(const json &j, const std::string &what, const std::string &base_dir) {
  MeshArrays m;
  if (j.contains("shape")) {
    const json &s = j["shape"];
    const std::string shape = what + " shape";
    if (!s.is_object()) throw std::runtime_error(shape + " must be a JSON object");
    std::string type = text_of(s, "type", "", shape);
    if (type == "sphere") make_sphere(m, float_of(s, "radius", 1.0f, shape), shape_segments(s, what, type, 48));
    else if (type == "quad") {
      float size = float_of(s, "size", 2.0f, shape);
      make_quad(m, float_of(s, "size_x", size, shape), float_of(s, "size_y", size, shape));
    } else if (type == "disk") make_disk(m, float_of(s, "radius", 1.0f, shape), shape_segments(s, what, type, 64));
    else if (type == "box") {
      auto size = s.contains("size") ? numbers<float>(s["size"], what + " shape size") : std::vector<float>{2, 2, 2};
      if (size.size() != 3) throw std::runtime_error(what + ": box size needs 3 numbers");
      make_box(m, size[0], size[1], size[2]);
    } else throw std::runtime_error(what + ": unknown shape type '" + type + "' (sphere, quad, disk, box)");
    if (!flag_of(s, "smooth", true, shape)) m.normals.clear();  // flat shading: face normals only
  } else if (j.contains("binary")) {
    const json &b = j["binary"];
    const std::string side = what + " 'binary'";
    if (!b.is_object()) throw std::runtime_error(side + " must be a JSON object");
    std::string file = (std::filesystem::path(base_dir) / text_of(b, "file", "", side)).string();
    std::ifstream f(file, std::ios::binary);
    if (!f) throw std::runtime_error(what + ": cannot open side file '" + file + "'");
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(file, ec);
    if (ec) throw std::runtime_error(what + ": cannot read side file '" + file + "'");
    // Counts above the vertex limit of the C ABI (32 bits) cannot be a mesh; below it,
    // multiplied by 3 they stay far from 64-bit overflow.
    uint64_t nv = count_of(b, "num_vertices", 0, UINT32_MAX, side), nt = count_of(b, "num_triangles", 0, UINT32_MAX, side);
    auto offset = [&](const char *key) { return count_of(b, key, 0, UINT64_MAX, side); };
    m.positions = read_binary<float>(f, size, offset("positions"), nv * 3, what);
    m.indices = read_binary<uint32_t>(f, size, offset("indices"), nt * 3, what);
    if (b.contains("normals")) m.normals = read_binary<float>(f, size, offset("normals"), nv * 3, what);
    if (b.contains("uvs")) m.uvs = read_binary<float>(f, size, offset("uvs"), nv * 2, what);
    if (b.contains("material_indices")) m.slots = read_binary<uint32_t>(f, size, offset("material_indices"), nt, what);
  } else {
    if (!j.contains("positions") || !j.contains("indices"))
      throw std::runtime_error(what + ": needs 'positions' and 'indices', a 'shape' or a 'binary' file");
    m.positions = numbers<float>(j["positions"], what + " 'positions'");
    m.indices = numbers<uint32_t>(j["indices"], what + " 'indices'");
    if (j.contains("normals")) m.normals = numbers<float>(j["normals"], what + " 'normals'");
    if (j.contains("uvs")) m.uvs = numbers<float>(j["uvs"], what + " 'uvs'");
  }
  if (j.contains("material_indices")) m.slots = numbers<uint32_t>(j["material_indices"], what + " 'material_indices'");
  if (m.positions.size() % 3) throw std::runtime_error(what + ": 'positions' length is not a multiple of 3");
  if (m.indices.size() % 3) throw std::runtime_error(what + ": 'indices' length is not a multiple of 3");
  size_t nv = m.positions.size() / 3;
  if (!m.normals.empty() && m.normals.size() != nv * 3)
    throw std::runtime_error(what + ": 'normals' must have 3 numbers per vertex");
  if (!m.uvs.empty() && m.uvs.size() != nv * 2) throw std::runtime_error(what + ": 'uvs' must have 2 numbers per vertex");
  if (!m.slots.empty() && m.slots.size() != m.indices.size() / 3)
    throw std::runtime_error(what + ": 'material_indices' must have one entry per triangle");
  return m;
}

// Image files named in materials ({"node":"image","file":...}), the world's
// environment and volume grids' VDB files are relative to the scene file, as side files are.
json with_resolved_files(json j, const std::string &base_dir, bool holds_file = false) {
  if (j.is_object()) {
    bool image = holds_file || (j.contains("node") && j["node"] == "image");
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (image && it.key() == "file" && it.value().is_string()) {
        std::filesystem::path f = it.value().get<std::string>();
        if (f.is_relative() && !f.empty()) it.value() = (std::filesystem::path(base_dir) / f).lexically_normal().string();
      } else {
        it.value() = with_resolved_files(it.value(), base_dir, it.key() == "environment" || it.key() == "grid");
      }
    }
  } else if (j.is_array()) {
    for (auto &v : j) v = with_resolved_files(v, base_dir);
  }
  return j;
}

std::string without(const json &j, std::initializer_list<const char *> keys) {
  json copy = j;
  for (const char *k : keys) copy.erase(k);
  return copy.dump();
}

// Every object of the file nests at most kMaxJsonDepth levels, checked without recursion
// before anything copies, dumps or walks it (those recurse once per level).
void check_nesting(const json &doc) {
  auto check = [](const json &j, const std::string &what) {
    if (rdv::json_depth(j) > rdv::kMaxJsonDepth)
      throw rdv::Error(RDV_ERROR_LIMIT, what + ": nests more than " + std::to_string(rdv::kMaxJsonDepth) +
                                            " levels of JSON arrays / objects (a Mix shader or texture node adds "
                                            "one); too deep to be a real scene object");
  };
  const std::map<std::string, std::string> kLists = {
      {"materials", "material"}, {"meshes", "mesh"}, {"lights", "light"}, {"instances", "instance"}};
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    auto list = kLists.find(it.key());
    if (list == kLists.end() || !it.value().is_array()) { check(it.value(), "'" + it.key() + "'"); continue; }
    const std::string &kind = list->second;
    size_t i = 0;
    for (const json &e : it.value()) {
      std::string what = it.key() + "[" + std::to_string(i++) + "]";
      if (e.is_object() && e.contains("name") && e["name"].is_string())
        what = kind + " '" + e["name"].get<std::string>() + "' (" + what + ")";
      check(e, what);
    }
  }
}

// Limits (status RDV_ERROR_LIMIT) stop the load: a hostile file is an error, not a magenta material.
void stop_at_limit(rdv_status status) {
  if (status == RDV_ERROR_LIMIT) throw rdv::Error(status, rdv_last_error());
}

const std::map<std::string, int> kTopLevelKeys = {{"settings", 0}, {"camera", 0}, {"world", 0}, {"materials", 0},
                                                  {"meshes", 0}, {"instances", 0}, {"lights", 0}, {"version", 0}};

}  // namespace

LoadedScene load_scene_json(const std::string &text, const std::string &base_dir, rdv_scene *scene,
                            const LoadOptions &options) {
  LoadedScene out;
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception &e) {
    throw std::runtime_error(std::string("malformed JSON: ") + e.what());
  }
  if (!doc.is_object()) throw std::runtime_error("the scene must be a JSON object");
  check_nesting(doc);
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (!kTopLevelKeys.count(it.key())) out.problems.push_back("unknown top-level key '" + it.key() + "' ignored");
  auto report = [&](const std::string &what) { out.problems.push_back(what + ": " + rdv_last_error()); };

  std::map<std::string, uint32_t> materials;
  size_t material_index = 0;
  for (const json &m : list_of(doc, "materials")) {
    const std::string index = "materials[" + std::to_string(material_index++) + "]";
    std::string name = text_of(m, "name", "material " + std::to_string(materials.size()), index);
    uint32_t id;
    rdv_status status =
        rdv_scene_add_material(scene, name.c_str(), without(with_resolved_files(m, base_dir), {"name"}).c_str(), &id);
    stop_at_limit(status);
    if (status != RDV_OK) {
      out.problems.push_back(std::string(rdv_last_error()) + "; rendering it magenta");
      rdv_scene_add_material(scene, name.c_str(), R"({"type":"diffuse","color":[1,0,1]})", &id);
    }
    materials[name] = id;
  }
  uint32_t default_material = 0;
  bool have_default = false;
  auto get_default = [&]() {
    if (!have_default) {
      rdv_scene_add_material(scene, "default", R"({"type":"diffuse","color":[0.8,0.8,0.8]})", &default_material);
      have_default = true;
    }
    return default_material;
  };

  // An instance's object settings (rdv_scene_set_instance_params): "holdout", "shadow_catcher", "look_copy", "visibility",
  // "pass_index", "random_id", "color", "object_attributes", "instancer_attributes", "cryptomatte"; and its "motion"
  // (rdv_scene_set_instance_motion), unless motion blur is off.
  auto object_params = [&options](const json &j, const std::string &what) {
    json p = json::object();
    if (flag_of(j, "holdout", false, what)) p["holdout"] = true;
    if (flag_of(j, "shadow_catcher", false, what)) p["shadow_catcher"] = true;
    if (flag_of(j, "look_copy", false, what)) p["look_copy"] = true;
    if (j.contains("visibility")) p["visibility"] = j["visibility"];  // the engine checks it
    if (j.contains("pass_index")) p["pass_index"] = j["pass_index"];  // and these
    if (j.contains("random_id")) p["random_id"] = j["random_id"];
    if (j.contains("color")) p["color"] = j["color"];
    for (const char *key : {"object_attributes", "instancer_attributes", "cryptomatte"})
      if (j.contains(key)) p[key] = j[key];
    if (j.contains("motion") && options.motion_blur) p["motion"] = j["motion"];
    return p;
  };
  struct MeshEntry { uint32_t id; json transform; bool instanced = false; json params; };
  std::map<std::string, MeshEntry> meshes;
  for (const json &j : list_of(doc, "meshes")) {
    std::string name = text_of(j, "name", "mesh " + std::to_string(meshes.size()), "mesh " + std::to_string(meshes.size()));
    std::string what = "mesh '" + name + "'";
    try {
      MeshArrays a = mesh_arrays(j, what, base_dir);
      std::vector<uint32_t> slot_ids;
      const json &slots = j.contains("materials") ? j["materials"] : json::array();
      if (!slots.is_array()) throw std::runtime_error(what + ": 'materials' must be a list of material names");
      for (const json &s : slots) {
        std::string mname = s.is_string() ? s.get<std::string>() : "";
        auto it = materials.find(mname);
        if (it == materials.end()) {
          out.problems.push_back(what + ": material '" + mname + "' does not exist; using the default");
          slot_ids.push_back(get_default());
        } else slot_ids.push_back(it->second);
      }
      if (slot_ids.empty()) slot_ids.push_back(get_default());
      std::vector<uint32_t> ids(a.indices.size() / 3, slot_ids[0]);
      for (size_t t = 0; t < a.slots.size(); ++t) {
        if (a.slots[t] >= slot_ids.size())
          throw std::runtime_error(what + ": triangle " + std::to_string(t) + " uses material slot " +
                                   std::to_string(a.slots[t]) + " of " + std::to_string(slot_ids.size()));
        ids[t] = slot_ids[a.slots[t]];
      }
      uint32_t id;
      rdv_status status =
          rdv_scene_add_mesh(scene, name.c_str(), a.positions.data(), uint32_t(a.positions.size() / 3),
                             a.normals.empty() ? nullptr : a.normals.data(), a.uvs.empty() ? nullptr : a.uvs.data(),
                             a.indices.data(), uint32_t(a.indices.size() / 3), ids.data(), 0, &id);
      stop_at_limit(status);
      if (status != RDV_OK) {
        out.problems.push_back(std::string(rdv_last_error()) + "; mesh left out");
        continue;
      }
      // Deformation blur (rdv_scene_set_mesh_motion): "motion_positions" (and, optionally,
      // "motion_normals"), a list of steps of 3 numbers per vertex, unless motion blur is off.
      if (j.contains("motion_positions") && options.motion_blur) {
        auto steps_of = [&](const char *key) {
          std::vector<float> flat;
          if (!j.contains(key)) return flat;
          if (!j[key].is_array()) throw std::runtime_error(what + ": '" + key + "' must be a list of steps");
          for (size_t k = 0; k < j[key].size(); ++k) {
            std::vector<float> step = numbers<float>(j[key][k], what + " '" + key + "' step " + std::to_string(k));
            if (step.size() != a.positions.size())
              throw std::runtime_error(what + ": '" + key + "' step " + std::to_string(k) + " has " +
                                       std::to_string(step.size()) + " numbers, the mesh's vertices " +
                                       std::to_string(a.positions.size()));
            flat.insert(flat.end(), step.begin(), step.end());
          }
          return flat;
        };
        std::vector<float> positions = steps_of("motion_positions"), normals = steps_of("motion_normals");
        if (!normals.empty() && normals.size() != positions.size())
          throw std::runtime_error(what + ": 'motion_normals' has " + std::to_string(normals.size() / std::max<size_t>(a.positions.size(), 1)) +
                                   " steps, 'motion_positions' " + std::to_string(positions.size() / std::max<size_t>(a.positions.size(), 1)));
        const uint32_t nv = uint32_t(a.positions.size() / 3);
        const uint32_t num_steps = nv ? uint32_t(positions.size() / (3 * size_t(nv))) : 0;
        if (rdv_scene_set_mesh_motion(scene, id, positions.data(), normals.empty() ? nullptr : normals.data(), nv,
                                      num_steps) != RDV_OK)
          out.problems.push_back(std::string(rdv_last_error()) + "; rendered without deformation blur");
      }
      // Named per-vertex attributes: [{"name", "kind": "uv"|"color", "components", "data"}].
      for (const json &at : list_of(j, "attributes")) {
        std::string an = text_of(at, "name", "", what + " attribute"), kind = text_of(at, "kind", "color", what + " attribute '" + an + "'");
        const std::string attribute = what + " attribute '" + an + "'";
        uint32_t comps = uint32_t(count_of(at, "components", kind == "uv" ? 2u : 3u, 4, attribute));
        std::vector<float> data = numbers<float>(at.contains("data") ? at["data"] : json::array(), attribute);
        if (comps == 0 || data.size() % comps)
          throw std::runtime_error(what + " attribute '" + an + "': data length is not a multiple of its components");
        if (rdv_scene_add_mesh_attribute(scene, id, an.c_str(), kind.c_str(), data.data(), comps,
                                         uint32_t(data.size() / comps)) != RDV_OK)
          out.problems.push_back(std::string(rdv_last_error()) + "; attribute left out");
      }
      meshes[name] = {id, j.contains("transform") ? j["transform"] : json(), false, object_params(j, what)};
    } catch (const rdv::Error &e) {
      if (e.status == RDV_ERROR_LIMIT) throw;
      out.problems.push_back(std::string(e.what()) + "; mesh left out");
    } catch (const std::exception &e) {
      out.problems.push_back(std::string(e.what()) + "; mesh left out");
    }
  }

  auto add_instance = [&](uint32_t mesh, const json &transform, const std::string &what, const json &params) {
    // The engine's own transform rules (16 numbers, or translate/rotate/scale).
    rdv::Transform t;
    try {
      if (!transform.is_null()) t = rdv::parse_transform(transform, what);
    } catch (const rdv::Error &e) {
      throw std::runtime_error(e.what());
    }
    // Motion steps: a list of transforms (the same rules), evenly spaced over the shutter.
    std::vector<float> steps;
    json settings = params;
    if (settings.contains("motion")) {
      const json &motion = settings["motion"];
      if (!motion.is_array()) throw std::runtime_error(what + ": 'motion' must be a list of transforms");
      try {
        for (size_t k = 0; k < motion.size(); ++k) {
          rdv::Transform step = rdv::parse_transform(motion[k], what + " 'motion' step " + std::to_string(k));
          steps.insert(steps.end(), &step.m[0][0], &step.m[0][0] + 16);
        }
      } catch (const rdv::Error &e) {
        throw std::runtime_error(e.what());
      }
      settings.erase("motion");
    }
    uint32_t id;
    if (rdv_scene_add_instance(scene, mesh, &t.m[0][0], &id) != RDV_OK) return report(what);
    if (!settings.empty() && rdv_scene_set_instance_params(scene, id, settings.dump().c_str()) != RDV_OK) report(what);
    if (!steps.empty() && rdv_scene_set_instance_motion(scene, id, steps.data(), uint32_t(steps.size() / 16)) != RDV_OK)
      report(what);
  };

  for (const json &j : list_of(doc, "instances")) {
    std::string mesh = text_of(j, "mesh", "", "instance");
    auto it = meshes.find(mesh);
    if (it == meshes.end()) {
      out.problems.push_back("instance of mesh '" + mesh + "': no such mesh; instance left out");
      continue;
    }
    it->second.instanced = true;
    try {
      add_instance(it->second.id, j.contains("transform") ? j["transform"] : json(), "instance of mesh '" + mesh + "'",
                   object_params(j, "instance of mesh '" + mesh + "'"));
    } catch (const std::exception &e) {
      out.problems.push_back(e.what());
    }
  }
  for (auto &[name, entry] : meshes) {
    if (entry.instanced) continue;
    try {
      add_instance(entry.id, entry.transform, "mesh '" + name + "'", entry.params);
    } catch (const std::exception &e) {
      out.problems.push_back(e.what());
    }
  }

  int light_index = 0;
  for (const json &j : list_of(doc, "lights")) {
    std::string name = text_of(j, "name", "light " + std::to_string(light_index), "light " + std::to_string(light_index));
    ++light_index;
    rdv_status status = rdv_scene_add_light(scene, name.c_str(), without(j, {"name"}).c_str(), nullptr);
    stop_at_limit(status);
    if (status != RDV_OK) out.problems.push_back(std::string(rdv_last_error()) + "; light left out");
  }
  if (doc.contains("world")) {
    rdv_status status = rdv_scene_set_world(scene, with_resolved_files(doc["world"], base_dir).dump().c_str());
    stop_at_limit(status);
    if (status != RDV_OK) out.problems.push_back(std::string(rdv_last_error()) + "; using the default world");
  }
  if (!doc.contains("camera")) throw std::runtime_error("the scene has no 'camera'");
  json camera = doc["camera"];
  if (!options.motion_blur && camera.is_object())
    for (const char *key : {"shutter_open", "shutter_close", "motion"}) camera.erase(key);
  if (rdv_scene_set_camera(scene, camera.dump().c_str()) != RDV_OK)
    throw std::runtime_error(rdv_last_error());
  out.settings_json = doc.contains("settings") ? doc["settings"].dump() : "{}";
  return out;
}

LoadedScene load_scene_file(const std::string &path, rdv_scene *scene, const LoadOptions &options) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot open scene file '" + path + "'");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string base = std::filesystem::path(path).parent_path().string();
  try {
    return load_scene_json(ss.str(), base.empty() ? "." : base, scene, options);
  } catch (const std::exception &e) {
    throw std::runtime_error("scene file '" + path + "': " + e.what());
  }
}

}  // namespace rdv_tools
