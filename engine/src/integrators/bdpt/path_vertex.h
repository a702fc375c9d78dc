// An explicit path vertex (Veach 1997, ch. 10; pbrt-v3's bdpt.h): camera, light or
// surface, with the throughput of its subpath and the forward and reverse densities
// of generating it, both in area measure (solid angle for infinite lights). BDPT's
// MIS, light tracing and, later, path-space mutations all work on these.
#pragma once
#include <new>
#include <type_traits>
#include "bsdfs/bsdf.h"
#include "integrators/caustics_switches.h"
#include "integrators/light_path_limits.h"
#include "media/medium_stack.h"
#include "scene/scene.h"

namespace rdv::bdpt {

enum class VertexType : uint8_t { Camera, Light, Surface, Medium };

struct PathVertex {
  VertexType type = VertexType::Surface;
  Color beta{0.0f};     // subpath throughput up to and including this vertex
  Vec3 p{0.0f};
  Vec3 ng{0.0f};        // geometric normal (zero: a point-like vertex, no cosine)
  Vec3 error{0.0f};     // rounding error bound of p on geometry Embree can hit (core/ray_offset.h)
  Vec3 ns{0.0f};        // shading normal
  Vec3 wo{0.0f};        // toward the vertex this one was reached from
  float pdf_fwd = 0, pdf_rev = 0;
  bool delta = false;   // scattered by a delta lobe: cannot be connected to
  // Went straight through (Transparent BSDF, alpha): no scattering for the light passes.
  // Only a surface that is no plain layer (Scene::is_plain_layer) is such a vertex: the
  // walks pass plain layers without making them vertices.
  bool passed_through = false;
  // On its walk before it (after the walk's start): the straight passes (plain layers and
  // vertices passed through; Transparent max bounces) and the vertices that scattered.
  uint16_t passes = 0, scatterings = 0;
  int light = -1;       // light index: light vertices, and surfaces on emitters
  bool infinite = false;  // an infinite light (escaped ray or light-subpath start); p unused, dir set
  Vec3 dir{0.0f};       // infinite lights: direction from the scene toward the light
  Color emitted{0.0f};  // radiance of the lamp or emissive surface where a path hit it
  uint32_t material = 0;
  CoincidentBoundary boundary;  // a medium boundary lying in this surface (Scene::intersect_media)
  Bsdf bsdf;
  int medium = -1;      // medium vertices: the medium that scattered (its phase function)
  // Points of volume lights: camera paths gather emission at this many points per unit
  // length (media/emission_gather.h), so the density of a camera path reaching the
  // point is its solid-angle density / distance^2 times this rate.
  float gather_rate = 0;
  MediumStack media;    // the media the path was in when it reached this vertex
  // Surface and medium vertices: what converts densities of scattering back toward
  // the vertex before this one on its subpath into area measure there (the cosine or
  // gather rate there and 1 / distance^2; to_prev_density), set once by the random walk.
  float prev_scale = 1, prev_inv_d2 = 1;
  bool surface_connectible = false;  // a surface with a non-delta lobe
  double mis_sum = 0;  // MIS sum of the strategies at or below this vertex (set_mis_sum)
  float specularity = 0;  // Lafortune & Willems' weights only: their W at camera-path vertices
  // Cycles' Light Paths (set only when the settings classify paths, light_path_limits.h):
  // the kind of this vertex's scattering along its subpath (toward the next vertex), the
  // bounces of each kind on its subpath up to and including it (light subpaths leave out
  // their first vertex after the light: it is always a path's last scattering vertex).
  ScatterKind kind = ScatterKind::Transparent;
  // Camera subpaths with a transparent film or holdouts (integrators/film_alpha.h): every
  // scattering between the camera and this vertex kept the background seen through.
  bool see_through = false;
  // Scenes with a shadow catcher (bdpt/shadow_catcher.cpp): a surface of a catcher that is no
  // holdout object.
  bool catcher = false;
  float holdout = 0;  // scenes with holdouts: what of this surface is held out (Scene::holdout_weight)
  // The caustics switches (caustics_switches.h; set only when one is off): on a camera
  // subpath the chain's state past this vertex and the share of f the switches keep here
  // after a diffuse bounce; on a light subpath the weight of the rest of the path, from this
  // vertex toward the light, by the state in which a path enters it.
  CausticState caustics;
  Color caustic_kept = Color(1.0f);
  BounceCounts counts;
  // Filter Glossy (integrators/filter_glossy.h; set only when it is on). Camera subpaths:
  // filter_pdf, the smallest density of the scatterings before this vertex (what its BSDF
  // was blurred by), and blurred: the blur changed its BSDF. Light subpaths: filter_pdf,
  // the density (solid angle) with which a camera walk scattering here samples the
  // direction toward the vertex before it (infinite for a delta event), and blur_threshold,
  // the BSDF's (Bsdf::blur_threshold; infinite for media).
  float filter_pdf = kInf;
  float blur_threshold = kInf;
  bool blurred = false;
  // Mixed visibility (camera subpaths; bdpt.h): no light walk could have made the segment
  // that reaches this vertex, so no strategy with fewer camera vertices than this one's
  // index + 1 makes the path (set_mis_sum stops the running sums here, as for `blurred`).
  bool light_cut = false;
  // A delta scattering whose two directions see different shading frames (a mapped normal
  // bent for one of them, the terminator fallback: Bsdf::same_frame_both_ways): a light
  // walk's delta lobe, sampled in the other frame, does not send the light to the camera
  // side here, so no light walk passes this camera vertex.
  bool one_way = false;
  // Any: the strategies below this camera vertex cannot make the path.
  bool ends_light_side() const { return blurred || light_cut || one_way; }
  // On a look copy of mixed visibility (Scene::ends_light_walks): no light walk makes a
  // vertex here (camera subpaths; bdpt.h).
  bool look_copy = false;
  // Ray visibility (scene/ray_visibility.h): a surface's instance's bits (scenes with ray
  // visibility), and on camera subpaths the kind of the ray that left the vertex.
  uint32_t visibility = visibility::kAll;
  uint32_t out_mask = visibility::kAnyRay;

