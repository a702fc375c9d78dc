// The scene: meshes, instances, materials, lights, world and camera, plus what
// commit() derives from them (Embree BVHs, emissive-triangle lights, the light
// sampler). Only what the scene contains is built.
#pragma once
#include <bit>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>
#include "bsdfs/material.h"
#include "core/distribution.h"
#include "film/data_passes.h"
#include "lights/environment.h"
#include "lights/lamp_emission.h"
#include "lights/light.h"
#include "lights/volume_light.h"
#include "media/medium.h"
#include "scene/camera.h"
#include "scene/embree_accel.h"
#include "textures/texture_rays.h"
#include "scene/mesh.h"
#include "scene/ray_visibility.h"

namespace rdv {

// An index-matched medium boundary lying in a real surface (a smoke domain's bottom
// face on the floor), found with it (Scene::intersect_media): a path that goes on
// through the surface crosses the boundary too, one that is reflected does not.
struct CoincidentBoundary {
  int material = -1;  // none
  Vec3 ng;
};

struct SurfaceHit {
  Vec3 p;        // world-space position, reconstructed from barycentrics
  Vec3 error{0.0f};  // per-coordinate bound of its rounding error (core/ray_offset.h)
  Vec3 ng;       // geometric normal (unit), on the same side as ns
  Vec3 ns;       // shading normal (unit)
  Vec2 uv;
  float t = 0;
  uint32_t instance = 0, prim = 0, material = 0;
  float b1 = 0, b2 = 0;  // barycentrics of vertices 1 and 2 (for textures: Scene::shading_point)
};

class Scene : private TextureRays {
 public:
  Scene();

  uint32_t add_material(const std::string &name, Params &params);
  uint32_t add_error_material(const std::string &name);
  // A dense grid (nx*ny*nz floats, x fastest, copied) that media name by {"buffer": name};
  // adding a name again replaces its voxels for materials parsed from then on.
  uint32_t add_grid(const std::string &name, const float *values, uint32_t nx, uint32_t ny, uint32_t nz);
  // An image (width*height texels of `channels` floats, bottom row first, copied) that
  // image texture nodes name by {"buffer": name}; adding a name again replaces its
  // texels for materials parsed from then on (materials parsed before keep theirs).
  uint32_t add_image(const std::string &name, const float *pixels, uint32_t width, uint32_t height,
                     uint32_t channels, const std::string &colorspace);
  uint32_t add_mesh(const std::string &name, const float *positions, uint32_t num_vertices, const float *normals,
                    const float *uvs, const uint32_t *indices, uint32_t num_triangles,
                    const uint32_t *material_ids, uint32_t default_material);
  // A named per-vertex attribute: kind "uv" (2 floats per vertex) or "color" (3 or 4).
  void add_mesh_attribute(uint32_t mesh, const std::string &name, const std::string &kind, const float *data,
                          uint32_t num_components, uint32_t num_vertices);
  // In-place edits for interactive rendering (ids from the add_* calls): a replaced mesh
  // rebuilds only its own BVH (and the top level); materials and lights mark the light
  // tables for rebuilding at the next commit.
  void set_material(uint32_t id, Params &params);
  void set_mesh(uint32_t id, const float *positions, uint32_t num_vertices, const float *normals, const float *uvs,
                const uint32_t *indices, uint32_t num_triangles, const uint32_t *material_ids,
                uint32_t default_material);
  void set_light(uint32_t id, Params &params);
  uint32_t add_instance(uint32_t mesh, const Transform &to_world);
  void set_instance_transform(uint32_t instance, const Transform &to_world);
  // Motion blur (scene/motion.h): the instance's transform at n evenly spaced times over
  // the open shutter (n = 0 or 1: it does not move). Non-finite steps are an error naming
  // the object; steps that pass through a zero scale leave it static, with a warning.
  void set_instance_motion(uint32_t instance, const std::vector<Transform> &steps);
  // The most steps an object may give (Cycles' 7 motion steps are 65 transforms).
  static constexpr size_t kMaxMotionSteps = 1024;
  // Deformation motion blur (scene/motion.h): the mesh's vertex positions (3 floats per
  // vertex) at num_steps evenly spaced times over the open shutter, one step after the
  // other, and its vertex normals at the same times (null: its normals at every time).
  // num_steps 0 or 1: it does not deform. A vertex count other than the mesh's or a
  // non-finite value is an error naming the mesh, which keeps what it had.
  void set_mesh_motion(uint32_t mesh, const float *positions, const float *normals, uint32_t num_vertices,
                       uint32_t num_steps);
  // "object 'Name' (instance 3)": the instance in messages.
  std::string instance_description(uint32_t id) const;
  // {"holdout": bool, "shadow_catcher": bool, "visibility": {...}, "pass_index": n,
  //  "random_id": n, "color": [r, g, b, a], "object_attributes" / "instancer_attributes": {name:
  // value}} (rdv_scene_set_instance_params; scene/ray_visibility.h; Object Info reads random_id
  // and color, Attribute nodes of type Object / Instancer the attributes).
  void set_instance_params(uint32_t instance, Params &params);
  uint32_t add_light(const std::string &name, Params &params);
  void set_world(Params &params);
  void set_camera(Params &params);
  void commit();

