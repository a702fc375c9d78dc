// What the benchmarks share: rendering a JSON scene through the C ABI and the
// relative MSE against a reference.
#pragma once
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "film/image_error.h"
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

// Relative MSE (film/image_error.h): mean of (x - ref)^2 / (ref^2 + 1e-2).
inline double rel_mse(const std::vector<float> &x, const std::vector<double> &ref) { return rdv::relative_mse(x, ref); }

// A scene file read for the equal-time benchmarks, and the settings every render of it
// shares (the image `width` wide with the scene's aspect, no sample limit).
struct BenchScene {
  std::string text, base, name;
  json common;
};
inline BenchScene load_bench_scene(const std::string &path, int width) {
  BenchScene b;
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  b.text = ss.str();
  b.base = path.substr(0, path.find_last_of('/'));
  b.name = path.substr(path.find_last_of('/') + 1);
  json doc = json::parse(b.text);
  double aspect = double(doc["settings"].value("height", 480)) / doc["settings"].value("width", 640);
  int height = std::max(1, int(std::lround(width * aspect)));
  b.common = {{"width", width}, {"height", height}, {"samples", 0}, {"threads", 0}};
  return b;
}

// The reference of the equal-time benchmarks: the mean of two independent BDPT renders of
// `seconds` each, and its own noise (relMSE(a, b) ~ 2 var_single; the mean's own error is
// var_single / 2 = relMSE(a, b) / 4), which every figure against it contains. With a
// cache directory the reference is kept in a file named by scene, width and seconds, so
// repeated benchmark runs share one long reference.
struct Reference {
  std::vector<double> image;
  double noise = 0;
  uint32_t spp_a = 0, spp_b = 0;
  Render a, b;  // the two renders (empty when read from the cache)
};
inline Reference bdpt_reference(const BenchScene &scene, double seconds, const std::string &cache_dir = "") {
  Reference r;
  const std::string cache = cache_dir.empty() ? "" : cache_dir + "/" + scene.name + "-w" +
                                                         std::to_string(scene.common["width"].get<int>()) + "-" +
                                                         std::to_string(int(seconds)) + "s.ref";
  if (!cache.empty()) {
    std::ifstream in(cache, std::ios::binary);
    uint64_t n = 0;
    if (in.read(reinterpret_cast<char *>(&n), sizeof n)) {
      r.image.resize(n);
      in.read(reinterpret_cast<char *>(&r.noise), sizeof r.noise);
      in.read(reinterpret_cast<char *>(&r.spp_a), sizeof r.spp_a);
      in.read(reinterpret_cast<char *>(&r.spp_b), sizeof r.spp_b);
      if (in.read(reinterpret_cast<char *>(r.image.data()), std::streamsize(n * sizeof(double)))) return r;
    }
  }
  json s = scene.common;
  s["integrator"] = "bdpt";
  s["time_limit"] = seconds;
  s["seed"] = 9001;
  const Render &a = r.a = render(scene.text, scene.base, s);
  s["seed"] = 9002;
  const Render &b = r.b = render(scene.text, scene.base, s);
  r.image.resize(a.rgb.size());
  for (size_t i = 0; i < r.image.size(); ++i) r.image[i] = 0.5 * (double(a.rgb[i]) + b.rgb[i]);
  std::vector<double> ad(a.rgb.begin(), a.rgb.end());
  r.noise = rel_mse(b.rgb, ad) / 4;
  r.spp_a = a.progress.samples_done;
  r.spp_b = b.progress.samples_done;
  if (!cache.empty()) {
    std::ofstream out(cache, std::ios::binary);
    uint64_t n = r.image.size();
    out.write(reinterpret_cast<const char *>(&n), sizeof n);
    out.write(reinterpret_cast<const char *>(&r.noise), sizeof r.noise);
    out.write(reinterpret_cast<const char *>(&r.spp_a), sizeof r.spp_a);
    out.write(reinterpret_cast<const char *>(&r.spp_b), sizeof r.spp_b);
    out.write(reinterpret_cast<const char *>(r.image.data()), std::streamsize(n * sizeof(double)));
  }
  return r;
}

}  // namespace rdv_bench
