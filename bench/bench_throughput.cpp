// Benchmark (prints numbers, asserts nothing): raw Embree throughput for incoherent
// rays, the path tracer's rays/s on the same scene and its ratio to raw Embree
// (goal >= 0.5: the path tracer spends at least half its time in traversal),
// samples/s, and how fast a cancel stops a render.
#include <tbb/parallel_for.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>
#include "api/handles.h"
#include "core/hash.h"
#include "core/ray_offset.h"
#include "core/sampling.h"
#include "scene_file.h"

using Clock = std::chrono::steady_clock;

static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Incoherent rays of the kind a path tracer shoots: from points on the visible
// surfaces (found by camera rays) in uniformly random directions. Generated first,
// then timed alone, so the figure is pure Embree traversal.
static double raw_embree_rays_per_second(const rdv::Scene &scene, int count) {
  std::vector<rdv::Ray> rays;
  rays.reserve(count);
  rdv::Pcg32 rng(42);
  const rdv::Camera &cam = scene.camera();
  for (int guard = 0; int(rays.size()) < count && guard < 50 * count; ++guard) {
    rdv::Ray primary = cam.generate_ray({rng.next_float() * 256, rng.next_float() * 256}, {0.5f, 0.5f});
    rdv::SurfaceHit h;
    if (!scene.intersect(primary, h)) continue;
    rdv::Vec3 d = rdv::uniform_sphere({rng.next_float(), rng.next_float()});
    rays.push_back({rdv::spawn_origin(h.p, h.ng, h.error, d), d, rdv::kInf});
  }
  std::atomic<int64_t> hits{0};
  auto start = Clock::now();
  tbb::parallel_for(size_t(0), rays.size() / 4096, [&](size_t block) {
    int64_t local = 0;
    for (size_t i = block * 4096; i < (block + 1) * 4096; ++i) {
      rdv::SurfaceHit h;
      local += scene.intersect(rays[i], h);
    }
    hits += local;
  });
  return double(rays.size() / 4096 * 4096) / seconds_since(start);
}

static void bench_scene(const char *label, const std::string &scene_json, const std::string &base_dir, int width,
                        int height, int samples) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  auto loaded = rdv_tools::load_scene_json(scene_json, base_dir, scene);
  for (auto &p : loaded.problems) std::printf("  problem: %s\n", p.c_str());
  auto t0 = Clock::now();
  rdv_scene_commit(scene);
  double build = seconds_since(t0);
  const char *summary;
  rdv_scene_summary(scene, &summary);
  auto js = nlohmann::json::parse(summary);
  scene->scene->camera().set_resolution(256, 256);
  double raw = raw_embree_rays_per_second(*scene->scene, 2'000'000);

  nlohmann::json settings = {{"width", width}, {"height", height}, {"samples", samples}, {"threads", 0}};
  rdv_session *session = nullptr;
  if (rdv_session_create(scene, settings.dump().c_str(), &session) != RDV_OK) {
    std::printf("%s: %s\n", label, rdv_last_error());
    return;
  }
  rdv_session_start(session);
  rdv_session_wait(session);
  rdv_progress p{};
  rdv_session_progress(session, &p);
  double samples_per_s = double(width) * height * p.samples_done / p.elapsed_seconds;
  std::printf("%-22s %9llu tris  build %6.3f s | raw Embree %6.2f Mrays/s | path tracer %6.2f Mrays/s, ratio %.2f | %6.3f Msamples/s (%u spp %dx%d in %.2f s)\n",
              label, (unsigned long long)js["triangles_instanced"].get<uint64_t>(), build, raw * 1e-6,
              p.rays_per_second * 1e-6, p.rays_per_second / raw, samples_per_s * 1e-6, p.samples_done, width, height,
              p.elapsed_seconds);
  rdv_session_destroy(session);

  // Cancel latency: how long after rdv_session_cancel until the render has halted.
  settings["samples"] = 1000000;
  rdv_session_create(scene, settings.dump().c_str(), &session);
  rdv_session_start(session);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  auto c0 = Clock::now();
  rdv_session_cancel(session);
  while (true) {
    rdv_session_progress(session, &p);
    if (p.finished) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  std::printf("%-22s cancel -> halted in %.1f ms\n", label, seconds_since(c0) * 1e3);
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
}

static std::string read_file(const std::string &path) {
  FILE *f = std::fopen(path.c_str(), "rb");
  std::string s;
  char buf[65536];
  size_t n;
  while (f && (n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  if (f) std::fclose(f);
  return s;
}

int main() {
  std::printf("Rendezvous throughput benchmark, %u hardware threads\n", std::thread::hardware_concurrency());
  std::string scenes = std::string(RDV_SOURCE_DIR) + "/scenes";
  bench_scene("cornell_box", read_file(scenes + "/cornell_box.json"), scenes, 256, 256, 64);
  // One mesh of ~1M triangles (a finely tessellated sphere) in the Cornell box.
  auto cb = nlohmann::json::parse(read_file(scenes + "/cornell_box.json"));
  cb["meshes"].push_back({{"name", "million"}, {"shape", {{"type", "sphere"}, {"radius", 0.35}, {"segments", 1000}}},
                          {"materials", {"white"}}, {"transform", {{"translate", {0.0, -0.2, 1.2}}}}});
  bench_scene("cornell_box+1M_sphere", cb.dump(), scenes, 256, 256, 32);
  bench_scene("instanced_pebbles", read_file(scenes + "/instanced_pebbles.json"), scenes, 256, 144, 32);
  return 0;
}