  // Ray queries (after commit). intersect and occluded see real surfaces only: they
  // serve scenes without media. intersect_media finds index-matched medium boundaries
  // too; where a boundary and a real surface lie within a ray offset of each other, the
  // real surface is the hit and the boundary its `boundary`, whichever rounding put
  // first (scene/boundary_hits.cpp).
  bool intersect(const Ray &ray, SurfaceHit &hit) const;
  bool intersect_media(const Ray &ray, SurfaceHit &hit, CoincidentBoundary &boundary) const {
    boundary.material = -1;
    RawHit raw;
    bool found = accel_.intersect(ray, raw);
    if (accel_.has_boundaries()) return intersect_with_boundaries(ray, found ? &raw : nullptr, hit, boundary);
    if (found) surface_at(raw, hit);
    return found;
  }
  // mask: the kinds of ray the query stands for (scene/ray_visibility.h); instances
  // invisible to all of them do not block it.
  bool occluded(Vec3 o, Vec3 d, float tmax, uint32_t mask = visibility::kAnyRay) const {
    return accel_.occluded(o, d, tmax, mask);
  }
  // The nearest surface along ray (its mask: visibility::kMixed, or catcher_rays of it) of
  // an instance of mixed visibility: its distance, instance and triangle; false if none.
  bool nearest_mixed(const Ray &ray, float &t, uint32_t &instance, uint32_t &prim) const {
    RawHit raw;
    if (!accel_.intersect(ray, raw)) return false;
    t = raw.t;
    instance = raw.instance;
    prim = raw.prim;
    return true;
  }
  // What textures need at a hit: object / generated coordinates, named attributes, UV
  // tangents, and the footprint of a ray along dir that is `width` wide there.
  ShadingPoint shading_point(const SurfaceHit &hit, Vec3 dir = Vec3(0.0f), float width = 0) const;
  // The hit's material as a Bsdf toward wo, image textures filtered over a footprint
  // `width` wide (RayCone::width_at); constant materials need no ShadingPoint. Le, if
  // given, receives the radiance the surface emits there toward the ray's origin, hit.t away.
  Bsdf bsdf(const SurfaceHit &hit, Vec3 wo, float width = 0, Color *Le = nullptr) const;
  // The lights' sampling routines (lights/light.h) with textured emissive triangles
  // evaluated at the sampled point.
  bool sample_light(uint32_t light, Vec3 ref, Vec2 u, Vec3 u_volume, LightSample &out) const;
  bool sample_emission(uint32_t light, Vec2 u_pos, Vec2 u_dir, Vec3 u_volume, EmissionSample &out) const;
  // The light where it is at this thread's shutter time (scene/motion.h): an emissive
  // triangle of a moving or deforming object (Light::moves) is placed in `storage`, as
  // surface_at places a hit on it; every other light is lights()[light] itself.
  const Light &light_now(uint32_t light, Light &storage) const;
  // What a finite light sends from its point p (normal n: a sphere lamp's side) along w to
  // the point `receiver` (lights/light.h's lamp_radiance, textured triangles, volumes: per
  // unit length). Lights at infinity: 0 (infinite_light_radiance).
  Color light_radiance(const Light &light, Vec3 p, Vec3 n, Vec3 w, Vec3 receiver) const;
  // Radiance of a textured emissive triangle at point p on it (unfiltered texture lookup)
  // toward a point `distance` away.
  Color triangle_emission(const Light &light, Vec3 p, float distance) const;

