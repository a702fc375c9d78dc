#include "render_helpers.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <unistd.h>
#include "statistics.h"

namespace rdv::test {

bool Image::all_finite() const {
  for (float v : rgba)
    if (!std::isfinite(v)) return false;
  return true;
}

static Image render_scene(rdv_scene *scene, const rdv_tools::LoadedScene &loaded, const std::string &override_json) {
  Image img;
  for (const auto &p : loaded.problems) img.warnings += p + "\n";
  nlohmann::json settings = nlohmann::json::parse(loaded.settings_json);
  settings.update(nlohmann::json::parse(override_json));
  rdv_session *session = nullptr;
  if (rdv_session_create(scene, settings.dump().c_str(), &session) != RDV_OK)
    throw std::runtime_error(std::string("session: ") + rdv_last_error());
  const char *text = nullptr;
  if (rdv_scene_messages(scene, &text) == RDV_OK && text) img.warnings += text;
  rdv_session_start(session);
  rdv_session_wait(session);
  rdv_session_progress(session, &img.progress);
  if (rdv_session_stats(session, &text) == RDV_OK && text) img.stats = text;
  img.width = settings.value("width", 640);
  img.height = settings.value("height", 480);
  img.rgba.resize(size_t(img.width) * img.height * 4);
  if (rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, img.width, img.height, 1, img.rgba.data()) != RDV_OK)
    throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
  img.noise.resize(size_t(img.width) * img.height);
  if (rdv_session_read_film(session, RDV_PASS_NOISE, 0, 0, img.width, img.height, 1, img.noise.data()) != RDV_OK)
    throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
  for (auto [pass, out] : {std::pair{RDV_PASS_MIST, &img.mist}, std::pair{RDV_PASS_OBJECT_INDEX, &img.object_index},
                           std::pair{RDV_PASS_MATERIAL_INDEX, &img.material_index}}) {
    out->resize(size_t(img.width) * img.height);
    if (rdv_session_read_film(session, pass, 0, 0, img.width, img.height, 1, out->data()) != RDV_OK)
      throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
  }
  img.normal.resize(size_t(img.width) * img.height * 3);
  if (rdv_session_read_film(session, RDV_PASS_NORMAL, 0, 0, img.width, img.height, 1, img.normal.data()) != RDV_OK)
    throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
  if (settings.value("denoising_passes", false))
    for (auto [pass, out] : {std::pair{RDV_PASS_DENOISING_NORMAL, &img.denoising_normal},
                             std::pair{RDV_PASS_DENOISING_ALBEDO, &img.denoising_albedo},
                             std::pair{RDV_PASS_DENOISING_DEPTH, &img.denoising_depth}}) {
      out->resize(size_t(img.width) * img.height * size_t(rdv_pass_channels(pass)));
      if (rdv_session_read_film(session, pass, 0, 0, img.width, img.height, 1, out->data()) != RDV_OK)
        throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
    }
  // Shadow catchers: read from every session (1 and zeros without a catcher).
  for (auto [pass, out] : {std::pair{RDV_PASS_SHADOW_CATCHER, &img.shadow_catcher},
                           std::pair{RDV_PASS_SHADOW_CATCHER_MATTE, &img.shadow_catcher_matte}}) {
    out->resize(size_t(img.width) * img.height * size_t(rdv_pass_channels(pass)));
    if (rdv_session_read_film(session, pass, 0, 0, img.width, img.height, 1, out->data()) != RDV_OK)
      throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
  }
  if (settings.contains("aovs"))
    for (size_t k = 0; k < settings["aovs"].size(); ++k) {
      const bool color = settings["aovs"][k].value("type", std::string("color")) == "color";
      const rdv_pass pass = rdv_pass((color ? RDV_PASS_AOV_COLOR_FIRST : RDV_PASS_AOV_VALUE_FIRST) + int(k));
      std::vector<float> &out = img.shader_aovs.emplace_back(size_t(img.width) * img.height * (color ? 4 : 1));
      if (rdv_session_read_film(session, pass, 0, 0, img.width, img.height, 1, out.data()) != RDV_OK)
        throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
    }
  if (settings.contains("cryptomatte"))
    for (int pass = RDV_PASS_CRYPTOMATTE_FIRST; pass <= RDV_PASS_CRYPTOMATTE_LAST; ++pass) {
      std::vector<float> &out = img.cryptomatte.emplace_back(size_t(img.width) * img.height * 4);
      if (rdv_session_read_film(session, rdv_pass(pass), 0, 0, img.width, img.height, 1, out.data()) != RDV_OK)
        throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
    }
  // The 3-float passes of [first, last] a setting asks for.
  auto read_passes = [&](const char *setting, int first, int last, std::vector<std::vector<float>> &passes) {
    if (!settings.value(setting, false)) return;
    for (int pass = first; pass <= last; ++pass) {
      std::vector<float> &out = passes.emplace_back(size_t(img.width) * img.height * 3);
      if (rdv_session_read_film(session, rdv_pass(pass), 0, 0, img.width, img.height, 1, out.data()) != RDV_OK)
        throw std::runtime_error(std::string("read_film: ") + rdv_last_error());
    }
  };
  read_passes("light_passes", RDV_PASS_EMISSION, RDV_PASS_VOLUME_INDIRECT, img.light_passes);
  read_passes("strategy_passes", RDV_PASS_STRATEGY_FIRST, RDV_PASS_STRATEGY_LAST, img.strategy_passes);
  rdv_session_destroy(session);
  return img;
}

