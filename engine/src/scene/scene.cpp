#include "scene/scene.h"
#include <map>
#include <nlohmann/json.hpp>
#include "core/limits.h"
#include "core/log.h"
#include "core/ray_offset.h"
#include "lights/sky_nishita.h"
#include "lights/sphere_lamp.h"
#include "lights/volume_light.h"
#include "lights/sky_preetham.h"
#include "textures/image_texture.h"

namespace rdv {

Scene::Scene() = default;

void Scene::warn(const std::string &message) const {
  log_warning(message);
  std::lock_guard<std::mutex> lock(messages_mutex_);
  // Once each: a viewport makes a session per change, each with the same settings' warnings.
  if (("\n" + messages_).find("\n" + message + "\n") != std::string::npos) return;
  messages_ += message;
  messages_ += '\n';
}

std::string Scene::messages() const {
  std::lock_guard<std::mutex> lock(messages_mutex_);
  return messages_;
}

// A material description may carry a "volume" (the medium inside meshes using it), and
// "type": "volume" means no surface at all: an index-matched medium boundary.
Scene::ParsedMaterial Scene::parse_material(const std::string &name, Params &params) {
  ParsedMaterial pm;
  if (const nlohmann::json *volume = params.get_json("volume")) {
    Params v(volume->dump(), params.what() + " volume");
    pm.medium = Medium::from_params(v, name, &grid_buffers_);
    v.check_all_used();
    pm.has_medium = true;
  }
  pm.boundary_only = params.has("type") && params.get_string("type", "") == "volume";
  if (pm.boundary_only) {
    params.get_string("cryptomatte", name);  // a boundary has no surface: no Cryptomatte pass sees it
    params.check_all_used();
    if (!pm.has_medium) fail(params.what() + ": type 'volume' needs a 'volume' object");
    pm.material = Material::error_material(name);  // never shaded: rays pass through
  } else {
    pm.material = Material::from_params(params, name, &image_buffers_);
  }
  return pm;
}

uint32_t Scene::add_material(const std::string &name, Params &params) {
  ParsedMaterial pm = parse_material(name, params);
  for (const std::string &w : pm.material.warnings) warn(w);
  for (const std::string &w : pm.medium.warnings) warn(w);
  materials_.push_back(std::move(pm.material));
  material_edits_.push_back(0);
  material_interior_.push_back(pm.has_medium ? int(media_.size()) : -1);
  if (pm.has_medium) media_.push_back(pm.medium);
  material_boundary_.push_back(pm.boundary_only ? 1 : 0);
  dirty_ = true;
  return static_cast<uint32_t>(materials_.size() - 1);
}

uint32_t Scene::add_grid(const std::string &name, const float *values, uint32_t nx, uint32_t ny, uint32_t nz) {
  const std::string what = "grid '" + name + "'";
  if (!values) fail(what + ": no values");
  if (nx < 1 || ny < 1 || nz < 1 || double(nx) * ny * nz > 1e9)
    fail(what + ": the resolution must be positive (at most 1e9 voxels)");
  size_t count = size_t(nx) * ny * nz;
  check_memory(what, std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + " voxels",
               double(count) * sizeof(float) * 2);  // the copy, and the medium's grid built from it
  for (size_t i = 0; i < count; ++i)
    if (!(values[i] >= 0) || !std::isfinite(values[i])) fail(what + ": densities must be finite and not negative");
  GridBuffer buffer{name, int(nx), int(ny), int(nz), std::vector<float>(values, values + count)};
  for (uint32_t id = 0; id < grid_buffers_.size(); ++id)
    if (grid_buffers_[id].name == name) {  // re-added (a simulation step): replace it
      grid_buffers_[id] = std::move(buffer);
      return id;
    }
  grid_buffers_.push_back(std::move(buffer));
  return uint32_t(grid_buffers_.size() - 1);
}

uint32_t Scene::add_image(const std::string &name, const float *pixels, uint32_t width, uint32_t height,
                          uint32_t channels, const std::string &colorspace) {
  const std::string what = "image '" + name + "'";
  if (!pixels) fail(what + ": no pixels");
  if (width < 1 || height < 1 || width > 65536 || height > 65536 || double(width) * height > double(1 << 28))
    fail(what + ": the size must be positive (at most 65536 on a side, 2^28 texels)");
  if (channels < 1 || channels > 4) fail(what + ": 'channels' must be 1 to 4");
  check_memory(what, std::to_string(width) + "x" + std::to_string(height) + " texels",
               double(width) * height * channels * sizeof(float) * 4 / 3);  // float texels and their MIP levels
  std::string problem;
  size_t non_finite = 0;
  int id = ImageTextures::instance().add_pixels(pixels, int(width), int(height), int(channels), colorspace, problem,
                                                &non_finite);
  ImageBuffer buffer{name, std::make_shared<const MemoryImage>(id, int(width), int(height), int(channels))};
  if (!problem.empty()) warn(what + ": " + problem);
  if (non_finite)
    warn(what + ": " + std::to_string(non_finite) + " pixel values are NaN or infinite; set to 0");
  for (uint32_t i = 0; i < image_buffers_.size(); ++i)
    if (image_buffers_[i].name == name) {  // re-added (painted, edited): replace it
      image_buffers_[i] = std::move(buffer);
      return i;
    }
  image_buffers_.push_back(std::move(buffer));
  return uint32_t(image_buffers_.size() - 1);
}

uint32_t Scene::add_error_material(const std::string &name) {
  materials_.push_back(Material::error_material(name));
  material_edits_.push_back(0);
  material_interior_.push_back(-1);
  material_boundary_.push_back(0);
  return static_cast<uint32_t>(materials_.size() - 1);
}

void Scene::set_material(uint32_t id, Params &params) {
  if (id >= materials_.size())
    fail("material " + std::to_string(id) + ": no such material (" + std::to_string(materials_.size()) + " materials)");
  ParsedMaterial pm = parse_material(materials_[id].name, params);
  for (const std::string &w : pm.material.warnings) warn(w);
  for (const std::string &w : pm.medium.warnings) warn(w);
  materials_[id] = std::move(pm.material);
  ++material_edits_[id];
  if (material_boundary_[id] != uint8_t(pm.boundary_only)) {
    // Boundaries have BVHs of their own: the meshes using this material are rebuilt.
    material_boundary_[id] = pm.boundary_only ? 1 : 0;
    for (uint32_t m = 0; m < meshes_.size(); ++m)
      if (std::find(meshes_[m].materials.begin(), meshes_[m].materials.end(), id) != meshes_[m].materials.end())
        accel_.mark_mesh_dirty(m);
  }
  if (!pm.has_medium) {
    drop_medium(material_interior_[id]);
    material_interior_[id] = -1;
  } else if (material_interior_[id] >= 0) {
    media_[material_interior_[id]] = pm.medium;
  } else {
    material_interior_[id] = int(media_.size());
    media_.push_back(pm.medium);
  }
  dirty_ = true;  // emission may have changed: rebuild the light tables
}

// Every medium has one owner (a material's interior or the world), so the one an edit
// takes away is referred to by nothing else: erase it, and the ids after it move down one
// in the owners (what commit() derives from media is rebuilt: the edit set dirty_). A scene
// whose media are all taken away is media-free again (has_media(), no medium code).
void Scene::drop_medium(int id) {
  if (id < 0) return;
  media_.erase(media_.begin() + id);
  for (int &m : material_interior_)
    if (m > id) --m;
  if (world_medium_ > id) --world_medium_;
  camera_media_.clear();  // found again by commit()
  dirty_ = true;
}

void Scene::set_light(uint32_t id, Params &params) {
  if (id >= user_lights_.size())
    fail("light " + std::to_string(id) + ": no such light (" + std::to_string(user_lights_.size()) + " lights)");
  UserLight made = make_light(params, &image_buffers_);
  for (const std::string &w : made.warnings) warn(w);
  user_lights_[id] = made.light;
  user_light_emissions_[id] = std::move(made.emission);
  dirty_ = true;
}

uint32_t Scene::add_mesh(const std::string &name, const float *positions, uint32_t num_vertices, const float *normals,
                         const float *uvs, const uint32_t *indices, uint32_t num_triangles,
                         const uint32_t *material_ids, uint32_t default_material) {
  meshes_.push_back(make_mesh(name, positions, num_vertices, normals, uvs, indices, num_triangles, material_ids,
                              default_material));
  dirty_ = true;
  return static_cast<uint32_t>(meshes_.size() - 1);
}

void Scene::set_mesh(uint32_t id, const float *positions, uint32_t num_vertices, const float *normals,
                     const float *uvs, const uint32_t *indices, uint32_t num_triangles, const uint32_t *material_ids,
                     uint32_t default_material) {
  if (id >= meshes_.size())
    fail("mesh " + std::to_string(id) + ": no such mesh (" + std::to_string(meshes_.size()) + " meshes)");
  meshes_[id] = make_mesh(meshes_[id].name, positions, num_vertices, normals, uvs, indices, num_triangles,
                          material_ids, default_material);
  accel_.mark_mesh_dirty(id);
  dirty_ = true;
}

Mesh Scene::make_mesh(const std::string &name, const float *positions, uint32_t num_vertices, const float *normals,
                      const float *uvs, const uint32_t *indices, uint32_t num_triangles,
                      const uint32_t *material_ids, uint32_t default_material) {
  const std::string what = "mesh '" + name + "'";
  if (num_vertices > 0 && !positions) fail(what + ": 'positions' is NULL");
  if (num_triangles > 0 && !indices) fail(what + ": 'indices' is NULL");
  if (!material_ids && default_material >= materials_.size())
    fail(what + ": default material " + std::to_string(default_material) + " does not exist (" +
         std::to_string(materials_.size()) + " materials)");
  // What the engine keeps per vertex (position, normal, UV) and per triangle (indices,
  // material, about 64 bytes of BVH), checked before anything is allocated.
  check_memory(what, std::to_string(num_vertices) + " vertices and " + std::to_string(num_triangles) + " triangles",
               double(num_vertices) * (sizeof(Vec3) * 2 + sizeof(Vec2)) + double(num_triangles) * (16 + 64));
  // Validate everything before keeping anything: a rejected mesh leaves no trace.
  for (uint64_t i = 0; i < 3ull * num_triangles; ++i)
    if (indices[i] >= num_vertices)
      fail(what + ": triangle " + std::to_string(i / 3) + " uses vertex " + std::to_string(indices[i]) +
           " but the mesh has " + std::to_string(num_vertices) + " vertices");
  if (material_ids)
    for (uint32_t i = 0; i < num_triangles; ++i)
      if (material_ids[i] >= materials_.size())
        fail(what + ": triangle " + std::to_string(i) + " uses material " + std::to_string(material_ids[i]) +
             " which does not exist (" + std::to_string(materials_.size()) + " materials)");

  Mesh m;
  m.name = name;
  m.positions.resize(size_t(num_vertices) + 1);  // +1: padding for Embree
  uint32_t bad_vertices = 0;
  std::vector<bool> vertex_ok(num_vertices, true);
  for (uint32_t i = 0; i < num_vertices; ++i) {
    Vec3 p{positions[3 * size_t(i)], positions[3 * size_t(i) + 1], positions[3 * size_t(i) + 2]};
    if (!is_finite(p)) { vertex_ok[i] = false; ++bad_vertices; p = Vec3(0.0f); }
    m.positions[i] = p;
  }
  if (normals) {
    m.normals.resize(num_vertices);
    uint32_t bad_normals = 0;
    for (uint32_t i = 0; i < num_vertices; ++i) {
      Vec3 n{normals[3 * size_t(i)], normals[3 * size_t(i) + 1], normals[3 * size_t(i) + 2]};
      float len = length(n);
      if (!std::isfinite(len) || len == 0) { ++bad_normals; n = Vec3(0.0f); }
      else n = n / len;
      m.normals[i] = n;  // zero marks "use the face normal"
    }
    if (bad_normals) warn(what + ": " + std::to_string(bad_normals) + " vertex normals are zero or not finite; those corners use the face normal");
  }
  if (uvs) {
    m.uvs.resize(num_vertices);
    uint32_t bad_uvs = 0;
    for (uint32_t i = 0; i < num_vertices; ++i) {
      Vec2 uv{uvs[2 * size_t(i)], uvs[2 * size_t(i) + 1]};
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) { ++bad_uvs; uv = {0, 0}; }
      m.uvs[i] = uv;
    }
    if (bad_uvs) warn(what + ": " + std::to_string(bad_uvs) + " UVs are not finite; set to (0, 0)");
  }
  uint32_t dropped_nonfinite = 0, dropped_degenerate = 0;
  m.indices.reserve(3ull * num_triangles);
  m.materials.reserve(num_triangles);
  for (uint32_t t = 0; t < num_triangles; ++t) {
    uint32_t a = indices[3 * size_t(t)], b = indices[3 * size_t(t) + 1], c = indices[3 * size_t(t) + 2];
    if (!vertex_ok[a] || !vertex_ok[b] || !vertex_ok[c]) { ++dropped_nonfinite; continue; }
    Vec3 n = cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
    if (!(length_squared(n) > 0) || !is_finite(n)) { ++dropped_degenerate; continue; }
    m.indices.insert(m.indices.end(), {a, b, c});
    m.materials.push_back(material_ids ? material_ids[t] : default_material);
  }
  if (bad_vertices)
    warn(what + ": " + std::to_string(bad_vertices) + " vertices are NaN or infinite; " +
         std::to_string(dropped_nonfinite) + " triangles using them are not rendered");
  if (dropped_degenerate)
    warn(what + ": " + std::to_string(dropped_degenerate) + " zero-area triangles are not rendered");
  if (num_triangles == 0) warn(what + ": has no faces; nothing to render");
  dropped_triangles_ += dropped_nonfinite + dropped_degenerate;
  m.indices.shrink_to_fit();
  m.materials.shrink_to_fit();
  if (num_vertices > 0) {  // object-space bounds: Generated texture coordinates
    m.bbox_lo = Vec3(kInf);
    m.bbox_hi = Vec3(-kInf);
    for (uint32_t i = 0; i < num_vertices; ++i)
      if (vertex_ok[i]) { m.bbox_lo = vmin(m.bbox_lo, m.positions[i]); m.bbox_hi = vmax(m.bbox_hi, m.positions[i]); }
    if (!(m.bbox_lo.x <= m.bbox_hi.x)) { m.bbox_lo = Vec3(0.0f); m.bbox_hi = Vec3(1.0f); }
  }
  return m;
}

