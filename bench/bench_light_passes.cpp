// Benchmark (prints numbers, asserts nothing): what Cycles' light passes cost
// (film/light_passes.h) for path and bdpt, and for the Metropolis integrators (table
// "metropolis": 64 mutations per pixel, bootstrap and pilot included), and BDPT's strategy
// passes (film/strategy_passes.h). Each scene
// renders at a fixed sample count, the passes off and on alternately (5 runs each, the
// film's memory and the median time printed), so that drifts of the machine's speed hit
// both alike.
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

// Renders each scene with each integrator, the passes `settings` ask for off and on alternately.
static void compare(const std::vector<const char *> &scenes, const std::vector<const char *> &integrators,
                    const nlohmann::json &settings, int samples = 16) {
  const int runs = 5;
  std::printf("%-16s %-6s %8s %8s %7s   (%s, %d samples)\n", "scene", "integ", "off s", "on s", "on/off",
              settings.dump().c_str(), samples);
  for (const char *name : scenes) {
    const std::string path = std::string(RDV_SOURCE_DIR) + "/scenes/" + name;
    for (const char *integrator : integrators) {
      nlohmann::json base = {{"integrator", integrator}, {"width", 256}, {"height", 256}, {"samples", samples}, {"seed", 1}};
      nlohmann::json with = base;
      with.update(settings);
      std::vector<double> off, on;
      for (int r = 0; r < runs; ++r) {
        off.push_back(render_seconds(path, base));
        on.push_back(render_seconds(path, with));
      }
      const double a = median(off), b = median(on);
      std::printf("%-16s %-6s %8.3f %8.3f %7.3f\n", name, integrator, a, b, b / a);
      std::fflush(stdout);
    }
  }
}

// bench_light_passes [light] [metropolis] [strategies]: which tables (all by default).
int main(int argc, char **argv) {
  auto wanted = [&](const char *table) {
    if (argc < 2) return true;
    for (int i = 1; i < argc; ++i)
      if (std::string(argv[i]) == table) return true;
    return false;
  };
  std::printf("film memory per pixel: %zu bytes without passes, %zu with light passes, %zu with strategy passes "
              "(max depth 3)\n",
              rdv::Film::bytes_per_pixel(false), rdv::Film::bytes_per_pixel(false, true),
              rdv::Film::bytes_per_pixel(false, false, 3));
  if (wanted("light"))
    compare({"cornell_box.json", "light_types.json", "fog_spot.json"}, {"path", "bdpt"}, {{"light_passes", true}});
  // The Metropolis integrators (light_types has a sun, which mlt does not sample).
  if (wanted("metropolis"))
    compare({"cornell_box.json", "fog_spot.json"}, {"pssmlt", "mmlt", "mlt"}, {{"light_passes", true}}, 64);
  // BDPT's strategy passes (film/strategy_passes.h), 14 passes at the default depth 3.
  if (wanted("strategies"))
    compare({"cornell_box.json", "caustic.json", "fog_spot.json"}, {"bdpt"}, {{"strategy_passes", true}});
  return 0;
}
