// Renders for equal-time comparisons (`rendezvous study`, the benchmarks): a JSON scene
// rendered through the C ABI with a time limit, and a long reference image to measure
// relative MSE against, kept in a cache keyed by the scene's bytes and the reference's
// settings, so a changed scene or other settings make a new one.
#pragma once
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "rendezvous.h"

namespace rdv_tools {

// FNV-1a (64 bits) of some bytes, as 16 hex digits: names scenes in render parts and
// reference caches.
std::string content_hash(const std::string &bytes);

// A scene file read for equal-time renders, and the settings every render of it shares:
// the image `width` wide with the scene's aspect, no sample limit, all cores.
struct EqualTimeScene {
  std::string path, text, base, name;  // name: the file name without ".json"
  nlohmann::json common;
};
// Throws std::runtime_error naming the file when it cannot be read or is not JSON.
EqualTimeScene load_equal_time_scene(const std::string &path, int width);

struct TimedRender {
  std::vector<float> rgb;  // width x height x 3, linear
  rdv_progress progress{};
  nlohmann::json stats;  // rdv_session_stats: the integrator's own figures
};

// The settings of one render of `scene`: the file's settings, then the shared ones,
// then `overrides`.
nlohmann::json render_settings(const EqualTimeScene &scene, const nlohmann::json &overrides);

// Called about ten times a second while a render runs.
using RenderProgress = std::function<void(const rdv_progress &)>;

// Renders `scene` (already loaded) with the scene file's settings updated by `settings`.
// Throws std::runtime_error with the engine's message when the session fails.
TimedRender render_loaded(rdv_scene *scene, const nlohmann::json &settings, const RenderProgress &progress = {});
// Loads the scene text (warnings ignored) and renders it.
TimedRender render_text(const std::string &text, const std::string &base, const nlohmann::json &settings,
                        const RenderProgress &progress = {});

// The reference: the mean m of two independent renders a, b (seeds 9001, 9002) of half
// the seconds each, and its own noise, which every figure measured against it contains:
// the mean's error var_single / 2, estimated as relMSE(a, m) (E(a - m)^2 = var_single / 2).
struct Reference {
  std::vector<double> image;
  double noise = 0;
  uint32_t spp_a = 0, spp_b = 0;
  std::string integrator, cache_file;  // cache_file: where it is kept ("" = not kept)
  bool from_cache = false;
  TimedRender a, b;  // the two renders (empty when read from the cache)
};
struct ReferenceRequest {
  std::string integrator = "bdpt";
  double seconds = 60;    // both halves together
  std::string cache_dir;  // "" = no cache
};
// `progress` gets each half's progress and which half (0, 1).
Reference make_reference(const EqualTimeScene &scene, rdv_scene *loaded, const ReferenceRequest &request,
                         const std::function<void(int, const rdv_progress &)> &progress = {});
// The cache file a request maps to (scene name, then the hash of the scene's bytes and
// the reference's settings).
std::string reference_cache_file(const EqualTimeScene &scene, const ReferenceRequest &request);

// An engine scene loaded from `scene`'s text, destroyed with the object. Throws
// std::runtime_error naming the file when the scene cannot be created.
class EngineScene {
 public:
  explicit EngineScene(const EqualTimeScene &scene);
  ~EngineScene();
  EngineScene(const EngineScene &) = delete;
  EngineScene &operator=(const EngineScene &) = delete;
  rdv_scene *get() const { return scene_; }
  const std::vector<std::string> &problems() const { return problems_; }

 private:
  rdv_scene *scene_ = nullptr;
  std::vector<std::string> problems_;
};

}  // namespace rdv_tools
