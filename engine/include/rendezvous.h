/*
 * rendezvous.h - the one public header of the Rendezvous render engine.
 *
 * A plain C ABI: opaque handles, POD arrays, status codes. No C++ type and no
 * exception crosses it. Every call returns an rdv_status; on failure
 * rdv_last_error() returns a message (thread-local) naming the object and the
 * field at fault.
 *
 * Conventions (the same as Blender's, so the add-on passes its data through):
 *  - right-handed, Z up; a camera looks down its local -Z with +Y up;
 *  - matrices are 4x4, row-major, float, mapping local to world (p' = M p);
 *  - lengths are scene units (Blender units = metres unless scaled);
 *  - colours are scene-linear Rec.709 RGB.
 *
 * Parameter descriptions (materials, lights, camera, world, render settings) are
 * JSON objects of key/value pairs, passed as UTF-8 strings. Unknown keys are
 * reported as an error naming the object and the key, never silently ignored.
 * docs/scene-format.md lists every key.
 *
 * Threading: a scene may be edited from one thread at a time and must not be
 * edited while a session that renders it is running (stop or cancel it first).
 * rdv_session_progress / rdv_session_read_film / rdv_session_cancel may be
 * called from any thread while the session renders.
 */
#ifndef RENDEZVOUS_H
#define RENDEZVOUS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define RDV_API __declspec(dllexport)
#else
#define RDV_API __attribute__((visibility("default")))
#endif

/* Bumped on every incompatible change of this header. */
#define RDV_API_VERSION 2

typedef enum rdv_status {
  RDV_OK = 0,
  RDV_ERROR_INVALID_ARGUMENT = 1, /* a NULL handle, a malformed or out-of-range value */
  RDV_ERROR_UNKNOWN_PARAMETER = 2, /* a key the object type does not have */
  RDV_ERROR_IO = 3,               /* a file could not be read or written */
  RDV_ERROR_STATE = 4,            /* the call is not allowed now (e.g. edit while rendering) */
  RDV_ERROR_INTERNAL = 5,         /* a bug or out of memory: the message says more */
  RDV_ERROR_LIMIT = 6             /* an input beyond a documented limit (nesting depth, generated
                                     geometry, memory): the message names the object, the figure
                                     and the limit (docs/scene-format.md, Limits) */
} rdv_status;

typedef struct rdv_scene rdv_scene;
typedef struct rdv_session rdv_session;

/* ---- library ---------------------------------------------------------------- */
RDV_API int rdv_api_version(void);
/* Message of the last failed call on this thread ("" if none). */
RDV_API const char *rdv_last_error(void);
/* How many scenes and sessions exist in this process (leak checks); either may be NULL. */
RDV_API rdv_status rdv_live_objects(uint32_t *out_scenes, uint32_t *out_sessions);

/* ---- scene ------------------------------------------------------------------ */
RDV_API rdv_status rdv_scene_create(rdv_scene **out_scene);
RDV_API rdv_status rdv_scene_destroy(rdv_scene *scene);

/* Materials. params is a JSON object, e.g. {"type":"diffuse","color":[0.8,0.8,0.8]}.
 * Types: "diffuse", "emission", "glossy" (GGX conductor), "glass", "principled",
 * "transparent", "translucent", "sheen", "mix", "add"; any colour or float parameter
 * may be a texture graph; see docs/scene-format.md. */
RDV_API rdv_status rdv_scene_add_material(rdv_scene *scene, const char *name,
                                          const char *params_json, uint32_t *out_material);

/* A dense grid from a caller-owned array (copied): nx * ny * nz floats, x fastest
 * (values[(k * ny + j) * nx + i]), finite and not negative: the layout of a grid's JSON
 * "values". A medium names it in place of "resolution" and "values", wherever a dense
 * grid is accepted ("grid", "emission_grid", "temperature_grid"):
 *   {"buffer": name, "bounds": [[x0,y0,z0],[x1,y1,z1]], "transform": [16]}
 * Add the grid before the material that names it; an unknown name warns (naming the
 * medium) and the medium renders without that grid, as with a missing VDB file. Adding
 * a name again replaces its voxels (same id) for materials added or set from then on:
 * call rdv_scene_set_material again for a material to see them. out_grid may be NULL. */