  // The camera as set (at its "transform"). A sample traces with camera_now().
  const Camera &camera() const { return camera_; }
  Camera &camera() {
    camera_generation_ = next_camera_generation();  // the caller may change it
    return camera_;
  }
  // The camera at the shutter time of the sample this thread traces (scene/motion.h):
  // the camera itself unless it moves.
  const Camera &camera_now() const;
  // Motion blur: the camera or some instance moves while the shutter is open (derived by
  // commit()). Without, samples draw no time and every ray is traced at time 0.
  bool has_motion() const { return has_motion_; }
  // The first moving object's name (for messages), "" if none.
  const std::string &moving_object() const { return moving_object_; }
  bool has_camera() const { return has_camera_; }
  const Material &material(uint32_t id) const { return materials_[id]; }
  // ---- Participating media (scene.cpp). A scene without them pays nothing: the
  // integrators test has_media() once per sample, never per ray.
  bool has_media() const { return !media_.empty(); }
  // Some medium is a grid: its estimators need random numbers of their own.
  bool has_heterogeneous_media() const { return has_heterogeneous_media_; }
  const Medium &medium(int id) const { return media_[id]; }
  int num_media() const { return int(media_.size()); }
  int world_medium() const { return world_medium_; }
  int interior_medium(uint32_t material) const { return material_interior_[material]; }
  // A material with no surface ("type": "volume"): an index-matched medium boundary
  // that rays and shadow rays pass straight through.
  bool is_boundary_only(uint32_t material) const { return material_boundary_[material] != 0; }
  const std::vector<int> &camera_media() const { return camera_media_; }  // innermost last
  // The media a point is in, found by walking a ray from o along d out of the scene
  // (the boundaries it leaves without having entered); outermost first.
  std::vector<int> media_along(Vec3 o, Vec3 d) const;
  // The media a light's points are in (outermost first), found once per commit
  // (light_media.cpp); null where they depend on the point (a medium boundary passes
  // through the light, volume lights): then media_along from the point.
  const std::vector<int> *light_media(uint32_t light) const {
    const LightMedia &m = light_media_[light];
    return m.fixed ? &m.media : nullptr;
  }
  // Some material lets shadow rays through (Transparent BSDF, Principled alpha).
  bool has_transparency() const { return has_transparency_; }
  // Whether a transparent surface may be no plain layer (is_plain_layer): a transparent
  // material that emits or holds out, or any transparent material in a scene with holdout or
  // shadow-catcher objects (which may wear it).
  bool has_transparent_non_layers() const { return has_transparent_non_layers_; }
  // Some instance or material is a holdout (integrators/film_alpha.h).
  bool has_holdouts() const { return has_holdouts_; }
  // What of the surface at hit is held out: 1 on a holdout instance, else its material's
  // Holdout closures' weight (0 for most).
  float holdout_weight(const SurfaceHit &hit) const;
  // ---- Shadow catchers (integrators/path/shadow_catcher.h). The first enabled instance
  // that is one ("object 'Floor' (instance 3)", for messages), "" if none: read from the
  // instances, so it holds before commit() too.
  std::string shadow_catcher_object() const;
  bool has_shadow_catchers() const { return !shadow_catcher_object().empty(); }
  bool is_shadow_catcher(uint32_t instance) const { return instances_[instance].shadow_catcher; }
  // A transparent layer BDPT's walks pass straight through without making it a path vertex,
  // and its connections see through (bdpt/subpaths.cpp), as the path tracer's paths and
  // shadow rays do: a material that may let rays through and neither emits nor holds out,
  // on an instance that is neither a holdout nor a shadow catcher (those stay vertices: the
  // camera's see-through chain and the emission found there read them).
  bool is_plain_layer(const SurfaceHit &hit) const {
    const Material &m = materials_[hit.material];
    const Instance &inst = instances_[hit.instance];
    return m.transparent && !m.emits() && !m.holdout && !inst.holdout && !inst.shadow_catcher;
  }
  bool is_holdout_instance(uint32_t instance) const { return instances_[instance].holdout; }
  // ---- Data passes (film/data_passes.h): the world's mist settings, and the surface at
  // hit as a camera path's see-through chain meets it with throughput beta (its distance
  // from the camera, opacity and pass indices) added to data.
  const MistSettings &mist() const { return mist_; }
  void add_data_passes(const SurfaceHit &hit, Color beta, float alpha_threshold, DataPassSample &data) const;
  // The world where the chain leaves along unit direction dir: its AOV Outputs, then
  // DataPassSample::add_world.
  void add_world_data_passes(Vec3 dir, DataPassSample &data) const;
  // Cryptomatte's manifests (film/cryptomatte.h): the names of the enabled instances'
  // objects and assets, and of the materials.
  CryptoManifests crypto_manifests() const;
  // Denoising data (film/denoising_passes.h): a surface of BSDF bsdf seen from wo, reached
  // by a ray segment of length `segment`, added to a sample whose features are active.
  void add_denoising_surface(const Bsdf &bsdf, Vec3 wo, float segment, DenoisingSample &sample) const {
    const Camera &camera = camera_now();
    const CameraAxes axes{normalize(camera.to_world.column(0)), normalize(camera.to_world.column(1)), camera.forward()};
    sample.add_surface(bsdf.denoising_closures(wo), segment, axes);
  }
  // The ray segment from o along unit d to tmax through `medium`, entered with path
  // throughput beta, added to a sample whose features are active. Grid media estimate the
  // segment's transmittance by ratio tracking (or their ray marching) with numbers of its
  // own, from a generator seeded by the segment, so the image samples the same with the
  // passes on or off; a medium that does not scatter adds nothing and costs nothing.
  static void add_denoising_volume(const Medium &medium, Vec3 o, Vec3 d, float tmax, Color beta,
                                   DenoisingSample &sample) {
    const Color albedo = medium.scattering_albedo();
    if (is_black(albedo)) return;
    Color transmittance;
    if (medium.is_heterogeneous()) {
      const uint32_t seed = hash3(hash3(std::bit_cast<uint32_t>(o.x), std::bit_cast<uint32_t>(o.y),
                                        std::bit_cast<uint32_t>(o.z)),
                                  hash3(std::bit_cast<uint32_t>(d.x), std::bit_cast<uint32_t>(d.y),
                                        std::bit_cast<uint32_t>(d.z)),
                                  std::bit_cast<uint32_t>(tmax));
      SampleRun run{Pcg32(seed, 0x64656e6fu)};
      transmittance = medium.transmittance(o, d, tmax, run);
    } else {
      transmittance = medium.transmittance(tmax);
    }
    sample.add_volume_segment(beta, albedo, transmittance);
  }
  // ---- Ray visibility (scene/ray_visibility.h). has_ray_visibility: some instance, light
  // or the world is hidden from some kind of ray beyond what lamps hide from the camera
  // by default, so integrators classify their rays. has_mixed_visibility: some instance
  // is seen by some but not all kinds of ray after a scattering or by shadow rays, or a
  // lamp casts no shadows: then a ray of one kind passes what another meets, which paths
  // traced from the lights cannot follow (integrators/path, bdpt say what they do).
  bool has_ray_visibility() const { return has_ray_visibility_; }
  // A look copy of mixed visibility (Instance::look_copy): which of the object's copies a
  // ray that any kind but the camera's may be meets there is the BVH's choice.
  bool ends_light_walks(uint32_t instance) const {
    const Instance &inst = instances_[instance];
    return inst.look_copy && visibility::is_mixed(inst.visibility);
  }
  bool has_mixed_visibility() const { return has_mixed_visibility_; }
  uint32_t instance_visibility(uint32_t instance) const { return instances_[instance].visibility; }
  // The first object (or light, or the world) hidden from some kind of ray, and the first
  // whose visibility is mixed, for messages; "" if none.
  const std::string &ray_visibility_object() const { return ray_visibility_object_; }
  const std::string &mixed_visibility_object() const { return mixed_visibility_object_; }
  const std::vector<Light> &lights() const { return lights_; }
  // The light an emissive triangle is, for MIS when a path hits it.
  uint32_t triangle_light(uint32_t instance, uint32_t prim) const {
    const Instance &inst = instances_[instance];
    return inst.light_base + meshes_[inst.mesh].emissive_rank[prim];
  }
  const Distribution1D &light_distribution() const { return light_distribution_; }
  // Lights a ray can hit (disks, rectangles) apart from mesh emitters; infinite lights.
  const std::vector<uint32_t> &hittable_lights() const { return hittable_lights_; }
  const std::vector<uint32_t> &infinite_lights() const { return infinite_lights_; }
  // The nearest lamp (sphere, rectangle, ellipse) along the ray before tmax, or -1; lamps hidden
  // from the ray's kind (ray.mask; camera rays see lamps only when asked) are skipped,
  // and `skip` (the lamp the ray just passed). Sets tmax to its distance and L to its radiance. Lamps are transparent, as in Cycles 3.4 (shade_light goes on
  // through them): a path that meets one adds its radiance and carries on to what lies
  // behind it from the lamp's point (LampCrossing), and shadow rays ignore lamps.
  // catcher_only: the catcher pass's path of a shadow catcher (Light::shadow_catcher).
  int nearest_lamp(const Ray &ray, int skip, float &tmax, Color &L, bool catcher_only = false) const {
    int lamp = -1;
    for (uint32_t li : hittable_lights_) {
      if (!(lights_[li].visibility & ray.mask) || int(li) == skip) continue;
      if (catcher_only && !lights_[li].shadow_catcher) continue;
      float t;
      Color Le;
      if (intersect_light(lights_[li], ray, tmax, t, Le)) { tmax = t; lamp = int(li); L = Le; }
    }
    return lamp;
  }
  float bounding_radius() const { return bounding_radius_; }
  Vec3 bounding_center() const { return bounding_center_; }

