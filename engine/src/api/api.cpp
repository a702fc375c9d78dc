// The C ABI boundary: every entry point catches everything, so no C++ exception
// ever reaches the caller (Blender's process); failures become a status code plus
// a thread-local message for rdv_last_error().
#include <atomic>
#include <memory>
#include <new>
#include <string>
#include <vector>
#include "core/error.h"
#include "core/log.h"
#include "film/image_output.h"
#include "film/render_part.h"
#include "render/session.h"
#include "api/handles.h"
#include "rendezvous.h"


namespace {

thread_local std::string g_last_error;
std::atomic<uint32_t> g_live_scenes{0}, g_live_sessions{0};

template <class F>
rdv_status guarded(F &&body) {
  try {
    g_last_error.clear();
    body();
    return RDV_OK;
  } catch (const rdv::Error &e) {
    g_last_error = e.what();
    return e.status;
  } catch (const std::bad_alloc &) {
    g_last_error = "out of memory";
    return RDV_ERROR_INTERNAL;
  } catch (const std::exception &e) {
    g_last_error = std::string("internal error: ") + e.what();
    return RDV_ERROR_INTERNAL;
  } catch (...) {
    g_last_error = "internal error: unknown exception";
    return RDV_ERROR_INTERNAL;
  }
}

void require(const void *p, const char *what) {
  if (!p) rdv::fail(std::string(what) + " is NULL");
}

std::string name_or(const char *name, const char *fallback) { return name && *name ? name : fallback; }

rdv::Scene &editable(rdv_scene *s) {
  require(s, "scene");
  if (s->scene.use_count() > 1)
    rdv::fail("scene: cannot be edited while a render session uses it (destroy the session first)", RDV_ERROR_STATE);
  return *s->scene;
}

}  // namespace