RDV_API rdv_status rdv_scene_add_grid(rdv_scene *scene, const char *name, const float *values,
                                      uint32_t nx, uint32_t ny, uint32_t nz, uint32_t *out_grid);

/* An image from a caller-owned array (copied): width * height texels of `channels` floats
 * (1 grey, 2 grey + alpha, 3 RGB, 4 straight RGBA), rows bottom first, left to right
 * (pixels[((y * width) + x) * channels + c], y = 0 the bottom row: Blender's
 * image.pixels). Values are in `colorspace`, a colour space of Blender's OCIO config
 * (NULL or "" = Linear, i.e. scene-linear; "Non-Color" = data), converted to scene-linear
 * as an image file's texels are (after filtering, as for files). An image texture node
 * names it in place of a file: {"node": "image", "buffer": name, "interpolation",
 * "extension", ...} and filters it exactly as a file. NaN / infinite values are set to 0
 * with a warning naming the image; an unknown colour space warns and uses the values as
 * they are. Add the image before the material that names it; an unknown name warns
 * (naming the material) and renders magenta, as a missing file does. Adding a name again
 * replaces its texels (same id) for materials added or set from then on: call
 * rdv_scene_set_material again for a material to see them. out_image may be NULL. */
RDV_API rdv_status rdv_scene_add_image(rdv_scene *scene, const char *name, const float *pixels, uint32_t width,
                                       uint32_t height, uint32_t channels, const char *colorspace,
                                       uint32_t *out_image);

/* A triangle mesh from caller-owned arrays; the engine copies what it keeps.
 *   positions      3 * num_vertices floats
 *   normals        3 * num_vertices floats, or NULL (flat shading)
 *   uvs            2 * num_vertices floats, or NULL
 *   indices        3 * num_triangles vertex indices
 *   material_ids   num_triangles material ids from rdv_scene_add_material, or NULL
 *                  (then every triangle uses default_material)
 * Triangles with non-finite or degenerate (zero-area) corners are dropped with a
 * warning (rdv_scene_messages); an index out of range rejects the whole mesh. */
RDV_API rdv_status rdv_scene_add_mesh(rdv_scene *scene, const char *name,
                                      const float *positions, uint32_t num_vertices,
                                      const float *normals, const float *uvs,
                                      const uint32_t *indices, uint32_t num_triangles,
                                      const uint32_t *material_ids, uint32_t default_material,
                                      uint32_t *out_mesh);

/* A named per-vertex attribute of a mesh (added after rdv_scene_add_mesh, before
 * rendering): kind "uv" (a UV map, num_components = 2) or "color" (a vertex colour,
 * num_components 3 or 4, scene-linear RGB(A)). num_vertices must equal the mesh's.
 * Texture nodes read them by name ({"node":"uv","layer":name},
 * {"node":"vertex_color","layer":name}, {"node":"attribute","name":name}).
 * The mesh's own uvs array is the default UV map. Adding a name again replaces it. */
RDV_API rdv_status rdv_scene_add_mesh_attribute(rdv_scene *scene, uint32_t mesh, const char *name,
                                                const char *kind, const float *data,
                                                uint32_t num_components, uint32_t num_vertices);

/* In-place edits for interactive rendering (like every edit: not while a session on the
 * scene exists). Replace material `material` (same id, same name; triangles keep using it),
 * mesh `mesh`'s geometry (arguments as rdv_scene_add_mesh; its attributes are dropped, add
 * them again; at the next commit only this mesh's BVH and the top level are rebuilt), or
 * light `light` (to switch a light off, give it zero power or strength). */