void Scene::add_mesh_attribute(uint32_t mesh, const std::string &name, const std::string &kind, const float *data,
                               uint32_t num_components, uint32_t num_vertices) {
  if (mesh >= meshes_.size()) fail("attribute '" + name + "': no mesh " + std::to_string(mesh));
  Mesh &m = meshes_[mesh];
  const std::string what = "mesh '" + m.name + "' attribute '" + name + "'";
  if (name.empty()) fail(what + ": needs a name");
  if (!data) fail(what + ": 'data' is NULL");
  if (kind == "uv") {
    if (num_components != 2) fail(what + ": a UV map has 2 components, got " + std::to_string(num_components));
  } else if (kind == "color") {
    if (num_components != 3 && num_components != 4)
      fail(what + ": a colour has 3 or 4 components, got " + std::to_string(num_components));
  } else {
    fail(what + ": kind must be \"uv\" or \"color\", got '" + kind + "'");
  }
  if (num_vertices != m.num_vertices())
    fail(what + ": has " + std::to_string(num_vertices) + " values but the mesh has " + std::to_string(m.num_vertices()) +
         " vertices (attributes are per vertex)");
  MeshAttribute a;
  a.name = name;
  a.id = attribute_id(name);
  a.components = int(num_components);
  a.data.assign(data, data + size_t(num_vertices) * num_components);
  uint32_t bad = 0;
  for (float &v : a.data)
    if (!std::isfinite(v)) { v = 0; ++bad; }
  if (bad) warn(what + ": " + std::to_string(bad) + " values are not finite; set to 0");
  for (MeshAttribute &old : m.attributes)
    if (old.id == a.id) { old = std::move(a); return; }
  m.attributes.push_back(std::move(a));
}

