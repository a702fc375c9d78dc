// What the benchmarks share: rendering a JSON scene through the C ABI and the
// relative MSE against a reference.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "rendezvous.h"
#include "scene_file.h"

namespace rdv_bench {

using nlohmann::json;

struct Render {
  std::vector<float> rgb;
  rdv_progress progress{};
  json stats;  // rdv_session_stats: the integrator's own figures
};

inline Render render(const std::string &scene_text, const std::string &base, json settings) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  auto loaded = rdv_tools::load_scene_json(scene_text, base, scene);
  json s = json::parse(loaded.settings_json);
  s.update(settings);
  rdv_session *session = nullptr;
  Render r;
  if (rdv_session_create(scene, s.dump().c_str(), &session) != RDV_OK) {
    std::fprintf(stderr, "bench: %s\n", rdv_last_error());
    std::exit(1);
  }
  rdv_session_start(session);
  rdv_session_wait(session);
  rdv_session_progress(session, &r.progress);
  const char *stats = nullptr;
  if (rdv_session_stats(session, &stats) == RDV_OK && stats) r.stats = json::parse(stats);
  int w = s["width"], h = s["height"];
  std::vector<float> rgba(size_t(w) * h * 4);
  rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, w, h, 1, rgba.data());
  r.rgb.resize(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int c = 0; c < 3; ++c) r.rgb[3 * i + c] = rgba[4 * i + c];
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
  return r;
}

// Relative MSE (pbrt / Mitsuba convention): mean of (x - ref)^2 / (ref^2 + 1e-2).
inline double rel_mse(const std::vector<float> &x, const std::vector<double> &ref) {
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += (x[i] - ref[i]) * (x[i] - ref[i]) / (ref[i] * ref[i] + 1e-2);
  return s / x.size();
}

}  // namespace rdv_bench