RDV_API rdv_status rdv_scene_set_material(rdv_scene *scene, uint32_t material, const char *params_json);
RDV_API rdv_status rdv_scene_set_mesh(rdv_scene *scene, uint32_t mesh, const float *positions,
                                      uint32_t num_vertices, const float *normals, const float *uvs,
                                      const uint32_t *indices, uint32_t num_triangles,
                                      const uint32_t *material_ids, uint32_t default_material);
RDV_API rdv_status rdv_scene_set_light(rdv_scene *scene, uint32_t light, const char *params_json);

/* An instance of a mesh: the mesh is stored once however many instances use it. */
RDV_API rdv_status rdv_scene_add_instance(rdv_scene *scene, uint32_t mesh,
                                          const float transform[16], uint32_t *out_instance);
RDV_API rdv_status rdv_scene_set_instance_transform(rdv_scene *scene, uint32_t instance,
                                                    const float transform[16]);
/* Motion blur: the instance's transform at num_steps evenly spaced times from the shutter's
 * opening to its closing (the camera's "shutter_open" / "shutter_close"), 16 row-major
 * floats each, interpolated linearly between steps; num_steps 0 or 1: it does not move.
 * A non-finite step is RDV_ERROR_INVALID_ARGUMENT naming the object; motion through a zero
 * scale or a mirror flip leaves the instance static with a warning. Instances that emit
 * light or bound a medium do not move (they stay at their transform). */
RDV_API rdv_status rdv_scene_set_instance_motion(rdv_scene *scene, uint32_t instance,
                                                 const float *transforms, uint32_t num_steps);
/* Deformation motion blur: the mesh's vertex positions at num_steps evenly spaced times
 * from the shutter's opening to its closing, num_vertices x 3 floats per step, one step
 * after the other, blended linearly between steps (as transforms); normals: its vertex
 * normals at the same times, laid out alike (NULL: the mesh's normals at every time; a
 * flat mesh ignores them). num_steps 0 or 1: it does not deform. num_vertices other than
 * the mesh's, or a NaN / Inf value, is RDV_ERROR_INVALID_ARGUMENT naming the mesh, which
 * keeps what it had. Every instance of the mesh deforms. Meshes that emit light or bound
 * a medium do not deform (a warning; they render as at their frame). A replaced mesh
 * (rdv_scene_set_mesh) has no steps until given them again. */
RDV_API rdv_status rdv_scene_set_mesh_motion(rdv_scene *scene, uint32_t mesh, const float *positions,
                                             const float *normals, uint32_t num_vertices, uint32_t num_steps);
/* An instance's object settings: {"holdout": false} (Object > Visibility > Holdout: the
 * instance renders black and cuts its coverage out of RDV_PASS_COMBINED's alpha where the
 * camera sees it, as Cycles), "visibility": {"camera": true, "diffuse": true, "glossy": true,
 * "transmission": true, "shadow": true, "volume_scatter": true} (Object > Visibility > Ray
 * Visibility: rays of a kind pass through what is hidden from them, as Cycles; lights and
 * the world take the same "visibility" in their parameters), "shadow_catcher": false
 * (Object > Visibility > Shadow Catcher, as Cycles 3.4: with the path tracer, RDV_PASS_COMBINED
 * shows the other objects over the catcher, which holds only the shadows and light they
 * add to it, and RDV_PASS_SHADOW_CATCHER that change as a factor; docs/scene-format.md,
 * Shadow catcher), "pass_index": 0, "random_id": 0 and "color": [1,1,1,1] (what an
 * "object_info" texture node reads: Blender's random id, Object > Viewport Display > Color).
 * Absent keys take their defaults. */
RDV_API rdv_status rdv_scene_set_instance_params(rdv_scene *scene, uint32_t instance, const char *params_json);

/* Lights: {"type":"point"|"spot"|"sun"|"area", "transform":[16], ...}. Units are
 * Blender's: Watts for point/spot/area, irradiance (W/m^2) for sun. */
