#include "equal_time.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include "film/image_error.h"
#include "scene_file.h"

namespace rdv_tools {

using nlohmann::json;

std::string content_hash(const std::string &bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    h ^= uint8_t(c);
    h *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", (unsigned long long)h);
  return text;
}

EqualTimeScene load_equal_time_scene(const std::string &path, int width) {
  EqualTimeScene s;
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot read the file");
  std::stringstream ss;
  ss << f.rdbuf();
  s.path = path;
  s.text = ss.str();
  std::filesystem::path p(path);
  s.base = p.parent_path().empty() ? "." : p.parent_path().string();
  s.name = p.stem().string();
  json doc = json::parse(s.text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) throw std::runtime_error(path + ": not a JSON scene");
  const json settings = doc.value("settings", json::object());
  double aspect = 0.75;
  if (settings.is_object() && settings.value("width", 0) > 0 && settings.value("height", 0) > 0)
    aspect = double(settings["height"].get<int>()) / settings["width"].get<int>();
  int height = std::max(1, int(std::lround(width * aspect)));
  s.common = {{"width", width}, {"height", height}, {"samples", 0}, {"threads", 0}};
  return s;
}

EngineScene::EngineScene(const EqualTimeScene &scene) {
  if (rdv_scene_create(&scene_) != RDV_OK) throw std::runtime_error(scene.path + ": " + rdv_last_error());
  try {
    problems_ = load_scene_json(scene.text, scene.base, scene_).problems;
  } catch (const std::exception &e) {
    rdv_scene_destroy(scene_);
    throw std::runtime_error(scene.path + ": " + e.what());
  }
}

EngineScene::~EngineScene() { rdv_scene_destroy(scene_); }

namespace {

// The scene file's own settings (rdv_tools::load_scene_json keeps them as text).
json scene_settings(const std::string &text) {
  json doc = json::parse(text, nullptr, false);
  if (doc.is_object() && doc.contains("settings") && doc["settings"].is_object()) return doc["settings"];
  return json::object();
}

}  // namespace

json render_settings(const EqualTimeScene &scene, const json &overrides) {
  json s = scene_settings(scene.text);
  s.update(scene.common);
  s.update(overrides);
  return s;
}

TimedRender render_loaded(rdv_scene *scene, const json &settings, const RenderProgress &progress) {
  rdv_session *session = nullptr;
  if (rdv_session_create(scene, settings.dump().c_str(), &session) != RDV_OK)
    throw std::runtime_error(std::string("session: ") + rdv_last_error());
  struct Destroy {
    rdv_session *s;
    ~Destroy() { rdv_session_destroy(s); }
  } destroy{session};
  if (rdv_session_start(session) != RDV_OK) throw std::runtime_error(std::string("start: ") + rdv_last_error());
  TimedRender r;
  if (progress) {
    while (true) {
      rdv_session_progress(session, &r.progress);
      progress(r.progress);
      if (r.progress.finished) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  if (rdv_session_wait(session) != RDV_OK) throw std::runtime_error(std::string("render: ") + rdv_last_error());
  rdv_session_progress(session, &r.progress);
  const char *stats = nullptr;
  if (rdv_session_stats(session, &stats) == RDV_OK && stats) r.stats = json::parse(stats);
  const int w = settings.at("width"), h = settings.at("height");
  std::vector<float> rgba(size_t(w) * h * 4);
  if (rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, w, h, 1, rgba.data()) != RDV_OK)
    throw std::runtime_error(std::string("read film: ") + rdv_last_error());
  r.rgb.resize(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int c = 0; c < 3; ++c) r.rgb[3 * i + c] = rgba[4 * i + c];
  return r;
}

TimedRender render_text(const std::string &text, const std::string &base, const json &settings,
                        const RenderProgress &progress) {
  EqualTimeScene scene;
  scene.path = base + "/(scene text)";
  scene.text = text;
  scene.base = base;
  EngineScene loaded(scene);
  json s = scene_settings(text);
  s.update(settings);
  return render_loaded(loaded.get(), s, progress);
}

std::string reference_cache_file(const EqualTimeScene &scene, const ReferenceRequest &request) {
  if (request.cache_dir.empty()) return "";
  json key = scene.common;
  key["integrator"] = request.integrator;
  key["seconds"] = request.seconds;
  key["seeds"] = {9001, 9002};
  return request.cache_dir + "/" + scene.name + "-" + content_hash(scene.text + "\n" + key.dump()) + ".ref";
}

namespace {

// Version 2: the noise as relative_mse(a, mean) (version 1: relMSE(b, a) / 4).
constexpr char kCacheMagic[8] = {'R', 'D', 'V', 'R', 'E', 'F', '2', '\n'};

bool read_cache(const std::string &file, size_t expected_values, Reference &r) {
  std::ifstream in(file, std::ios::binary);
  char magic[8];
  uint64_t n = 0;
  if (!in.read(magic, 8) || !std::equal(magic, magic + 8, kCacheMagic)) return false;
  if (!in.read(reinterpret_cast<char *>(&n), sizeof n) || n != expected_values) return false;
  r.image.resize(n);
  in.read(reinterpret_cast<char *>(&r.noise), sizeof r.noise);
  in.read(reinterpret_cast<char *>(&r.spp_a), sizeof r.spp_a);
  in.read(reinterpret_cast<char *>(&r.spp_b), sizeof r.spp_b);
  if (!in.read(reinterpret_cast<char *>(r.image.data()), std::streamsize(n * sizeof(double)))) return false;
  return std::all_of(r.image.begin(), r.image.end(), [](double v) { return std::isfinite(v); });
}

void write_cache(const std::string &file, const Reference &r) {
  std::filesystem::create_directories(std::filesystem::path(file).parent_path());
  const std::string partial = file + ".partial";  // renamed when whole: a killed run leaves no bad cache
  {
    std::ofstream out(partial, std::ios::binary);
    uint64_t n = r.image.size();
    out.write(kCacheMagic, 8);
    out.write(reinterpret_cast<const char *>(&n), sizeof n);
    out.write(reinterpret_cast<const char *>(&r.noise), sizeof r.noise);
    out.write(reinterpret_cast<const char *>(&r.spp_a), sizeof r.spp_a);
    out.write(reinterpret_cast<const char *>(&r.spp_b), sizeof r.spp_b);
    out.write(reinterpret_cast<const char *>(r.image.data()), std::streamsize(n * sizeof(double)));
    if (!out) throw std::runtime_error(file + ": cannot write the reference cache");
  }
  std::filesystem::rename(partial, file);
}

}  // namespace

Reference make_reference(const EqualTimeScene &scene, rdv_scene *loaded, const ReferenceRequest &request,
                         const std::function<void(int, const rdv_progress &)> &progress) {
  Reference r;
  r.integrator = request.integrator;
  r.cache_file = reference_cache_file(scene, request);
  const size_t values = size_t(scene.common["width"].get<int>()) * scene.common["height"].get<int>() * 3;
  if (!r.cache_file.empty() && read_cache(r.cache_file, values, r)) {
    r.from_cache = true;
    return r;
  }
  json s = render_settings(scene, {{"integrator", request.integrator}, {"time_limit", request.seconds / 2}});
  for (int half = 0; half < 2; ++half) {
    s["seed"] = 9001 + half;
    RenderProgress p;
    if (progress) p = [&](const rdv_progress &q) { progress(half, q); };
    (half ? r.b : r.a) = render_loaded(loaded, s, p);
  }
  r.image.resize(r.a.rgb.size());
  for (size_t i = 0; i < r.image.size(); ++i) r.image[i] = 0.5 * (double(r.a.rgb[i]) + r.b.rgb[i]);
  // Measured as every figure against the reference is, relative to the mean m: E(a - m)^2
  // = var_single / 2 = the mean's own error. (A quarter of relMSE(b, a) agrees for mild
  // noise but divides a firefly in b by a's dark pixel and can overstate it ~10x.)
  std::vector<float> mean(r.image.begin(), r.image.end());
  r.noise = rdv::relative_mse(r.a.rgb, mean);
  r.spp_a = r.a.progress.samples_done;
  r.spp_b = r.b.progress.samples_done;
  if (!r.cache_file.empty()) write_cache(r.cache_file, r);
  return r;
}

}  // namespace rdv_tools