static bool invertible(const Transform &t) { return std::fabs(t.det3()) > 1e-30f && t.is_finite(); }
// The largest entry of an instance's inverse transform that is rendered (see set_instance_transform).
constexpr float kMaxInverseEntry = 1e12f;

InstancePlacement InstancePlacement::of(const Transform &to_world) {
  InstancePlacement p;
  p.to_world = to_world;
  p.to_object = to_world.inverse();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.abs_linear.m[r][c] = std::fabs(to_world.m[r][c]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      float sum = 0;
      for (int k = 0; k < 3; ++k) sum += p.abs_linear.m[r][k] * std::fabs(p.to_object.m[k][c]);
      p.error_mixing.m[r][c] = sum;
    }
  return p;
}

uint32_t Scene::add_instance(uint32_t mesh, const Transform &to_world) {
  if (mesh >= meshes_.size())
    fail("instance of mesh " + std::to_string(mesh) + ": no such mesh (" + std::to_string(meshes_.size()) + " meshes)");
  if (!to_world.is_finite()) fail("instance of mesh '" + meshes_[mesh].name + "': transform is not finite");
  Instance inst;
  inst.mesh = mesh;
  inst.crypto_object = inst.crypto_asset = crypto_name(meshes_[mesh].name);
  instances_.push_back(inst);
  set_instance_transform(static_cast<uint32_t>(instances_.size() - 1), to_world);
  return static_cast<uint32_t>(instances_.size() - 1);
}

void Scene::set_instance_transform(uint32_t id, const Transform &to_world) {
  if (id >= instances_.size()) fail("instance " + std::to_string(id) + ": no such instance");
  if (!to_world.is_finite()) fail("instance of mesh '" + meshes_[instances_[id].mesh].name + "': transform is not finite");
  Instance &inst = instances_[id];
  inst.to_world = to_world;
  inst.enabled = invertible(to_world);
  bool in_range = true;
  if (inst.enabled) {
    inst.to_object = to_world.inverse();
    // A ray in the instance's object space must stay within Embree's range (1.8e18,
    // embree_accel.cpp): an inverse of 1e30 (a shear of 4.7e30, a translation of 1e30)
    // cannot be traced, and would narrow every other ray's range.
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) in_range = in_range && std::fabs(inst.to_object.m[r][c]) <= kMaxInverseEntry;
    inst.enabled = in_range;
  }
  if (inst.enabled) {
    static_cast<InstancePlacement &>(inst) = InstancePlacement::of(to_world);
  } else if (!in_range) {
    warn("instance of mesh '" + meshes_[inst.mesh].name +
         "': transform places it beyond the range rays reach (its inverse has an entry over 1e12: a scale "
         "below 1e-12 or a translation over 1e12); not rendered");
  } else warn("instance of mesh '" + meshes_[inst.mesh].name + "': transform has zero scale; not rendered");
  accel_.mark_instances_dirty();
  dirty_ = true;
}

uint32_t Scene::add_light(const std::string &name, Params &params) {
  UserLight made = make_light(params, &image_buffers_);
  for (const std::string &w : made.warnings) warn(w);
  user_lights_.push_back(made.light);
  user_light_emissions_.push_back(std::move(made.emission));
  user_light_names_.push_back(name);
  dirty_ = true;
  return static_cast<uint32_t>(user_lights_.size() - 1);
}

void Scene::set_world(Params &params) {
  MistSettings mist;
  if (const nlohmann::json *j = params.get_json("mist")) {  // World > Mist Pass
    Params m(j->dump(), params.what() + " mist");
    mist.start = m.get_float("start", mist.start);
    mist.depth = m.get_float("depth", mist.depth);
    const std::string falloff = m.get_string("falloff", "quadratic");
    m.check_all_used();
    if (!std::isfinite(mist.start) || !std::isfinite(mist.depth) || mist.start < 0 || mist.depth < 0)
      fail(m.what() + ": 'start' and 'depth' must be finite and not negative, got " + std::to_string(mist.start) +
           " and " + std::to_string(mist.depth));
    if (falloff == "quadratic") mist.falloff = MistSettings::Falloff::Quadratic;
    else if (falloff == "linear") mist.falloff = MistSettings::Falloff::Linear;
    else if (falloff == "inverse_quadratic") mist.falloff = MistSettings::Falloff::InverseQuadratic;
    else fail(m.what() + ": 'falloff' must be quadratic, linear or inverse_quadratic, got '" + falloff + "'");
  }
  if (const nlohmann::json *volume = params.get_json("volume")) {  // fog everywhere
    Params v(volume->dump(), params.what() + " volume");
    Medium m = Medium::from_params(v, "world");
    v.check_all_used();
    if (m.grid || !m.warnings.empty())
      fail(params.what() + ": the world volume is homogeneous; put a grid in a material's volume (a box around it)");
    if (m.is_emissive() && min_component(m.sigma_t) == 0)
      fail(params.what() + ": an emitting world volume needs density in every channel (it would glow infinitely)");
    if (world_medium_ >= 0) media_[world_medium_] = m;
    else { world_medium_ = int(media_.size()); media_.push_back(m); }
  } else {  // no fog (any more)
    drop_medium(world_medium_);
    world_medium_ = -1;
  }
  WorldLook look = parse_world_look(params);
  // Light Path > Is Camera Ray in the World's nodes (the add-on evaluates them for camera
  // rays and for the rest): "camera" is what camera rays see, the rest is what lights.
  std::optional<WorldLook> camera_look;
  if (const nlohmann::json *camera = params.get_json("camera")) {
    Params c(camera->dump(), params.what() + " camera");
    camera_look = parse_world_look(c);
    c.check_all_used();
  }
  // The World's AOV Outputs: a material's graph and AOV list (Material::aovs), shaded where a
  // camera sample's see-through chain leaves for the world (add_world_data_passes).
  std::optional<Material> world_aovs;
  if (const nlohmann::json *aovs = params.get_json("aovs")) {
    Params a(nlohmann::json{{"type", "diffuse"}, {"aovs", *aovs}}.dump(), params.what());
    world_aovs = Material::from_params(a, "world", &image_buffers_);
    for (const std::string &w : world_aovs->warnings) warn(w);
  }
  const uint32_t world_visibility = visibility::from_params(params);
  if (!(world_visibility & visibility::kShadow))
    warn(params.what() + ": 'visibility.shadow' is no world setting in Cycles 3.4 (the world has no shadow rays of "
                         "its own); ignored");
  params.check_all_used();
  world_visibility_ = world_visibility;
  mist_ = mist;
  world_ = std::move(look);
  camera_world_ = std::move(camera_look);
  world_aovs_ = std::move(world_aovs);
  dirty_ = true;
}

void Scene::add_world_data_passes(Vec3 dir, DataPassSample &data) const {
  // Cycles' background shading point: P the ray's direction (Generated and Object coordinates
  // too), N facing back along it; written for the samples that set no index yet, as surfaces.
  if (world_aovs_ && data.aovs.active() && !data.indices_done) {
    ShadingPoint sp;
    sp.p = sp.p_object = sp.generated = dir;
    sp.ns = sp.ng = -dir;
    world_aovs_->write_aovs(sp, data.aovs);
  }
  data.add_world();
}

