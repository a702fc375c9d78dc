// Benchmark (prints numbers, asserts nothing): what Cycles' light passes cost
// (film/light_passes.h). Each scene renders with path tracing and BDPT at a fixed sample
// count, the light passes off and on alternately (5 runs each, the film's memory and the
// median time printed), so that drifts of the machine's speed hit both alike.
// Goal: on < 1.10x off. A render without them computes and stores nothing of them.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "film/film.h"
#include "rendezvous.h"
#include "scene_file.h"

using Clock = std::chrono::steady_clock;

static double render_seconds(const std::string &path, const nlohmann::json &overrides) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  rdv_tools::LoadedScene loaded = rdv_tools::load_scene_file(path, scene);
  nlohmann::json settings = nlohmann::json::parse(loaded.settings_json);
  settings.update(overrides);
  rdv_session *session = nullptr;
  if (rdv_session_create(scene, settings.dump().c_str(), &session) != RDV_OK) {
    std::fprintf(stderr, "bench: %s\n", rdv_last_error());
    std::exit(1);
  }
  rdv_scene_commit(scene);  // not timed: the scene is the same with and without passes
  auto start = Clock::now();
  rdv_session_start(session);
  rdv_session_wait(session);
  double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
  return seconds;
}

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main() {
  const int runs = 5;
  std::printf("film memory per pixel: %zu bytes without light passes, %zu with\n", rdv::Film::bytes_per_pixel(false),
              rdv::Film::bytes_per_pixel(false, true));
  std::printf("%-16s %-5s %8s %8s %7s\n", "scene", "integ", "off s", "on s", "on/off");
  for (const char *name : {"cornell_box.json", "light_types.json", "fog_spot.json"}) {
    const std::string path = std::string(RDV_SOURCE_DIR) + "/scenes/" + name;
    for (const char *integrator : {"path", "bdpt"}) {
      nlohmann::json base = {{"integrator", integrator}, {"width", 256}, {"height", 256}, {"samples", 16}, {"seed", 1}};
      std::vector<double> off, on;
      for (int r = 0; r < runs; ++r) {
        nlohmann::json with = base;
        with["light_passes"] = true;
        off.push_back(render_seconds(path, base));
        on.push_back(render_seconds(path, with));
      }
      const double a = median(off), b = median(on);
      std::printf("%-16s %-5s %8.3f %8.3f %7.3f\n", name, integrator, a, b, b / a);
      std::fflush(stdout);
    }
  }
  return 0;
}