RDV_API rdv_status rdv_scene_add_light(rdv_scene *scene, const char *name,
                                       const char *params_json, uint32_t *out_light);
/* World background: {"color":[r,g,b],"strength":s} (radiance). */
RDV_API rdv_status rdv_scene_set_world(rdv_scene *scene, const char *params_json);
/* Camera: {"type":"perspective"|"orthographic","transform":[16],"focal_length":mm,...}. */
RDV_API rdv_status rdv_scene_set_camera(rdv_scene *scene, const char *params_json);

/* Builds acceleration structures and light tables; called implicitly by
 * rdv_session_start. Fails cleanly (e.g. no camera). */
RDV_API rdv_status rdv_scene_commit(rdv_scene *scene);

/* Warnings collected while building the scene, one per line (valid until the
 * next call on this scene). */
RDV_API rdv_status rdv_scene_messages(rdv_scene *scene, const char **out_text);
/* What the engine modelled, as a JSON object (meshes, triangles, instances,
 * lights by type, media, memory). Valid until the next call on this scene. */
RDV_API rdv_status rdv_scene_summary(rdv_scene *scene, const char **out_json);

/* ---- render session ------------------------------------------------------------ */
/* settings JSON: {"width":W,"height":H,"integrator":"path","samples":N,
 *   "time_limit":seconds,"max_bounces":B,"seed":S,"threads":T,"clamp":C,
 *   "border":[x0,y0,x1,y1],"sample_offset":O,"scene_hash":"...","noise_target":E,
 *   "noise_pass":false,"adaptive_sampling":false,"adaptive_threshold":0.01,
 *   "adaptive_min_samples":0,"film_transparent":false,"film_transparent_glass":false,
 *   "film_transparent_roughness":0.1,"light_passes":false,"strategy_passes":false,
 *   "strategy_passes_max_depth":3} (strategy_passes: BDPT's per-strategy images,
 *   RDV_PASS_STRATEGY_FIRST ..; light_passes: keep Cycles' light
 *   passes RDV_PASS_EMISSION .. RDV_PASS_VOLUME_INDIRECT, path and bdpt only; film_transparent: the world seen directly is transparent and
 *   RDV_PASS_COMBINED's alpha is coverage, as Cycles' Film > Transparent; noise_target: halt once the estimated relative MSE is below E,
 *   0 = off; noise_pass: estimate the noise for RDV_PASS_NOISE without a target;
 *   docs/noise.md) (sample_offset and
 *   scene_hash: render parts, see rdv_merge_parts). A session always has a halt condition: samples
 *   or time_limit (if neither is given, samples defaults to 128). integrator:
 *   path, bdpt, pssmlt, mmlt or mlt (Metropolis: samples = mutations per pixel; settings
 *   mlt_large_step, mlt_bootstrap, mlt_chains, mlt_step_size, mlt_target; docs/scene-format.md),
 *   or auto (needs time_limit: pilots of each of "auto_candidates", default
 *   ["path","bdpt","pssmlt","mmlt"], take 10% of it and the most efficient one renders the
 *   rest; docs/trade.md). */
RDV_API rdv_status rdv_session_create(rdv_scene *scene, const char *settings_json,
                                      rdv_session **out_session);
/* Starts rendering in the engine's own threads and returns at once. */
RDV_API rdv_status rdv_session_start(rdv_session *session);
/* Blocks until the render halts (samples reached, time limit, or cancel). */
RDV_API rdv_status rdv_session_wait(rdv_session *session);
/* Requests a stop; rendering threads stop within ~100 ms. Does not block. */
RDV_API rdv_status rdv_session_cancel(rdv_session *session);
RDV_API rdv_status rdv_session_destroy(rdv_session *session);