// {"color", "strength", "environment" | "sky"}: the world's look (set_world's keys).
Scene::WorldLook Scene::parse_world_look(Params &params) const {
  // With an "environment" HDRI or a "sky", "color" tints it (default white); radiance = image x
  // color x strength.
  const nlohmann::json *env = params.get_json("environment");
  const nlohmann::json *sky = params.get_json("sky");
  if (env && sky) fail(params.what() + ": give 'environment' or 'sky', not both");
  Color c = params.get_vec3("color", env || sky ? Color(1.0f) : Color(0.05f));
  float s = params.get_float("strength", 1.0f);
  if (c.x < 0 || c.y < 0 || c.z < 0 || s < 0) fail(params.what() + ": colour and strength must not be negative");
  WorldLook look;
  if (env) {
    Params e(env->dump(), params.what() + " environment");
    std::string file = e.get_string("file", "");
    std::string colorspace = e.get_string("colorspace", "");
    Vec3 rotation = e.get_vec3("rotation", Vec3(0.0f));
    e.check_all_used();
    try {
      if (file.empty()) fail(params.what() + ": 'environment' needs a 'file'");
      look.map = EnvironmentMap::load(file, colorspace, rotation, c * s);
    } catch (const Error &err) {  // as Blender: a missing image renders magenta
      warn(params.what() + ": environment image '" + file + "' cannot be used (" + err.what() +
           "); rendering it magenta");
      look.map.reset();
      c = Color(1, 0, 1);
    }
  } else if (sky) {  // Blender's Nishita or Preetham sky, baked into an environment map (lights/sky_*.h)
    Params k(sky->dump(), params.what() + " sky");
    const int width = 2048;
    std::vector<float> pixels;
    if (k.get_string("type", "nishita") == "preetham") {
      pixels = PreethamSky(PreethamSky::from_params(k)).bake(width);
    } else {
      const NishitaSky::Settings settings = NishitaSky::from_params(k);
      pixels = NishitaSky(settings).bake(width);
    }
    const Vec3 rotation = k.get_vec3("rotation", Vec3(0.0f));
    k.check_all_used();
    look.map = std::make_shared<EnvironmentMap>(width, width / 2, std::move(pixels), rotation, c * s);
  }
  look.radiance = c * s;
  return look;
}

void Scene::set_camera(Params &params) {
  Camera c = Camera::from_params(params);
  params.check_all_used();
  // Opening or closing the shutter starts or stops the instances' motion.
  if (!has_camera_ || c.shutter_is_open() != camera_.shutter_is_open()) {
    accel_.mark_instances_dirty();
    dirty_ = true;
  }
  camera_ = std::move(c);
  world_to_camera_ = camera_.to_world.inverse();
  camera_generation_ = next_camera_generation();
  has_camera_ = true;
}

void Scene::commit() {
  if (!has_camera_) fail("scene: no camera was set (rdv_scene_set_camera)", RDV_ERROR_STATE);
  if (!dirty_) {
    find_camera_media();  // the camera may have moved into or out of a volume
    has_motion_ = camera_.moves() || accel_.has_motion();
    return;
  }
  find_motion();
  displace_meshes();
  accel_.build(meshes_, instances_, material_boundary_);
  // Bounding sphere of the instanced geometry: sizes the power of infinite lights. A
  // moving instance or deforming mesh lies between its steps (linear interpolation) all
  // the shutter long.
  Vec3 lo(kInf), hi(-kInf);
  auto grow = [&](const std::vector<Vec3> &positions, const Transform &to_world) {
    for (size_t i = 0; i + 1 < positions.size(); ++i) {  // not the padding element
      Vec3 p = to_world.point(positions[i]);
      lo = vmin(lo, p);
      hi = vmax(hi, p);
    }
  };
  for (const Instance &inst : instances_) {
    if (!inst.enabled) continue;
    const Mesh &m = meshes_[inst.mesh];
    grow(m.positions, inst.to_world);
    if (inst.moving)
      for (const Transform &step : inst.motion) grow(m.positions, step);
    if (m.deforming)  // each step under each of the instance's transforms (a bound for the lights' power)
      for (const std::vector<Vec3> &positions : m.position_steps) {
        grow(positions, inst.to_world);
        if (inst.moving)
          for (const Transform &step : inst.motion) grow(positions, step);
      }
  }
  if (lo.x <= hi.x) {
    bounding_center_ = (lo + hi) * 0.5f;
    bounding_radius_ = std::max(length(hi - lo) * 0.5f, 1e-6f);
  }
  build_lights();
  has_transparency_ = has_holdouts_ = has_transparent_non_layers_ = false;
  for (const Material &m : materials_) {
    has_transparency_ = has_transparency_ || m.transparent;
    has_holdouts_ = has_holdouts_ || m.holdout;
    has_transparent_non_layers_ = has_transparent_non_layers_ || (m.transparent && (m.emits() || m.holdout));
  }
  bool special_objects = false;
  for (const Instance &inst : instances_) {
    has_holdouts_ = has_holdouts_ || (inst.enabled && inst.holdout);
    special_objects = special_objects || (inst.enabled && (inst.holdout || inst.shadow_catcher));
  }
  has_transparent_non_layers_ = has_transparent_non_layers_ || (has_transparency_ && special_objects);
  find_ray_visibility();
  has_heterogeneous_media_ = false;
  for (const Medium &m : media_) has_heterogeneous_media_ = has_heterogeneous_media_ || m.is_heterogeneous();
  find_camera_media();
  find_light_media();
  has_motion_ = camera_.moves() || accel_.has_motion();
  dirty_ = false;
}

void Scene::find_ray_visibility() {
  using namespace visibility;
  has_ray_visibility_ = has_mixed_visibility_ = false;
  ray_visibility_object_.clear();
  mixed_visibility_object_.clear();
  auto hidden = [&](const std::string &what) {
    if (!has_ray_visibility_) ray_visibility_object_ = what;
    has_ray_visibility_ = true;
  };
  auto mixed = [&](const std::string &what) {
    hidden(what);
    if (!has_mixed_visibility_) mixed_visibility_object_ = what;
    has_mixed_visibility_ = true;
  };
  for (uint32_t i = 0; i < instances_.size(); ++i) {
    const Instance &inst = instances_[i];
    if (!inst.enabled || inst.visibility == kAll) continue;
    const std::string what = "object '" + meshes_[inst.mesh].name + "' (instance " + std::to_string(i) + ")";
    if (is_mixed(inst.visibility)) mixed(what);
    else hidden(what);
  }
  for (uint32_t i = 0; i < user_lights_.size(); ++i) {
    const uint32_t v = user_lights_[i].visibility;
    const std::string what = "light '" + user_light_names_[i] + "'";
    if (!(v & kShadow)) mixed(what + " (casts no shadows)");
    else if ((v & kNonCamera) != kNonCamera) hidden(what);
  }
  if (world_visibility_ != kAll) hidden("the world");
  if (camera_world_) hidden("the world (a look of its own for camera rays: Light Path > Is Camera Ray)");
}

// Which media the camera starts in.
void Scene::find_camera_media() {
  camera_media_.clear();
  if (media_.empty()) return;
  camera_media_ = media_along(camera_.position(), normalize(Vec3(0.3141f, 0.2718f, 0.9101f)));
}

std::vector<int> Scene::media_along(Vec3 o, Vec3 d) const {
  std::vector<int> exited, entered;
  Ray ray{o, d, kInf};
  for (int guard = 0; guard < 256; ++guard) {
    SurfaceHit hit;
    CoincidentBoundary boundary;
    if (!intersect_media(ray, hit, boundary)) break;
    auto pass = [&](uint32_t material, Vec3 ng) {
      int m = material_interior_[material];
      if (m < 0) return;
      if (dot(ray.d, ng) < 0) entered.push_back(m);
      else if (!entered.empty() && entered.back() == m) entered.pop_back();
      else exited.push_back(m);
    };
    pass(hit.material, hit.ng);
    if (boundary.material >= 0) pass(uint32_t(boundary.material), boundary.ng);
    ray.o = spawn_origin(hit.p, hit.ng, hit.error, ray.d);
  }
  return {exited.rbegin(), exited.rend()};  // outermost first, innermost last
}

