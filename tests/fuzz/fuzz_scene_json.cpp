// libFuzzer target: the JSON scene loader (engine/tools/scene_file.cpp), as the
// command-line renderer runs it: load, commit, and a tiny render of what loaded.
// A file may be refused (std::runtime_error, rdv::Error naming the object), never
// crash, hang, fail with an internal error or put NaN / Inf in a pixel (fuzz_checks.h).
// Seeds: scenes/*.json (tests/fuzz/CMakeLists.txt); docs/reliability.md.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>
#include "fuzz_checks.h"
#include "scene_file.h"

namespace {

using nlohmann::json;
using rdv_fuzz::checked;

// The file's settings, kept except for what makes a render long: a tiny image, one
// sample, one thread, short Metropolis start-up.
std::string tiny_settings(const std::string &settings_json) {
  json s = json::parse(settings_json, nullptr, false);
  if (!s.is_object()) return settings_json;  // the session refuses it, naming the settings
  s["width"] = 6;
  s["height"] = 4;
  s["samples"] = 1;
  s["threads"] = 1;
  s.erase("time_limit");
  s.erase("noise_target");
  s.erase("adaptive_min_samples");
  if (s.contains("border")) s.erase("border");  // a border on a 6x4 image is mostly empty
  for (const char *key : {"max_bounces", "mlt_bootstrap", "mlt_chains", "diffuse_bounces", "glossy_bounces",
                          "transmission_bounces", "volume_bounces"}) {
    const int most = std::string(key) == "mlt_bootstrap" ? 64 : 8;
    if (s.contains(key) && s[key].is_number() && !(s[key].get<double>() <= most)) s[key] = most;
  }
  return s.dump();
}

void render(rdv_scene *scene, const std::string &settings_json) {
  rdv_session *session = nullptr;
  if (checked(rdv_session_create(scene, tiny_settings(settings_json).c_str(), &session), "rdv_session_create") != RDV_OK)
    return;
  if (checked(rdv_session_start(session), "rdv_session_start") == RDV_OK)
    checked(rdv_session_wait(session), "rdv_session_wait");
  std::vector<float> pixels(6 * 4 * 4);
  if (checked(rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 6, 4, 1, pixels.data()),
              "rdv_session_read_film") == RDV_OK)
    rdv_fuzz::check_finite(pixels.data(), pixels.size(), "combined pass");
  checked(rdv_session_destroy(session), "rdv_session_destroy");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string text(reinterpret_cast<const char *>(data), size);
  rdv_scene *scene = nullptr;
  checked(rdv_scene_create(&scene), "rdv_scene_create");
  try {
    rdv_tools::LoadedScene loaded = rdv_tools::load_scene_json(text, RDV_SOURCE_DIR "/scenes", scene);
    for (const std::string &problem : loaded.problems)
      if (problem.find("internal error") != std::string::npos || problem.find("[json.exception") != std::string::npos)
        rdv_fuzz::finding("loader problem: " + problem);
    if (checked(rdv_scene_commit(scene), "rdv_scene_commit") == RDV_OK) render(scene, loaded.settings_json);
  } catch (const std::runtime_error &) {
    // The file is refused with a message (rdv::Error is a std::runtime_error too).
  } catch (const std::exception &e) {
    rdv_fuzz::finding(std::string("load_scene_json threw a ") + typeid(e).name() + ": " + e.what());
  }
  checked(rdv_scene_destroy(scene), "rdv_scene_destroy");
  rdv_fuzz::check_no_live_objects();
  return 0;
}