typedef struct rdv_progress {
  uint32_t samples_done;      /* samples per pixel (MLT: mutations) of the frame a read shows now */
  uint32_t samples_target;    /* 0 when only a time limit halts */
  double elapsed_seconds;
  double time_limit_seconds;  /* 0 when off */
  double fraction_done;       /* 0..1, whichever halt comes first */
  uint64_t rays_traced;       /* closest-hit plus shadow rays */
  double rays_per_second;
  uint64_t samples_dropped;   /* NaN / Inf samples discarded (never enter the film) */
  int32_t finished;           /* 1 once the render halted */
  int32_t cancelled;          /* 1 if it halted because of rdv_session_cancel */
  /* The estimated relative MSE of the frame a read shows (docs/noise.md): -1 when not
   * estimated (no noise_target and no adaptive sampling), +inf until every pixel has
   * samples in both half images. */
  double noise_estimate;
  double noise_target;        /* the setting: the render halts below it; 0 when off */
  int32_t noise_reached;      /* 1 if it halted because the estimate fell below the target */
} rdv_progress;
RDV_API rdv_status rdv_session_progress(rdv_session *session, rdv_progress *out_progress);

/* The integrator's own figures, as a JSON object (valid until the next call on this
 * session; "{}" for path and bdpt). Metropolis integrators (pssmlt, mmlt, mlt): "chains",
 * "bootstrap_samples", "b" (the image's luminance sum the bootstrap estimated) and
 * "b_standard_error", "mutations", "small_step_acceptance", "large_step_acceptance",
 * mmlt also "depth_b" (b per path depth), "strategy_counts" (mutations ending in each
 * (depth, s) state, depth-major: depth 0 has s = 0 only, depth d >= 1 has s = 0..d+1) and
 * "strategy_b" (the bootstrap's b of each such state); mlt also "bidirectional_acceptance"
 * (= small_step_acceptance: its partial bidirectional mutations; large steps regenerate the
 * whole path), "mutation_types" and "<type>_acceptance" of each perturbation; "warning"
 * when the image cannot be made (e.g. the bootstrap found no light). Integrator auto: "auto" {"integrator" (the pick; null during
 * the pilots), "pilot_seconds", "pilots": [{"integrator", "seconds", "rel_mse",
 * "efficiency", "spp"}], "time_limit_extended" when slow pilots left the pick under 5% of
 * the limit}, next to the pick's own figures. Safe to call while rendering. */
RDV_API rdv_status rdv_session_stats(rdv_session *session, const char **out_json);