void Scene::build_lights() {
  lights_ = user_lights_;
  emissive_triangles_ = 0;
  for (Mesh &m : meshes_) {
    m.emissive_rank.assign(m.num_triangles(), Mesh::kNotEmissive);
    m.num_emissive = 0;
    for (uint32_t t = 0; t < m.num_triangles(); ++t)
      if (materials_[m.materials[t]].emits()) m.emissive_rank[t] = m.num_emissive++;
  }
  // Whether each material's emission depends on the distance its light travels (its graph
  // read once, not per triangle).
  std::vector<int8_t> falloff(materials_.size(), -1);
  auto by_distance = [&](uint32_t material) {
    if (falloff[material] < 0) falloff[material] = materials_[material].emission_by_distance();
    return falloff[material] > 0;
  };
  for (uint32_t i = 0; i < instances_.size(); ++i) {
    Instance &inst = instances_[i];
    const Mesh &m = meshes_[inst.mesh];
    inst.light_base = static_cast<uint32_t>(lights_.size());
    if (!inst.enabled || m.num_emissive == 0) continue;
    for (uint32_t t = 0; t < m.num_triangles(); ++t) {
      if (m.emissive_rank[t] == Mesh::kNotEmissive) continue;
      Vec3 a = inst.to_world.point(m.positions[m.indices[3 * t]]);
      Vec3 b = inst.to_world.point(m.positions[m.indices[3 * t + 1]]);
      Vec3 c = inst.to_world.point(m.positions[m.indices[3 * t + 2]]);
      const Material &mat = materials_[m.materials[t]];
      Light l = make_triangle_light(a, b, c, mat.emission_average);
      // Points sampled on it are as precise as hits on it (the largest world coordinates).
      Vec3 object_error = triangle_point_error(m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]],
                                               m.positions[m.indices[3 * t + 2]]);
      l.error = transformed_point_error(object_error, vmax(vabs(a), vmax(vabs(b), vabs(c))), inst.abs_linear,
                                        inst.error_mixing);
      l.instance = i;
      l.prim = t;
      l.visibility = inst.visibility;
      l.shadow_catcher = inst.shadow_catcher;
      l.textured = !mat.textured_emission.empty();
      l.by_distance = l.textured && by_distance(m.materials[t]);
      l.moves = inst.moving || m.deforming;  // motion blur: light_now places it
      lights_.push_back(l);
      ++emissive_triangles_;
    }
  }
  build_volume_lights();
  // The world (as Cycles: no world shadow setting); with a camera look, camera rays see that
  // one and every other ray this one.
  const uint32_t world_rays = world_visibility_ | visibility::kShadow;
  add_world_light(world_, camera_world_ ? world_rays & ~visibility::kCamera : world_rays);
  if (camera_world_) add_world_light(*camera_world_, world_rays & visibility::kCamera);
  for (Light &l : lights_) {
    // The world lights a shadow catcher's pass; so does emission in media, which the
    // catcher pass's paths meet anyway (Session warns).
    if (l.type == LightType::Background || l.type == LightType::Volume) l.shadow_catcher = true;
  }
  hittable_lights_.clear();
  infinite_lights_.clear();
  std::vector<float> power;
  for (uint32_t i = 0; i < lights_.size(); ++i) {
    Light &l = lights_[i];
    compute_light_power(l, bounding_radius_);
    // A light only camera rays see (a world's or an object's look for the camera, Light Path)
    // lights nothing: next-event estimation and light subpaths never choose it (its hits keep
    // their full weight). A light no ray sees keeps its power: it is chosen and gives nothing,
    // as before (tests compare renders with a lamp hidden so, sample for sample).
    power.push_back(l.visibility == visibility::kCamera ? 0.0f : l.power);
    if (l.is_infinite()) infinite_lights_.push_back(i);
    else if (l.type != LightType::Triangle && l.type != LightType::Volume && !l.is_delta()) hittable_lights_.push_back(i);
  }
  light_distribution_ = Distribution1D(power);
  if (lights_.empty()) warn("scene: there are no lights and no emissive materials; the image will be black");
}

// The world as a light seen by the given kinds of ray (none, or black: no light).
void Scene::add_world_light(const WorldLook &look, uint32_t rays) {
  if (!rays || look.is_black()) return;
  Light l = look.map ? make_environment_light(look.map.get()) : make_background_light(look.radiance);
  l.visibility = rays;
  lights_.push_back(l);
}

// Every emissive medium inside meshes becomes a volume light over the instances that
// hold it (the world's fog is unbounded: camera paths gather it alone).
void Scene::build_volume_lights() {
  volume_emitters_.clear();
  for (int mi = 0; mi < int(media_.size()); ++mi) {
    Medium &medium = media_[mi];
    medium.light = -1;
    medium.emission_step = 0;
    if (mi == world_medium_ || !medium.is_emissive()) continue;
    std::vector<VolumeEmitter::Region> regions;
    // The kinds of ray that see the light: those that see every object holding the medium
    // (a ray enters the medium only through a boundary it sees).
    uint32_t visibility = visibility::kAll;
    for (const Instance &inst : instances_) {
      const Mesh &mesh = meshes_[inst.mesh];
      if (!inst.enabled) continue;
      Vec3 lo(kInf), hi(-kInf);
      double volume = 0;  // divergence theorem over the triangles bounding the medium
      for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
        if (material_interior_[mesh.materials[t]] != mi) continue;
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) {
          p[k] = inst.to_world.point(mesh.positions[mesh.indices[3 * t + k]]);
          lo = vmin(lo, p[k]);
          hi = vmax(hi, p[k]);
        }
        volume += double(dot(p[0], cross(p[1], p[2]))) / 6.0;
      }
      if (!(hi.x >= lo.x)) continue;
      Vec3 size = hi - lo;
      float box = size.x * size.y * size.z;
      float enclosed = float(std::fabs(volume));
      regions.push_back({lo, hi, enclosed > 0 && enclosed <= box * 1.001f ? enclosed : box});
      visibility &= inst.visibility;
    }
    if (regions.empty()) continue;
    auto emitter = std::make_unique<VolumeEmitter>(medium, mi, regions);
    if (emitter->empty()) continue;
    medium.light = int(lights_.size());
    medium.light_lo = emitter->bounds_lo();
    medium.light_hi = emitter->bounds_hi();
    // Camera paths gather the emission at points this far apart: a voxel of the grid
    // that shapes it, else 1/64 of the light's extent.
    float extent = length(medium.light_hi - medium.light_lo);
    float step = extent / 64;
    if (const DensityGrid *g = emitter->lattice()) {
      const Transform &m = g->grid_to_world();
      step = std::min({length(m.column(0)), length(m.column(1)), length(m.column(2))});
    }
    medium.emission_step = std::max(step, extent / 4096);
    lights_.push_back(make_volume_light(emitter.get()));
    lights_.back().visibility = visibility;
    volume_emitters_.push_back(std::move(emitter));
  }
}

bool Scene::intersect(const Ray &ray, SurfaceHit &hit) const {
  RawHit raw;
  if (!accel_.intersect(ray, raw)) return false;
  surface_at(raw.instance, raw.prim, raw.u, raw.v, hit);
  hit.t = raw.t;
  return true;
}

void Scene::surface_at(uint32_t instance, uint32_t prim, float b1, float b2, SurfaceHit &hit) const {
  const Instance &inst = instances_[instance];
  const Mesh &m = meshes_[inst.mesh];
  const uint32_t *tri = &m.indices[3 * prim];
  float b0 = 1.0f - b1 - b2;
  Vec3 p[3];
  triangle_now(m, tri, p);  // a deforming mesh's triangle where Embree met it
  const Vec3 p0 = p[0], p1 = p[1], p2 = p[2];
  InstancePlacement moved;
  const InstancePlacement &at = inst.moving ? (moved = placement_now(inst)) : placement(inst);
  // Position from barycentrics in object space: more precise than o + t d.
  Vec3 p_object = p0 * b0 + p1 * b1 + p2 * b2;
  hit.p = at.to_world.point(p_object);
  Vec3 object_error = triangle_point_error(p0, p1, p2);
  // Embree blends a deforming mesh's vertex steps in its own rounding (perhaps with
  // fused multiply-adds): its vertices differ from ours by an ulp or two.
  if (m.deforming) object_error += vmax(vabs(p0), vmax(vabs(p1), vabs(p2))) * (2 * kUlp);
  hit.error = transformed_point_error(object_error, hit.p, at.abs_linear, at.error_mixing);
  // The same for a moving instance's steps: the matrices differ from ours by an ulp or
  // two of their entries.
  if (inst.moving) hit.error += (at.abs_linear.vector(vabs(p_object)) + vabs(at.to_world.column(3))) * (2 * kUlp);
  Vec3 ng = normalize(at.to_object.normal_by_inverse(cross(p1 - p0, p2 - p0)));
  Vec3 ns = ng;
  if (!m.normals.empty()) {
    Vec3 vn[3];
    normals_now(m, tri, vn);
    Vec3 n = vn[0] * b0 + vn[1] * b1 + vn[2] * b2;
    float len2 = length_squared(n);
    if (len2 > 1e-12f) {
      ns = normalize(at.to_object.normal_by_inverse(n));
      if (dot(ns, ng) < 0) ng = -ng;  // the vertex normals say which side is the front
    }
  }
  hit.ng = ng;
  hit.ns = ns;
  hit.uv = m.uvs.empty() ? Vec2(b1, b2)
                         : m.uvs[tri[0]] * b0 + m.uvs[tri[1]] * b1 + m.uvs[tri[2]] * b2;
  hit.b1 = b1;
  hit.b2 = b2;
  hit.instance = instance;
  hit.prim = prim;
  hit.material = m.materials[prim];
}

