// What the benchmarks share: rendering a JSON scene through the C ABI and the
// relative MSE against a reference (engine/tools/equal_time.h, which `rendezvous study`
// uses too).
#pragma once
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "equal_time.h"
#include "film/image_error.h"
#include "rendezvous.h"

namespace rdv_bench {

using nlohmann::json;
using Render = rdv_tools::TimedRender;
using BenchScene = rdv_tools::EqualTimeScene;
using Reference = rdv_tools::Reference;

// A benchmark that cannot render has nothing to print: it stops with the engine's message.
inline Render render(const std::string &scene_text, const std::string &base, const json &settings) {
  try {
    return rdv_tools::render_text(scene_text, base, settings);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench: %s\n", e.what());
    std::exit(1);
  }
}

// Relative MSE (film/image_error.h): mean of (x - ref)^2 / (ref^2 + 1e-2).
inline double rel_mse(const std::vector<float> &x, const std::vector<double> &ref) { return rdv::relative_mse(x, ref); }

// The scene `width` wide with its aspect, no sample limit (rdv_tools::load_equal_time_scene).
inline BenchScene load_bench_scene(const std::string &path, int width) {
  try {
    return rdv_tools::load_equal_time_scene(path, width);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench: %s\n", e.what());
    std::exit(1);
  }
}

// The benchmarks' reference: two independent BDPT renders of `seconds` each; with a cache
// directory kept in a file keyed by the scene's bytes and these settings.
inline Reference bdpt_reference(const BenchScene &scene, double seconds, const std::string &cache_dir = "") {
  try {
    rdv_tools::EngineScene loaded(scene);
    return rdv_tools::make_reference(scene, loaded.get(), {"bdpt", 2 * seconds, cache_dir});
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench: %s\n", e.what());
    std::exit(1);
  }
}

}  // namespace rdv_bench