extern "C" {

int rdv_api_version(void) { return RDV_API_VERSION; }
const char *rdv_last_error(void) { return g_last_error.c_str(); }

rdv_status rdv_live_objects(uint32_t *out_scenes, uint32_t *out_sessions) {
  if (out_scenes) *out_scenes = g_live_scenes.load();
  if (out_sessions) *out_sessions = g_live_sessions.load();
  return RDV_OK;
}

rdv_status rdv_scene_create(rdv_scene **out) {
  return guarded([&] {
    require(out, "out_scene");
    *out = nullptr;
    auto s = std::make_unique<rdv_scene>();
    s->scene = std::make_shared<rdv::Scene>();
    *out = s.release();
    ++g_live_scenes;
  });
}

rdv_status rdv_scene_destroy(rdv_scene *scene) {
  return guarded([&] {
    if (scene) --g_live_scenes;
    delete scene;  // a live session keeps its own reference
  });
}

rdv_status rdv_scene_set_material(rdv_scene *s, uint32_t material, const char *params) {
  return guarded([&] {
    rdv::Params p(params ? params : "", "material " + std::to_string(material));
    editable(s).set_material(material, p);
  });
}

rdv_status rdv_scene_set_mesh(rdv_scene *s, uint32_t mesh, const float *positions, uint32_t num_vertices,
                              const float *normals, const float *uvs, const uint32_t *indices,
                              uint32_t num_triangles, const uint32_t *material_ids, uint32_t default_material) {
  return guarded([&] {
    editable(s).set_mesh(mesh, positions, num_vertices, normals, uvs, indices, num_triangles, material_ids,
                         default_material);
  });
}

rdv_status rdv_scene_set_light(rdv_scene *s, uint32_t light, const char *params) {
  return guarded([&] {
    rdv::Params p(params ? params : "", "light " + std::to_string(light));
    editable(s).set_light(light, p);
  });
}

rdv_status rdv_scene_add_material(rdv_scene *s, const char *name, const char *params, uint32_t *out) {
  return guarded([&] {
    std::string n = name_or(name, "unnamed");
    rdv::Params p(params ? params : "", "material '" + n + "'");
    uint32_t id = editable(s).add_material(n, p);
    if (out) *out = id;
  });
}

rdv_status rdv_scene_add_grid(rdv_scene *s, const char *name, const float *values, uint32_t nx, uint32_t ny,
                              uint32_t nz, uint32_t *out) {
  return guarded([&] {
    require(name, "name");
    uint32_t id = editable(s).add_grid(name, values, nx, ny, nz);
    if (out) *out = id;
  });
}

rdv_status rdv_scene_add_image(rdv_scene *s, const char *name, const float *pixels, uint32_t width, uint32_t height,
                               uint32_t channels, const char *colorspace, uint32_t *out) {
  return guarded([&] {
    require(name, "name");
    uint32_t id = editable(s).add_image(name, pixels, width, height, channels, colorspace ? colorspace : "");
    if (out) *out = id;
  });
}

rdv_status rdv_scene_add_mesh(rdv_scene *s, const char *name, const float *positions, uint32_t num_vertices,
                              const float *normals, const float *uvs, const uint32_t *indices,
                              uint32_t num_triangles, const uint32_t *material_ids, uint32_t default_material,
                              uint32_t *out) {
  return guarded([&] {
    uint32_t id = editable(s).add_mesh(name_or(name, "unnamed"), positions, num_vertices, normals, uvs, indices,
                                       num_triangles, material_ids, default_material);
    if (out) *out = id;
  });
}

rdv_status rdv_scene_add_mesh_attribute(rdv_scene *s, uint32_t mesh, const char *name, const char *kind,
                                        const float *data, uint32_t num_components, uint32_t num_vertices) {
  return guarded([&] {
    editable(s).add_mesh_attribute(mesh, name ? name : "", kind ? kind : "", data, num_components, num_vertices);
  });
}

rdv_status rdv_scene_add_instance(rdv_scene *s, uint32_t mesh, const float transform[16], uint32_t *out) {
  return guarded([&] {
    require(transform, "transform");
    uint32_t id = editable(s).add_instance(mesh, rdv::Transform::from_row_major(transform));
    if (out) *out = id;
  });
}

rdv_status rdv_scene_set_instance_transform(rdv_scene *s, uint32_t instance, const float transform[16]) {
  return guarded([&] {
    require(transform, "transform");
    editable(s).set_instance_transform(instance, rdv::Transform::from_row_major(transform));
  });
}

rdv_status rdv_scene_set_instance_motion(rdv_scene *s, uint32_t instance, const float *transforms, uint32_t num_steps) {
  return guarded([&] {
    if (num_steps > 0) require(transforms, "transforms");
    if (num_steps > rdv::Scene::kMaxMotionSteps)  // before anything is allocated for them
      rdv::fail("instance " + std::to_string(instance) + ": " + std::to_string(num_steps) + " motion steps; at most " +
                    std::to_string(rdv::Scene::kMaxMotionSteps),
                RDV_ERROR_LIMIT);
    std::vector<rdv::Transform> steps(num_steps);
    for (uint32_t k = 0; k < num_steps; ++k) steps[k] = rdv::Transform::from_row_major(transforms + 16 * size_t(k));
    editable(s).set_instance_motion(instance, steps);
  });
}

rdv_status rdv_scene_set_mesh_motion(rdv_scene *s, uint32_t mesh, const float *positions, const float *normals,
                                     uint32_t num_vertices, uint32_t num_steps) {
  return guarded([&] { editable(s).set_mesh_motion(mesh, positions, normals, num_vertices, num_steps); });
}

rdv_status rdv_scene_set_instance_params(rdv_scene *s, uint32_t instance, const char *params) {
  return guarded([&] {
    rdv::Scene &scene = editable(s);
    rdv::Params p(params ? params : "", scene.instance_description(instance));
    scene.set_instance_params(instance, p);
  });
}

rdv_status rdv_scene_add_light(rdv_scene *s, const char *name, const char *params, uint32_t *out) {
  return guarded([&] {
    std::string n = name_or(name, "unnamed");
    rdv::Params p(params ? params : "", "light '" + n + "'");
    uint32_t id = editable(s).add_light(n, p);
    if (out) *out = id;
  });
}

rdv_status rdv_scene_set_world(rdv_scene *s, const char *params) {
  return guarded([&] {
    rdv::Params p(params ? params : "", "world");
    editable(s).set_world(p);
  });
}

rdv_status rdv_scene_set_camera(rdv_scene *s, const char *params) {
  return guarded([&] {
    rdv::Params p(params ? params : "", "camera");
    editable(s).set_camera(p);
  });
}

rdv_status rdv_scene_commit(rdv_scene *s) {
  return guarded([&] { editable(s).commit(); });
}

rdv_status rdv_scene_messages(rdv_scene *s, const char **out) {
  return guarded([&] {
    require(s, "scene");
    require(out, "out_text");
    s->text = s->scene->messages();
    *out = s->text.c_str();
  });
}

rdv_status rdv_scene_summary(rdv_scene *s, const char **out) {
  return guarded([&] {
    require(s, "scene");
    require(out, "out_json");
    s->text = s->scene->summary_json();
    *out = s->text.c_str();
  });
}

rdv_status rdv_session_create(rdv_scene *s, const char *settings, rdv_session **out) {
  return guarded([&] {
    require(s, "scene");
    require(out, "out_session");
    *out = nullptr;
    rdv::Params p(settings ? settings : "", "render settings");
    rdv::RenderSettings rs = rdv::RenderSettings::from_params(p);
    editable(s);  // no other session may be rendering this scene
    auto sess = std::make_unique<rdv_session>();
    sess->session = std::make_unique<rdv::Session>(s->scene, rs);
    *out = sess.release();
    ++g_live_sessions;
  });
}

rdv_status rdv_session_start(rdv_session *s) {
  return guarded([&] {
    require(s, "session");
    s->session->start();
  });
}

rdv_status rdv_session_wait(rdv_session *s) {
  return guarded([&] {
    require(s, "session");
    s->session->wait();
  });
}

rdv_status rdv_session_cancel(rdv_session *s) {
  return guarded([&] {
    require(s, "session");
    s->session->cancel();
  });
}

rdv_status rdv_session_destroy(rdv_session *s) {
  return guarded([&] {
    if (s) --g_live_sessions;
    delete s;
  });
}

rdv_status rdv_session_progress(rdv_session *s, rdv_progress *out) {
  return guarded([&] {
    require(s, "session");
    require(out, "out_progress");
    rdv::Progress p = s->session->progress();
    out->samples_done = p.samples_done;
    out->samples_target = p.samples_target;
    out->elapsed_seconds = p.elapsed;
    out->time_limit_seconds = p.time_limit;
    out->fraction_done = p.fraction;
    out->rays_traced = p.rays;
    out->rays_per_second = p.rays_per_second;
    out->samples_dropped = p.dropped;
    out->finished = p.finished;
    out->cancelled = p.cancelled;
    out->noise_estimate = p.noise_estimate;
    out->noise_target = p.noise_target;
    out->noise_reached = p.noise_reached;
  });
}

rdv_status rdv_session_stats(rdv_session *s, const char **out) {
  return guarded([&] {
    require(s, "session");
    require(out, "out_json");
    s->text = s->session->stats_json();
    *out = s->text.c_str();
  });
}

int rdv_pass_channels(rdv_pass pass) {
  switch (pass) {
    case RDV_PASS_COMBINED: return 4;
    case RDV_PASS_DEPTH: return 1;
    case RDV_PASS_NORMAL: return 3;
    case RDV_PASS_ALBEDO: return 3;
    case RDV_PASS_NOISE: return 1;
    case RDV_PASS_MIST:
    case RDV_PASS_OBJECT_INDEX:
    case RDV_PASS_MATERIAL_INDEX: return 1;
    case RDV_PASS_DENOISING_NORMAL:
    case RDV_PASS_DENOISING_ALBEDO: return 3;
    case RDV_PASS_DENOISING_DEPTH: return 1;
    case RDV_PASS_SHADOW_CATCHER: return 3;
    case RDV_PASS_SHADOW_CATCHER_MATTE: return 4;
    case RDV_PASS_EMISSION:
    case RDV_PASS_ENVIRONMENT:
    case RDV_PASS_DIFFUSE_DIRECT:
    case RDV_PASS_DIFFUSE_INDIRECT:
    case RDV_PASS_DIFFUSE_COLOR:
    case RDV_PASS_GLOSSY_DIRECT:
    case RDV_PASS_GLOSSY_INDIRECT:
    case RDV_PASS_GLOSSY_COLOR:
    case RDV_PASS_TRANSMISSION_DIRECT:
    case RDV_PASS_TRANSMISSION_INDIRECT:
    case RDV_PASS_TRANSMISSION_COLOR:
    case RDV_PASS_VOLUME_DIRECT:
    case RDV_PASS_VOLUME_INDIRECT: return 3;
    default: break;
  }
  if (pass >= RDV_PASS_AOV_COLOR_FIRST && pass <= RDV_PASS_AOV_COLOR_LAST) return 4;
  if (pass >= RDV_PASS_AOV_VALUE_FIRST && pass <= RDV_PASS_AOV_VALUE_LAST) return 1;
  if (pass >= RDV_PASS_CRYPTOMATTE_FIRST && pass <= RDV_PASS_CRYPTOMATTE_LAST) return 4;
  return pass >= RDV_PASS_STRATEGY_FIRST && pass <= RDV_PASS_STRATEGY_LAST ? 3 : 0;
}

rdv_status rdv_session_read_film(rdv_session *s, rdv_pass pass, uint32_t x, uint32_t y, uint32_t w, uint32_t h,
                                 int32_t top_down, float *out) {
  return guarded([&] {
    require(s, "session");
    require(out, "out");
    if (rdv_pass_channels(pass) == 0) rdv::fail("read_film: unknown pass " + std::to_string(int(pass)));
    const rdv::Film &film = s->session->film();
    if (uint64_t(x) + w > uint64_t(film.width()) || uint64_t(y) + h > uint64_t(film.height()))
      rdv::fail("read_film: rectangle " + std::to_string(x) + "," + std::to_string(y) + " " + std::to_string(w) +
                "x" + std::to_string(h) + " lies outside the " + std::to_string(film.width()) + "x" +
                std::to_string(film.height()) + " image");
    film.read(pass, int(x), int(y), int(w), int(h), top_down != 0, out);
  });
}

rdv_status rdv_session_write_image(rdv_session *s, const char *path, const char *view) {
  return guarded([&] {
    require(s, "session");
    require(path, "path");
    const rdv::PartRecord part = s->session->part_record();
    std::string warning = rdv::write_image(s->session->film(), path, view ? view : "Standard", &part);
    if (!warning.empty()) rdv::log_warning(warning);
  });
}

rdv_status rdv_merge_parts(const char *const *paths, uint32_t count, const char *output_path, const char *options_json,
                           const char **out_report) {
  return guarded([&] {
    if (count == 0) rdv::fail("merge: no parts given");
    require(paths, "paths");
    require(output_path, "output_path");
    thread_local std::string report;
    if (out_report) *out_report = "";
    std::vector<std::string> files;
    for (uint32_t i = 0; i < count; ++i) {
      require(paths[i], "paths[i]");
      files.push_back(paths[i]);
    }
    rdv::Params p(options_json ? options_json : "", "merge options");
    rdv::MergeOptions options;
    options.allow_missing = p.get_bool("allow_missing", false);
    int expected = p.get_int("samples", 0);
    if (expected < 0) rdv::fail("merge options: 'samples' must not be negative");
    options.expected_samples = uint64_t(expected);
    std::string view = p.get_string("view", "Standard");
    p.check_all_used();
    rdv::MergeResult merged = rdv::merge_parts(files, options);
    std::string warning = rdv::write_image(*merged.film, output_path, view, &merged.record);
    if (!warning.empty()) merged.warnings.push_back(warning);
    report = merged.report_json();
    if (out_report) *out_report = report.c_str();
  });
}

}  // extern "C"