Color Scene::triangle_emission(const Light &l, Vec3 p, float distance) const {
  // Barycentrics of p: p = p0 + b1 edge_u + b2 edge_v (least squares).
  Vec3 d = p - l.p0;
  float uu = dot(l.edge_u, l.edge_u), uv = dot(l.edge_u, l.edge_v), vv = dot(l.edge_v, l.edge_v);
  float du = dot(d, l.edge_u), dv = dot(d, l.edge_v), det = uu * vv - uv * uv;
  if (!(det > 0)) return l.radiance;
  float b1 = clampf((vv * du - uv * dv) / det, 0.0f, 1.0f), b2 = clampf((uu * dv - uv * du) / det, 0.0f, 1.0f - b1);
  SurfaceHit hit;
  surface_at(l.instance, l.prim, b1, b2, hit);
  ShadingPoint sp = shading_point(hit);
  sp.ray_length = distance;
  return materials_[hit.material].emission_at(sp);
}

Color Scene::light_radiance(const Light &l, Vec3 p, Vec3 n, Vec3 w, Vec3 receiver) const {
  if (is_sphere_lamp(l)) return sphere_lamp_radiance(l, n, w, sphere_lamp_distance(l, receiver));
  const float distance = length(receiver - p);
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot:
    case LightType::Area: return lamp_radiance(l, p, w, distance);
    case LightType::Triangle: return l.textured ? triangle_emission(l, p, distance) : l.radiance;
    // Radiance per unit length at the point (isotropic).
    case LightType::Volume: return l.volume->medium().emission_at(p);
    default: return Color(0.0f);  // lights at infinity: by the direction alone (infinite_light_radiance)
  }
}

const Light &Scene::light_now(uint32_t light, Light &storage) const {
  const Light &l = lights_[light];
  if (!l.moves) return l;
  const Instance &inst = instances_[l.instance];
  const Mesh &m = meshes_[inst.mesh];
  const uint32_t *tri = &m.indices[3 * l.prim];
  Vec3 p[3];
  triangle_now(m, tri, p);
  InstancePlacement moved;
  const InstancePlacement &at = inst.moving ? (moved = placement_now(inst)) : placement(inst);
  const Vec3 a = at.to_world.point(p[0]), b = at.to_world.point(p[1]), c = at.to_world.point(p[2]);
  storage = l;
  const Vec3 n = cross(b - a, c - a);
  const float len = length(n);
  if (!(len > 0) || !std::isfinite(len)) {  // collapsed at this time: it emits nothing now
    storage.inv_area = 0;
    storage.radiance = Color(0.0f);
    return storage;
  }
  storage.p0 = a;
  storage.edge_u = b - a;
  storage.edge_v = c - a;
  storage.axis = n / len;
  storage.inv_area = 2.0f / len;
  // As surface_at's bound for a hit on it at this time (Embree's blends differ by an ulp or two).
  Vec3 object_error = triangle_point_error(p[0], p[1], p[2]);
  const Vec3 largest = vmax(vabs(p[0]), vmax(vabs(p[1]), vabs(p[2])));
  if (m.deforming) object_error += largest * (2 * kUlp);
  storage.error = transformed_point_error(object_error, vmax(vabs(a), vmax(vabs(b), vabs(c))), at.abs_linear,
                                          at.error_mixing);
  if (inst.moving) storage.error += (at.abs_linear.vector(largest) + vabs(at.to_world.column(3))) * (2 * kUlp);
  return storage;
}

bool Scene::sample_light(uint32_t light, Vec3 ref, Vec2 u, Vec3 u_volume, LightSample &out) const {
  Light moved;
  const Light &l = light_now(light, moved);
  if (l.moves && !(l.inv_area > 0)) return false;  // a moving triangle collapsed at this time
  if (!rdv::sample_light(l, ref, u, u_volume, out)) return false;
  if (l.textured) out.L = triangle_emission(l, out.p, out.dist);
  return true;
}

bool Scene::sample_emission(uint32_t light, Vec2 u_pos, Vec2 u_dir, Vec3 u_volume, EmissionSample &out) const {
  Light moved;
  const Light &l = light_now(light, moved);
  if (l.moves && !(l.inv_area > 0)) return false;  // a moving triangle collapsed at this time
  if (!rdv::sample_emission(l, u_pos, u_dir, u_volume, bounding_center_, bounding_radius_, out)) return false;
  if (l.textured) out.Le = triangle_emission(l, out.ray.o, 1.0f);  // by_distance: at 1 (EmissionSample)
  return true;
}

// The footprint of a ray cone `width` wide arriving along dir: one axis across the
// plane of incidence (width long), the other along it, stretched by 1 / cos at grazing
// angles; both expressed in (u, v) by least squares on dp/du, dp/dv (pbrt's
// SurfaceInteraction::ComputeDifferentials).
static void set_footprint(ShadingPoint &sp, Vec3 dir, float width) {
  Vec3 n = sp.ng;
  float cos_i = dot(dir, n);
  Vec3 a = cross(dir, n);
  float len = length(a);
  a = len > 1e-6f ? a / len : Frame(n).s;
  Vec3 b = cross(a, dir);
  if (std::fabs(cos_i) > 1e-6f) b = b - dir * (dot(b, n) / cos_i);  // onto the surface along dir
  float uu = dot(sp.dpdu, sp.dpdu), uv = dot(sp.dpdu, sp.dpdv), vv = dot(sp.dpdv, sp.dpdv);
  float det = uu * vv - uv * uv;
  if (!(std::fabs(det) > 1e-20f)) return;
  auto to_uv = [&](Vec3 d) {
    float pu = dot(sp.dpdu, d), pv = dot(sp.dpdv, d);
    Vec2 r{(vv * pu - uv * pv) / det, (uu * pv - uv * pu) / det};
    return std::isfinite(r.x) && std::isfinite(r.y) ? r : Vec2(0.0f, 0.0f);
  };
  sp.dx = to_uv(a * width);
  sp.dy = to_uv(b * width);
}

bool Scene::texture_ray_occluded(const ShadingPoint &sp, Vec3 d, float tmax, bool only_local) const {
  Ray ray{spawn_origin(sp.p, sp.ng, sp.error, d), d, tmax, visibility::kShadow};  // what casts shadows
  if (!only_local) return accel_.occluded(ray.o, ray.d, ray.tmax, ray.mask);
  RawHit raw;  // Only Local: the point's own object
  return accel_.intersect_mesh(instances_[sp.instance].mesh, to_object_now(sp.instance, ray), raw);
}

int Scene::texture_ray_local_hits(const ShadingPoint &sp, Vec3 o, Vec3 d, float tmax, LocalHit *hits, int max_hits,
                                  uint32_t seed) const {
  // Every surface of the object along the segment, one after another: its own BVH, as
  // Cycles' local intersection reads it (a copy of the object for other kinds of ray, or
  // another object's face on the same spot, must not hide one).
  const uint32_t mesh = instances_[sp.instance].mesh;
  Ray ray = to_object_now(sp.instance, Ray{o, d, tmax});
  Pcg32 rng(seed);
  int found = 0;
  for (int steps = 0; steps < 64; ++steps) {
    RawHit raw;
    if (!accel_.intersect_mesh(mesh, ray, raw)) break;
    // Reservoir sampling: each of the `found` hits is kept with probability max_hits / found.
    const int slot = found < max_hits ? found : int(rng.next_u32() % uint32_t(found + 1));
    if (slot < max_hits) {
      raw.instance = sp.instance;
      SurfaceHit hit;
      surface_at(raw, hit);
      hits[slot] = {hit.p, hit.ng, hit.ns};
    }
    ++found;
    // Just past the hit, to look for what lies beyond it.
    const Vec3 p = ray.o + ray.d * raw.t;
    const float step = std::max(raw.t * 1e-4f, (std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z)) * 1e-6f);
    ray.o = p + ray.d * step;
    ray.tmax -= raw.t + step;
    if (!(ray.tmax > 0)) break;
  }
  return found;
}