typedef enum rdv_pass {
  RDV_PASS_COMBINED = 0, /* RGBA, 4 floats per pixel */
  RDV_PASS_DEPTH = 1,    /* camera-space distance along -Z, 1 float (1e10 = nothing hit) */
  RDV_PASS_NORMAL = 2,   /* world-space shading normal of the first hit, 3 floats */
  RDV_PASS_ALBEDO = 3,   /* first-hit albedo (Blender's Diffuse Color), 3 floats */
  RDV_PASS_NOISE = 4,    /* estimated relative error of each pixel, 1 float: the root of its
                            estimated relative MSE, averaged over R, G, B (docs/noise.md);
                            0 where there is no estimate yet (fewer than 2 samples) */
  /* Cycles' light passes (session setting "light_passes": true; path and bdpt), 3 floats
   * each: a path's contribution by the first scattering vertex the camera sees (its kind,
   * and Direct = the path's only scattering vertex, else Indirect; Emission and
   * Environment: emitters and the world's background seen with no scattering). Direct and
   * Indirect read divided by their kind's Color (as Cycles shows them), so Combined =
   * Emission + Environment + sum (Direct + Indirect) x Color + Volume Direct + Indirect.
   * Reading one from a session without light passes gives zeros. */
  RDV_PASS_EMISSION = 5,
  RDV_PASS_ENVIRONMENT = 6,
  RDV_PASS_DIFFUSE_DIRECT = 7,
  RDV_PASS_DIFFUSE_INDIRECT = 8,
  RDV_PASS_DIFFUSE_COLOR = 9,
  RDV_PASS_GLOSSY_DIRECT = 10,
  RDV_PASS_GLOSSY_INDIRECT = 11,
  RDV_PASS_GLOSSY_COLOR = 12,
  RDV_PASS_TRANSMISSION_DIRECT = 13,
  RDV_PASS_TRANSMISSION_INDIRECT = 14,
  RDV_PASS_TRANSMISSION_COLOR = 15,
  RDV_PASS_VOLUME_DIRECT = 16,
  RDV_PASS_VOLUME_INDIRECT = 17,
  /* Cycles' data passes (docs/scene-format.md, Passes), 1 float each, every integrator
   * (pssmlt, mmlt and mlt from their first-hit pass):
   * MIST: 0 at the camera side, 1 far away and where the world is seen (the world's
   * "mist": start, depth, falloff), filtered over the pixel, mixed through transparent
   * surfaces and fog as Cycles does; OBJECT_INDEX / MATERIAL_INDEX: the "pass_index" of
   * the object / material the pixel's first sample sees (the first surface at least
   * "pass_alpha_threshold" opaque; 0 for the world), not filtered, as Cycles. */
  RDV_PASS_MIST = 18,
  RDV_PASS_OBJECT_INDEX = 19,
  RDV_PASS_MATERIAL_INDEX = 20,
  /* Cycles' denoising data (session setting "denoising_passes": true; every integrator;
   * docs/scene-format.md, Passes), the feature images of Blender's Denoise node: the camera
   * path followed through near-specular surfaces (mirrors, smooth glass, alpha_x alpha_y
   * at most 0.075^2) to the first rough one, as Cycles 3.4. DENOISING_NORMAL: its shading
   * normal in camera space (x right, y up, z along the view), 3 floats; DENOISING_ALBEDO:
   * its rough closures' albedo times the specular ones' passed on the way, 3 floats;
   * DENOISING_DEPTH: the path's length to it (each segment weighted by the albedo before
   * it), 1 float. Means over the pixel's samples; 0 where the world is seen. Reading one
   * from a session without them gives zeros. */
  RDV_PASS_DENOISING_NORMAL = 21,
  RDV_PASS_DENOISING_ALBEDO = 22,
  RDV_PASS_DENOISING_DEPTH = 23,
  /* Shadow catchers (instance setting "shadow_catcher"; the path tracer; docs/scene-format.md,
   * Shadow catcher), as Cycles 3.4. SHADOW_CATCHER: the catcher's light with the other
   * objects over its light without them, per channel, 3 floats (1 where no catcher is seen,
   * below 1 in shadows: multiply footage by it). SHADOW_CATCHER_MATTE: the other objects
   * over a transparent catcher, RGBA. With a catcher in the scene, RDV_PASS_COMBINED reads
   * as Blender's Combined: the matte when the session setting "shadow_catcher_pass" is true
   * (View Layer > Passes > Shadow Catcher), else the matte with the shadow in its alpha
   * (film transparent) or over the world seen behind the catcher (film opaque). Without a
   * catcher, or with another integrator: 1 and zeros (alpha 1). */
  RDV_PASS_SHADOW_CATCHER = 24,
  RDV_PASS_SHADOW_CATCHER_MATTE = 25,
  /* BDPT's strategy passes (session setting "strategy_passes": true, bdpt only; docs/bdpt.md),
   * 3 floats each: pass RDV_PASS_STRATEGY_FIRST + k holds strategy k's MIS-weighted share of
   * Combined, for the paths of depth (bounces) d = s + t - 2 up to "strategy_passes_max_depth"
   * D (default 3, at most 6), numbered depth-major: k = 0 is s = 0, t = 2 (depth 0), then for
   * each depth d = 1 .. D: s = 0 .. d + 1 (t = d + 2 - s); the last, k = 1 + D (D + 5) / 2,
   * holds every longer path (EXR "Strategy_rest"). All of them sum to Combined's RGB. Reading
   * one beyond the session's passes (or without them) gives zeros. */
  RDV_PASS_STRATEGY_FIRST = 64,
  RDV_PASS_STRATEGY_LAST = 98, /* k = 34: the rest of D = 6 */
  /* Shader AOVs (session setting "aovs": [{"name", "type": "color" | "value"}], at most 16;
   * materials' "aovs"; Blender's View Layer > Shader AOV and AOV Output node): the session's
   * AOV k reads as RDV_PASS_AOV_COLOR_FIRST + k (4 floats: the mean of the colours written and
   * the share of samples that wrote one) when a colour pass, RDV_PASS_AOV_VALUE_FIRST + k (1
   * float) when a value pass; the other range, or a k beyond the session's, reads zeros. */
  RDV_PASS_AOV_COLOR_FIRST = 100,
  RDV_PASS_AOV_COLOR_LAST = 115,
  RDV_PASS_AOV_VALUE_FIRST = 116,
  RDV_PASS_AOV_VALUE_LAST = 131,
  /* Cryptomatte (session setting "cryptomatte": {"object", "material", "asset": true/false,
   * "levels": 1..16, default 6, "view_layer": name for the metadata}; instances' and
   * materials' "cryptomatte" names; Blender's View Layer > Passes > Cryptomatte): pass
   * RDV_PASS_CRYPTOMATTE_FIRST + 8 kind + k (kind 0 object, 1 material, 2 asset; k below
   * ceil(levels / 2)) is Blender's Crypto<Kind>0k, 4 floats: the ids (MurmurHash3_32 of
   * the name as a float) and coverages of the pixel's ranks 2k and 2k + 1, heaviest first;
   * zeros for an empty rank, a kind the session does not keep or k beyond its levels. The
   * layers' metadata (names, manifests) is in rdv_session_stats' "cryptomatte". */
  RDV_PASS_CRYPTOMATTE_FIRST = 140,
  RDV_PASS_CRYPTOMATTE_LAST = 163
} rdv_pass;
RDV_API int rdv_pass_channels(rdv_pass pass);