Image render_json(const std::string &scene_json, const std::string &settings_override) {
  return render_json_prepared([](rdv_scene *) {}, scene_json, settings_override);
}

Image render_json_prepared(const std::function<void(rdv_scene *)> &prepare, const std::string &scene_json,
                           const std::string &settings_override) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  try {
    prepare(scene);
    auto loaded = rdv_tools::load_scene_json(scene_json, ".", scene);
    Image img = render_scene(scene, loaded, settings_override);
    rdv_scene_destroy(scene);
    return img;
  } catch (...) {
    rdv_scene_destroy(scene);
    throw;
  }
}

Image render_file(const std::string &path, const std::string &settings_override) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  try {
    auto loaded = rdv_tools::load_scene_file(path, scene);
    Image img = render_scene(scene, loaded, settings_override);
    rdv_scene_destroy(scene);
    return img;
  } catch (...) {
    rdv_scene_destroy(scene);
    throw;
  }
}

nlohmann::json load_scene(const std::string &name) {
  std::ifstream f(source_path("scenes/" + name));
  std::stringstream ss;
  ss << f.rdbuf();
  return nlohmann::json::parse(ss.str());
}

MeanEstimate pixel_mean(const Image &img, int channel) {
  double s = 0, s2 = 0;
  int n = img.width * img.height;
  for (int i = 0; i < n; ++i) {
    double v = img.rgba[size_t(i) * 4 + channel];
    s += v;
    s2 += v * v;
  }
  double mean = s / n;
  return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n)};
}

std::string source_path(const std::string &relative) { return std::string(RDV_SOURCE_DIR) + "/" + relative; }

std::vector<std::vector<double>> seeded_renders(const std::string &scene_json, const std::string &settings, int runs,
                                                uint32_t seed0) {
  std::vector<std::vector<double>> out;
  for (int k = 0; k < runs; ++k) {
    nlohmann::json s = nlohmann::json::parse(settings);
    s["seed"] = seed0 + k;
    Image img = render_json(scene_json, s.dump());
    EXPECT_TRUE(img.all_finite());
    EXPECT_EQ(img.progress.samples_dropped, 0u);
    std::vector<double> v(size_t(img.width) * img.height);
    for (size_t i = 0; i < v.size(); ++i) v[i] = double(img.rgba[4 * i]) + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
    out.push_back(v);
  }
  return out;
}

const std::vector<std::vector<double>> &seeded_renders_once(const std::string &scene_json, const std::string &settings,
                                                            int runs, uint32_t seed0) {
  static std::map<std::string, std::vector<std::vector<double>>> rendered;
  const std::string key = scene_json + '\n' + settings + '\n' + std::to_string(runs) + ' ' + std::to_string(seed0);
  auto it = rendered.find(key);
  if (it == rendered.end()) it = rendered.emplace(key, seeded_renders(scene_json, settings, runs, seed0)).first;
  return it->second;
}

void expect_small_bdpt_matches_path(const nlohmann::json &scene, const std::string &what) {
  const double alpha_per_block = 1.0 - std::pow(1.0 - 0.01, 1.0 / 16);
  auto runs = [&](const char *integrator, int samples, uint32_t seed) {
    nlohmann::json settings = {{"integrator", integrator}, {"samples", samples}, {"width", 32}, {"height", 32}};
    return seeded_renders(scene.dump(), settings.dump(), 6, seed);
  };
  const std::vector<std::vector<double>> bdpt = runs("bdpt", 16, 100), path = runs("path", 32, 200);
  const BlockComparison c = compare_blocks(bdpt, path, 32, 32, 8, alpha_per_block);
  EXPECT_EQ(c.failed, 0) << what << ": " << c.detail;
  const BrightnessComparison b = compare_brightness(bdpt, path);
  EXPECT_LT(std::fabs(b.z), 3.3) << what << ": bdpt " << b.mean_a << " path " << b.mean_b;
  std::printf("[ %s ] bdpt / path mean %.4f +- %.4f; %s\n", what.c_str(), b.mean_a / b.mean_b, b.error / b.mean_b,
              c.detail.substr(0, 100).c_str());
}

rdv_status session_status(rdv_scene *scene, const std::string &settings) {
  rdv_session *session = nullptr;
  rdv_status status = rdv_session_create(scene, settings.c_str(), &session);
  if (status == RDV_OK) {
    status = rdv_session_start(session);
    if (status == RDV_OK) rdv_session_wait(session);
    rdv_session_destroy(session);
  }
  return status;
}

std::string temp_path(const std::string &name) {
  auto dir = std::filesystem::temp_directory_path() / ("rdv_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace rdv::test