// A world-space ray in an instance's object space at the sample's shutter time; its t
// parameters are the world ray's (the direction is carried, not normalised).
Ray Scene::to_object_now(uint32_t instance, const Ray &world) const {
  const Instance &inst = instances_[instance];
  InstancePlacement moved;
  const InstancePlacement &at = inst.moving ? (moved = placement_now(inst)) : placement(inst);
  return Ray{at.to_object.point(world.o), at.to_object.vector(world.d), world.tmax, world.mask};
}

ShadingPoint Scene::shading_point(const SurfaceHit &hit, Vec3 dir, float width) const {
  ShadingPoint sp;
  const Instance &inst = instances_[hit.instance];
  const Mesh &m = meshes_[inst.mesh];
  const uint32_t *tri = &m.indices[3 * hit.prim];
  sp.p = hit.p;
  sp.ng = hit.ng;
  sp.ns = hit.ns;
  sp.uv = hit.uv;
  sp.mesh = &m;
  sp.rays = this;
  sp.error = hit.error;
  sp.instance = hit.instance;
  sp.backfacing = dot(dir, hit.ng) > 0;
  sp.v[0] = tri[0]; sp.v[1] = tri[1]; sp.v[2] = tri[2];
  sp.b[0] = 1.0f - hit.b1 - hit.b2; sp.b[1] = hit.b1; sp.b[2] = hit.b2;
  Vec3 p[3];
  triangle_now(m, tri, p);
  const Vec3 p0 = p[0], p1 = p[1], p2 = p[2];
  sp.p_object = p0 * sp.b[0] + p1 * sp.b[1] + p2 * sp.b[2];
  // Blender's texture space: the bounding box to 0..1; a flat axis counts as 2 units
  // wide around the box's middle (BKE_mesh_texspace_calc), so it maps to 0.5.
  // A displaced mesh keeps the texture space of its positions as given (Blender's, which
  // Cycles interpolates as the Generated attribute).
  const Vec3 p_texture = m.given_positions.empty() ? sp.p_object
                                                   : m.given_positions[tri[0]] * sp.b[0] +
                                                         m.given_positions[tri[1]] * sp.b[1] +
                                                         m.given_positions[tri[2]] * sp.b[2];
  Vec3 extent = m.bbox_hi - m.bbox_lo;
  for (int i = 0; i < 3; ++i) {
    sp.generated_scale[i] = extent[i] > 0 ? 1.0f / extent[i] : 0.5f;
    sp.generated[i] = (p_texture[i] - m.bbox_lo[i]) * sp.generated_scale[i] + (extent[i] > 0 ? 0.0f : 0.5f);
  }
  InstancePlacement moved;
  const InstancePlacement &at = inst.moving ? (moved = placement_now(inst)) : placement(inst);
  std::copy(&at.to_world.m[0][0], &at.to_world.m[0][0] + 12, sp.object_to_world);
  sp.has_object_to_world = true;
  sp.object_random = inst.random;
  sp.object_color = inst.color;
  sp.object_alpha = inst.alpha;
  sp.object_attributes = inst.attributes.data();
  sp.num_object_attributes = uint32_t(inst.attributes.size());
  sp.object_index = inst.pass_index;
  sp.material_index = materials_[hit.material].pass_index;
  // dp/du, dp/dv from the triangle's UVs (pbrt's triangle derivatives). Displacement and Bump:
  // over the triangle as given, where Cycles takes its bump's differences (the moved surface's
  // slope is the displacement's, not to be counted twice).
  const bool as_given = !m.given_positions.empty() && materials_[hit.material].displacement_keeps_normals;
  Vec3 e1 = p1 - p0, e2 = p2 - p0;
  if (as_given) {
    e1 = m.given_positions[tri[1]] - m.given_positions[tri[0]];
    e2 = m.given_positions[tri[2]] - m.given_positions[tri[0]];
  }
  bool frame = false;
  if (!m.uvs.empty()) {
    Vec2 t0 = m.uvs[tri[0]], t1 = m.uvs[tri[1]], t2 = m.uvs[tri[2]];
    Vec2 d1 = t1 - t0, d2 = t2 - t0;
    float det = d1.x * d2.y - d1.y * d2.x;
    if (std::fabs(det) > 1e-12f) {
      float inv = 1.0f / det;
      sp.dpdu_object = (e1 * d2.y - e2 * d1.y) * inv;
      sp.dpdv_object = (e2 * d1.x - e1 * d2.x) * inv;
      frame = is_finite(sp.dpdu_object) && is_finite(sp.dpdv_object);
    }
  }
  if (!frame) {  // any frame in the triangle's plane, in object units
    Vec3 n = cross(e1, e2);
    float len = length(n);
    Frame f(len > 0 ? n / len : Vec3(0, 0, 1));
    sp.dpdu_object = f.s;
    sp.dpdv_object = f.t;
  }
  sp.has_uv_frame = frame;
  sp.dpdu = at.to_world.vector(sp.dpdu_object);
  sp.dpdv = at.to_world.vector(sp.dpdv_object);
  if (width > 0) set_footprint(sp, dir, width);
  return sp;
}

void Scene::add_data_passes(const SurfaceHit &hit, Color beta, float alpha_threshold, DataPassSample &data) const {
  const Material &m = materials_[hit.material];
  Color alpha(1.0f);  // Cycles' surface alpha: 1 - the Transparent closures' weight
  // Shader AOVs: every surface of the chain until the one that sets the indices, as Cycles.
  const bool aovs = data.aovs.active() && !data.indices_done && !m.aovs.empty();
  if (m.transparent || aovs) {
    const ShadingPoint sp = shading_point(hit);
    if (m.transparent) alpha = vmax(Color(1.0f) - m.shadow_transmission(sp), Color(0.0f));
    if (aovs) m.write_aovs(sp, data.aovs);
  }
  // Cycles' camera_distance: from the camera's position (orthographic: along its axis), at
  // the sample's shutter time.
  const Camera &camera = camera_now();
  const Vec3 w = hit.p - camera.position();
  const float distance = camera.type == Camera::Type::Orthographic ? std::fabs(dot(w, camera.forward())) : length(w);
  const Instance &inst = instances_[hit.instance];
  data.add_surface(mist_, alpha_threshold, distance, beta * alpha, average(alpha), inst.pass_index, m.pass_index);
  // Cryptomatte: every surface of the chain, as Cycles' average(throughput) x average(alpha).
  if (data.crypto.active())
    data.crypto.add(crypto_ids_[inst.crypto_object], m.crypto_id, crypto_ids_[inst.crypto_asset],
                    average(beta) * average(alpha));
}

uint32_t Scene::crypto_name(const std::string &name) {
  auto [it, added] = crypto_name_index_.emplace(name, uint32_t(crypto_names_.size()));
  if (added) {
    crypto_names_.push_back(name);
    crypto_ids_.push_back(cryptomatte::id_of(name));
  }
  return it->second;
}

CryptoManifests Scene::crypto_manifests() const {
  CryptoManifests out;
  for (const Instance &inst : instances_) {
    if (!inst.enabled) continue;
    out.add(Cryptomatte::Object, crypto_names_[inst.crypto_object]);
    out.add(Cryptomatte::Asset, crypto_names_[inst.crypto_asset]);
  }
  for (const Material &m : materials_) out.add(Cryptomatte::Material, m.crypto_name);
  return out;
}

std::string Scene::shadow_catcher_object() const {
  for (uint32_t i = 0; i < instances_.size(); ++i)
    if (instances_[i].enabled && instances_[i].shadow_catcher) return instance_name(i);
  return "";
}

