// Rendering a scene through the public C ABI, as the add-on and the CLI do, and
// simple statistics on the result.
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "rendezvous.h"
#include "scene_file.h"

namespace rdv::test {

// A scene made through the C ABI, destroyed with the test.
struct SceneHandle {
  rdv_scene *s = nullptr;
  SceneHandle() { rdv_scene_create(&s); }
  ~SceneHandle() { rdv_scene_destroy(s); }
  SceneHandle(const SceneHandle &) = delete;
  SceneHandle &operator=(const SceneHandle &) = delete;
};

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;  // top-down
  std::vector<float> noise; // the Noise pass (estimated relative error per pixel), top-down
  std::string warnings;     // scene messages + loader problems
  rdv_progress progress{};
  std::string stats;        // rdv_session_stats (the integrator's own figures)
  // Light passes (settings "light_passes"), by rdv_pass - RDV_PASS_EMISSION: 3 floats per
  // pixel, top-down; empty without them.
  std::vector<std::vector<float>> light_passes;
  // BDPT's strategy passes (settings "strategy_passes"), by rdv_pass - RDV_PASS_STRATEGY_FIRST
  // over the whole range (passes beyond the session's read as zeros): 3 floats per pixel,
  // top-down; empty without them.
  std::vector<std::vector<float>> strategy_passes;
  const float *strategy_pass(int k, int x, int y) const {
    return &strategy_passes[size_t(k)][(size_t(y) * width + x) * 3];
  }
  // Data passes (film/data_passes.h): Mist, Object Index, Material Index, top-down; the
  // Normal pass, 3 floats per pixel.
  std::vector<float> mist, object_index, material_index, normal;
  // Denoising data (settings "denoising_passes"; film/denoising_passes.h), top-down: Normal
  // and Albedo 3 floats per pixel, Depth 1; empty without them.
  std::vector<float> denoising_normal, denoising_albedo, denoising_depth;
  // Shadow catchers (film/shadow_catcher_passes.h), top-down: the Shadow Catcher pass, 3
  // floats per pixel, and the matte, RGBA.
  std::vector<float> shadow_catcher, shadow_catcher_matte;
  // Shader AOVs (settings "aovs"; film/shader_aovs.h), in the settings' order, top-down: a
  // colour pass 4 floats per pixel, a value pass 1; empty without them.
  std::vector<std::vector<float>> shader_aovs;
  // Cryptomatte (settings "cryptomatte"; film/cryptomatte.h), by rdv_pass -
  // RDV_PASS_CRYPTOMATTE_FIRST over the whole range: 4 floats per pixel, top-down; empty without it.
  std::vector<std::vector<float>> cryptomatte;
  const float *crypto_pass(int kind, int k, int x, int y) const {
    return &cryptomatte[size_t(kind * 8 + k)][(size_t(y) * width + x) * 4];
  }
  const float *light_pass(rdv_pass pass, int x, int y) const {
    return &light_passes[size_t(pass - RDV_PASS_EMISSION)][(size_t(y) * width + x) * 3];
  }
  float luminance(int x, int y) const {
    const float *p = &rgba[(size_t(y) * width + x) * 4];
    return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
  }
  float channel_mean(int c) const {
    double s = 0;
    for (int i = 0; i < width * height; ++i) s += rgba[size_t(i) * 4 + c];
    return float(s / (width * height));
  }
  bool all_finite() const;
};

// Renders JSON scene text; settings_override is merged into the scene's settings.
Image render_json(const std::string &scene_json, const std::string &settings_override = "{}");
Image render_file(const std::string &path, const std::string &settings_override = "{}");
// render_json after prepare(scene) on the empty scene (e.g. rdv_scene_add_grid).
Image render_json_prepared(const std::function<void(rdv_scene *)> &prepare, const std::string &scene_json,
                           const std::string &settings_override = "{}");

// K renders of the scene with seeds seed0, seed0 + 1, ... (settings merged into the
// scene's, "seed" set per run), each as per-pixel R + G + B, row-major: the input of
// compare_blocks (statistics.h). Expects every image finite with no dropped sample.
std::vector<std::vector<double>> seeded_renders(const std::string &scene_json, const std::string &settings, int runs,
                                                uint32_t seed0);
// The same, rendered once per process for each (scene, settings, runs, seed0): a reference
// that several comparisons share (renders with fixed seeds are deterministic).
const std::vector<std::vector<double>> &seeded_renders_once(const std::string &scene_json, const std::string &settings,
                                                            int runs, uint32_t seed0);

// Path tracing (32 spp) and BDPT (16 spp) render the scene at 32 x 32 six times each with
// their own seeds: every 8x8 block must agree by Welch's t-test (1% false-alarm rate for the 16
// blocks, Sidak-corrected) and the means within |z| < 3.3 (1e-3); prints "[ what ]" and the
// BDPT / path ratio. For emitters every integrator must evaluate alike.
void expect_small_bdpt_matches_path(const nlohmann::json &scene, const std::string &what);

// Mean and standard error of the per-pixel means (pixels are independent estimates).
struct MeanEstimate { double mean, standard_error; };
MeanEstimate pixel_mean(const Image &img, int channel);

std::string source_path(const std::string &relative);  // RDV_SOURCE_DIR + relative
nlohmann::json load_scene(const std::string &name);     // scenes/<name>, parsed

// Creates, starts and waits for a session on the scene: the first failed status (its
// message in rdv_last_error), or RDV_OK. For tests of what a session refuses.
rdv_status session_status(rdv_scene *scene, const std::string &settings);

// A path for a file a test writes, in a directory of this process's own: ctest runs
// test processes in parallel, and two that wrote the same name in a shared directory
// would read each other's half-written files.
std::string temp_path(const std::string &name);

}  // namespace rdv::test