  // A warning for the user (rdv_scene_messages), also from a session's settings (const:
  // the scene's content does not change).
  void warn(const std::string &message) const;
  std::string messages() const;
  const EnvironmentMap *environment() const { return world_.map.get(); }
  std::string summary_json() const;

 private:
  // The Ambient Occlusion and Bevel nodes' rays (TextureRays).
  bool texture_ray_occluded(const ShadingPoint &sp, Vec3 d, float tmax, bool only_local) const override;
  int texture_ray_local_hits(const ShadingPoint &sp, Vec3 o, Vec3 d, float tmax, LocalHit *hits, int max_hits,
                             uint32_t seed) const override;
  Vec3 texture_camera_space(Vec3 p) const override { return world_to_camera_.point(p); }
  Ray to_object_now(uint32_t instance, const Ray &world) const;
  // What the world looks like: a constant radiance, or an HDRI / baked sky (map) times it.
  struct WorldLook {
    Color radiance{0.05f};
    std::shared_ptr<EnvironmentMap> map;  // null: the constant
    bool is_black() const { return map ? rdv::is_black(map->mean()) : rdv::is_black(radiance); }
  };
  WorldLook parse_world_look(Params &params) const;
  void build_lights();
  void build_volume_lights();
  void add_world_light(const WorldLook &look, uint32_t rays);
  // ---- True displacement (scene/displacement.cpp), before the BVHs are built: moves the
  // vertices of meshes whose materials displace them, from the positions as given, where the
  // materials, the mesh or its first instance changed since it was last done.
  void displace_meshes();
  void displace_mesh(uint32_t mesh, uint32_t instance);
  static void restore_given_mesh(Mesh &m);  // undoes a displacement (none: nothing)
  std::vector<uint64_t> material_edits_;  // per material: set_material calls (displacement keys)
  // ---- Motion blur (scene/motion.cpp).
  // Which instances move (Instance::moving), before the BVHs are built.
  void find_motion();
  static const InstancePlacement &placement(const Instance &inst) { return inst; }
  // A moving instance's placement at the sample's shutter time.
  InstancePlacement placement_now(const Instance &inst) const;
  std::string instance_name(uint32_t id) const;
  // Cryptomatte: the index of an object or asset name among crypto_names_ (added once).
  uint32_t crypto_name(const std::string &name);
  std::vector<std::string> crypto_names_;
  std::vector<float> crypto_ids_;  // cryptomatte::id_of each name
  std::unordered_map<std::string, uint32_t> crypto_name_index_;
  // A triangle's vertices at the sample's shutter time: as stored unless the mesh deforms.
  static void triangle_now(const Mesh &m, const uint32_t *tri, Vec3 p[3]);
  // Its vertex normals at the same time (a smooth mesh's).
  static void normals_now(const Mesh &m, const uint32_t *tri, Vec3 n[3]);
  static uint64_t next_camera_generation();
  bool has_motion_ = false;
  std::string moving_object_;
  uint64_t camera_generation_ = next_camera_generation();  // tells camera_now's cache that the camera changed
  // The surface point at barycentrics (b1, b2) of a triangle of an instance.
  void surface_at(uint32_t instance, uint32_t prim, float b1, float b2, SurfaceHit &hit) const;
  void surface_at(const RawHit &raw, SurfaceHit &hit) const {
    surface_at(raw.instance, raw.prim, raw.u, raw.v, hit);
    hit.t = raw.t;
  }
  // intersect_media in a scene with medium boundaries; surface: the nearest real
  // surface, or null.
  bool intersect_with_boundaries(const Ray &ray, const RawHit *surface, SurfaceHit &hit,
                                 CoincidentBoundary &boundary) const;
  Mesh make_mesh(const std::string &name, const float *positions, uint32_t num_vertices, const float *normals,
                 const float *uvs, const uint32_t *indices, uint32_t num_triangles, const uint32_t *material_ids,
                 uint32_t default_material);
  std::vector<Material> materials_;
  GridBuffers grid_buffers_;
  ImageBuffers image_buffers_;
  struct ParsedMaterial {
    Material material;
    Medium medium;
    bool has_medium = false, boundary_only = false;
  };
  ParsedMaterial parse_material(const std::string &name, Params &params);
  std::vector<int> material_interior_;     // medium inside meshes of this material, or -1
  std::vector<uint8_t> material_boundary_;  // 1: no surface, only a medium boundary
  std::vector<Medium> media_;
  int world_medium_ = -1;
  std::vector<int> camera_media_;
  void find_camera_media();
  void find_ray_visibility();
  struct LightMedia {
    bool fixed = false;
    std::vector<int> media;
  };
  std::vector<LightMedia> light_media_;  // per light, derived by commit()
  void find_light_media();
  // Erases medium `id` (none if negative), which its owner no longer refers to.
  void drop_medium(int id);
  std::vector<Mesh> meshes_;
  std::vector<Instance> instances_;
  std::vector<Light> user_lights_;
  std::vector<std::unique_ptr<LampEmission>> user_light_emissions_;  // what user_lights_ point to
  std::vector<std::string> user_light_names_;
  WorldLook world_;
  // Light Path > Is Camera Ray in the World's nodes: what camera rays see, when it differs
  // from what every other ray sees (then the world above lights and this one is the backdrop).
  std::optional<WorldLook> camera_world_;
  std::optional<Material> world_aovs_;  // the World's AOV Outputs (set_world's "aovs")
  bool has_transparency_ = false;
  bool has_transparent_non_layers_ = false;
  bool has_holdouts_ = false;
  uint32_t world_visibility_ = visibility::kAll;
  MistSettings mist_;
  bool has_ray_visibility_ = false, has_mixed_visibility_ = false;  // derived by commit()
  std::string ray_visibility_object_, mixed_visibility_object_;
  bool has_heterogeneous_media_ = false;  // derived by commit()
  Camera camera_;
  Transform world_to_camera_;  // camera_.to_world's inverse (the Camera Data node)
  bool has_camera_ = false;
  bool dirty_ = true;

  // Derived by commit().
  EmbreeAccel accel_;
  std::vector<Light> lights_;
  std::vector<std::unique_ptr<VolumeEmitter>> volume_emitters_;
  Distribution1D light_distribution_;
  std::vector<uint32_t> hittable_lights_, infinite_lights_;
  Vec3 bounding_center_{0.0f};
  float bounding_radius_ = 1;
  uint64_t emissive_triangles_ = 0;
  uint32_t dropped_triangles_ = 0;

  // Sessions made on one scene from several threads may warn at once.
  mutable std::mutex messages_mutex_;
  mutable std::string messages_;
};

}  // namespace rdv