float Scene::holdout_weight(const SurfaceHit &hit) const {
  if (instances_[hit.instance].holdout) return 1;
  const Material &m = materials_[hit.material];
  return m.holdout ? m.holdout_at(shading_point(hit)) : 0.0f;
}

std::string Scene::instance_description(uint32_t id) const {
  if (id >= instances_.size()) return "instance " + std::to_string(id);
  return "object '" + meshes_[instances_[id].mesh].name + "' (instance " + std::to_string(id) + ")";
}

void Scene::set_instance_params(uint32_t id, Params &params) {
  if (id >= instances_.size()) fail("instance " + std::to_string(id) + ": no such instance");
  Instance &inst = instances_[id];
  const bool holdout = params.get_bool("holdout", false);
  const bool shadow_catcher = params.get_bool("shadow_catcher", false);
  const bool look_copy = params.get_bool("look_copy", false);
  const std::string object = instance_description(id);
  const uint32_t v = visibility::parse(params.get_json("visibility"), object);
  const int pass_index = pass_index_of(params, object);
  // Object Info's Random: Blender's random_id (an unsigned 32-bit number) as Cycles maps it.
  uint32_t random_id = 0;
  if (const nlohmann::json *r = params.get_json("random_id")) {
    if (!r->is_number_integer() || r->get<int64_t>() < 0 || r->get<int64_t>() > int64_t(0xFFFFFFFFu))
      fail(object + ": 'random_id' must be a whole number from 0 to 4294967295", RDV_ERROR_INVALID_ARGUMENT);
    random_id = uint32_t(r->get<int64_t>());
  }
  // Cryptomatte's names: {"object": name, "asset": name} (each the mesh's name if not given).
  std::string crypto_object = meshes_[inst.mesh].name, crypto_asset = crypto_object;
  if (const nlohmann::json *c = params.get_json("cryptomatte")) {
    bool ok = c->is_object();
    for (auto it = ok ? c->begin() : c->end(); ok && it != c->end(); ++it)
      ok = (it.key() == "object" || it.key() == "asset") && it->is_string();
    if (!ok)
      fail(object + ": 'cryptomatte' must be {\"object\": name, \"asset\": name}, got " + c->dump(),
           RDV_ERROR_INVALID_ARGUMENT);
    crypto_object = c->value("object", crypto_object);
    crypto_asset = c->value("asset", crypto_asset);
  }
  const std::vector<float> color = params.get_floats("color", 4, {1, 1, 1, 1});
  // Attribute nodes of type Object / Instancer: {"name": number or [up to 4 numbers]}.
  std::vector<ObjectAttribute> attributes;
  for (const char *key : {"object_attributes", "instancer_attributes"}) {
    const nlohmann::json *j = params.get_json(key);
    if (!j) continue;
    if (!j->is_object()) fail(object + ": '" + key + "' must be an object of names and values", RDV_ERROR_INVALID_ARGUMENT);
    const std::string prefix = key[0] == 'i' ? kInstancerPrefix : "";
    for (auto it = j->begin(); it != j->end(); ++it) {
      ObjectAttribute a{attribute_id(prefix + it.key()), {0, 0, 0, 1}};
      const nlohmann::json &v = it.value();
      bool ok = v.is_number() || (v.is_array() && !v.empty() && v.size() <= 4);
      if (v.is_number()) a.value[0] = a.value[1] = a.value[2] = v.get<float>();
      for (size_t c = 0; ok && v.is_array() && c < v.size(); ++c)
        if ((ok = v[c].is_number())) a.value[c] = v[c].get<float>();
      for (float f : a.value) ok = ok && std::isfinite(f);
      if (!ok)
        fail(object + ": attribute '" + it.key() + "' must be a finite number or 1 to 4 of them",
             RDV_ERROR_INVALID_ARGUMENT);
      attributes.push_back(a);
    }
  }
  params.check_all_used();
  inst.attributes = std::move(attributes);
  inst.holdout = holdout;
  inst.pass_index = float(pass_index);
  inst.crypto_object = crypto_name(crypto_object);
  inst.crypto_asset = crypto_name(crypto_asset);
  inst.random = float(random_id) * (1.0f / float(0xFFFFFFFFu));
  inst.color = Color(color[0], color[1], color[2]);
  inst.alpha = color[3];
  // Instance masks (visibility, shadow catchers) live in the top BVH.
  if (v != inst.visibility || shadow_catcher != inst.shadow_catcher) accel_.mark_instances_dirty();
  inst.visibility = v;
  inst.shadow_catcher = shadow_catcher;
  inst.look_copy = look_copy;
  dirty_ = true;
}

Bsdf Scene::bsdf(const SurfaceHit &hit, Vec3 wo, float width, Color *Le) const {
  const Material &m = materials_[hit.material];
  if (m.is_constant() && (!Le || m.textured_emission.empty())) {
    if (Le) *Le = m.emission;
    return m.make_bsdf(hit.ng, hit.ns, wo);
  }
  ShadingPoint sp = shading_point(hit, -wo, width);
  sp.ray_length = hit.t;  // the light it emits travels the ray back (Light Falloff)
  if (Le) *Le = m.emission_at(sp);
  return m.make_bsdf(sp, wo);
}

std::string Scene::summary_json() const {
  nlohmann::json j;
  uint64_t stored = 0, instanced = 0;
  size_t mesh_bytes = 0;
  for (const Mesh &m : meshes_) { stored += m.num_triangles(); mesh_bytes += m.memory_bytes(); }
  uint32_t enabled = 0;
  for (const Instance &inst : instances_)
    if (inst.enabled) { ++enabled; instanced += meshes_[inst.mesh].num_triangles(); }
  std::map<std::string, int> light_types;
  for (const Light &l : user_lights_) {
    static const char *names[] = {"point", "spot", "sun", "area", "triangle", "background"};
    light_types[names[static_cast<int>(l.type)]]++;
  }
  std::map<std::string, int> material_types;
  for (const Material &m : materials_) material_types[m.type_name()]++;
  j["meshes"] = meshes_.size();
  j["triangles_stored"] = stored;
  j["instances"] = enabled;
  j["triangles_instanced"] = instanced;
  j["triangles_dropped"] = dropped_triangles_;
  j["lights"] = light_types;
  j["emissive_triangles"] = emissive_triangles_;
  if (camera_.shutter_is_open()) {  // motion blur (scene/motion.h)
    uint32_t moving = 0;
    for (const Instance &inst : instances_) moving += inst.enabled && inst.moving;
    uint32_t deforming = 0;
    for (const Mesh &m : meshes_) deforming += m.deforming;
    j["motion_blur"] = {{"shutter", {camera_.shutter_open, camera_.shutter_close}},
                        {"moving_instances", moving},
                        {"deforming_meshes", deforming},
                        {"camera_moves", camera_.moves()}};
  }
  j["world"] = world_.map ? "environment" : world_.is_black() ? "none" : "constant";
  if (camera_world_) j["camera_world"] = camera_world_->map ? "environment" : camera_world_->is_black() ? "none" : "constant";
  j["materials"] = material_types;
  int textures = 0;
  for (const Material &mat : materials_) textures += mat.graph.num_images();
  j["textures"] = textures;
  if (media_.empty()) j["media"] = "none";
  else {
    size_t grids = 0, grid_bytes = 0;
    for (const Medium &m : media_) {
      if (m.grid) ++grids;
      for (const auto *g : {m.grid.get(), m.emission_grid.get(), m.temperature_grid.get()})
        if (g) grid_bytes += g->memory_bytes();
    }
    j["media"] = {{"homogeneous", media_.size() - grids}, {"grid", grids}, {"grid_bytes", grid_bytes},
                  {"world", world_medium_ >= 0}, {"volume_lights", volume_emitters_.size()}};
  }
  j["memory_bytes"] = {{"meshes", mesh_bytes}, {"embree", accel_.memory_bytes()},
                       {"lights", lights_.size() * sizeof(Light)},
                       {"environment", (world_.map ? world_.map->memory_bytes() : 0) +
                                          (camera_world_ && camera_world_->map ? camera_world_->map->memory_bytes() : 0)},
                       {"texture_cache_limit", size_t(ImageTextures::instance().cache_megabytes() * 1048576.0)}};
  return j.dump();
}

}  // namespace rdv