/* Copies a rectangle of the film into out (row-major, rows from the TOP of the
 * image down when top_down != 0, else bottom-up as Blender's RenderResult wants),
 * width * height * rdv_pass_channels(pass) floats. Coordinates are in pixels of the
 * full image. Safe to call while rendering: a read shows one frame, whole tiles of
 * camera samples and the splats of complete passes scaled for exactly those passes. */
RDV_API rdv_status rdv_session_read_film(rdv_session *session, rdv_pass pass, uint32_t x,
                                         uint32_t y, uint32_t width, uint32_t height,
                                         int32_t top_down, float *out);

/* Writes the film: ".exr" (scene-linear float, with passes as layers) or ".png"
 * through an OpenColorIO view transform (view: "Standard" or "Filmic"; NULL =
 * "Standard"; Blender's config.ocio). */
RDV_API rdv_status rdv_session_write_image(rdv_session *session, const char *path,
                                           const char *view);

/* ---- render farms (docs/farm.md) ------------------------------------------------
 * Every EXR written by rdv_session_write_image is a render part: it carries the film's
 * raw sums and a "rendezvous:part" header (scene_hash, settings, sample range). A part
 * renders samples [sample_offset, sample_offset + samples) of the whole render (session
 * settings "sample_offset", "scene_hash"). rdv_merge_parts adds parts into the image one
 * render of all their samples gives and writes it to output_path (.exr: itself a part,
 * so merges nest; .png through the view). options_json: {"allow_missing": false,
 * "samples": N (the ranges must cover [0, N)), "view": "Standard"}. Fails with a message
 * naming the part: another scene or other settings, overlapping ranges, an unreadable or
 * foreign file, missing ranges (unless allow_missing). out_report (may be NULL; valid
 * until the next call on this thread): JSON {"ranges", "samples", "missing", "warnings"}. */
RDV_API rdv_status rdv_merge_parts(const char *const *paths, uint32_t count, const char *output_path,
                                   const char *options_json, const char **out_report);

#ifdef __cplusplus
}
#endif

#endif /* RENDEZVOUS_H */