  // The media a connection leaving this vertex along w starts in: surfaces that w
  // goes through (transmission) hand over to the medium on the other side.
  MediumStack media_toward(const Scene &scene, Vec3 w) const {
    MediumStack s = media;
    if (type == VertexType::Surface && dot(w, ng) * dot(-wo, ng) > 0) s.cross(scene, material, ng, w, boundary);
    return s;
  }

  // The same up to and including this vertex.
  int passes_after() const { return passes + (passed_through ? 1 : 0); }
  int scatterings_after() const {
    return scatterings + ((type == VertexType::Surface || type == VertexType::Medium) && !passed_through ? 1 : 0);
  }
  bool on_surface() const { return ng.x != 0 || ng.y != 0 || ng.z != 0; }
  bool is_light() const { return type == VertexType::Light || (type == VertexType::Surface && light >= 0); }
  bool connectible(const Scene &scene) const;
  // Density conversion from solid angle at this vertex to area at `next`.
  float convert_density(float pdf_solid_angle, const PathVertex &next) const;
  // The same toward the previous vertex of the subpath (as convert_density(pdf, prev)).
  float to_prev_density(float pdf_solid_angle) const { return pdf_solid_angle * prev_scale * prev_inv_d2; }
  // Surface and medium vertices, on the random walk: pdf_fwd from pdf_dir, the
  // solid-angle density with which prev sampled the direction here, and the geometry
  // toward prev that to_prev_density uses.
  void link_to_prev(const PathVertex &prev, float pdf_dir);
};

static_assert(std::is_trivially_destructible_v<PathVertex>);

// Starts the vertex in v's storage afresh. Default-initialisation leaves the BSDF's
// raw lobe storage alone; assigning PathVertex{} zero-filled all 3.4 KB of it.
inline PathVertex &fresh_vertex(PathVertex &v) { return *new (&v) PathVertex; }

// A fresh surface vertex where a ray along d hit, in `media` (the BSDF is the caller's).
inline PathVertex &fresh_surface_vertex(PathVertex &storage, const SurfaceHit &hit, Vec3 d,
                                        const CoincidentBoundary &boundary, const MediumStack &media) {
  PathVertex &v = fresh_vertex(storage);
  v.type = VertexType::Surface;
  v.p = hit.p;
  v.error = hit.error;
  v.ng = hit.ng;
  v.ns = hit.ns;
  v.wo = -d;
  v.material = hit.material;
  v.boundary = boundary;
  v.media = media;
  return v;
}

}  // namespace rdv::bdpt
