// Soak (prints numbers, asserts nothing; issue 16, docs/reliability.md): what a long
// Blender session does to the engine, in one process.
//  1. Viewport: 1,000 scene edits of every kind (material, light, world volume on and
//     off, mesh geometry, instance transform, camera), each followed by a short
//     progressive render that is read while it runs and often cancelled mid-pass, as the
//     3D view does. Resident memory after 10, 100, 250, 500 and 1,000 edits.
//  2. Final renders: 100 times load scenes/cornell_box.json into a new scene, render it
//     with BDPT, read every pass, destroy. Resident memory after 1, 10, 50 and 100.
//  3. Cancel latency under load: renders of every integrator on a media scene cancelled
//     at 0.3-1.0 s; the time from rdv_session_cancel until the progress says finished
//     (goal < 100 ms), median and worst.
// Usage: bench_soak [--edits N] [--finals N] [--cancels N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>
#include "scene_file.h"

using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// VmRSS of this process, MiB.
double resident_mib() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1;
}

void check(rdv_status s, const char *what) {
  if (s != RDV_OK) {
    std::fprintf(stderr, "bench_soak: %s: %s\n", what, rdv_last_error());
    std::exit(1);
  }
}

// A grid of (n+1)^2 vertices over [-1,1]^2 at height z, waved by `phase`.
void grid(int n, float phase, std::vector<float> &positions, std::vector<uint32_t> &indices) {
  positions.clear();
  indices.clear();
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      const float u = -1 + 2.0f * x / n, v = -1 + 2.0f * y / n;
      positions.insert(positions.end(), {u, v, 0.1f * std::sin(4 * u + phase) * std::cos(3 * v)});
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});
    }
}

void viewport_soak(int edits) {
  rdv_scene *scene = nullptr;
  check(rdv_scene_create(&scene), "scene");
  uint32_t floor_mat, ball_mat, mesh, box, inst, box_inst, lamp;
  check(rdv_scene_add_material(scene, "Floor", R"({"type":"diffuse","color":[0.8,0.8,0.8]})", &floor_mat), "material");
  check(rdv_scene_add_material(scene, "Ball", R"({"type":"principled","base_color":[0.8,0.2,0.1],"roughness":0.3})", &ball_mat), "material");
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  grid(32, 0, positions, indices);
  const uint32_t nv = uint32_t(positions.size() / 3), nt = uint32_t(indices.size() / 3);
  check(rdv_scene_add_mesh(scene, "Floor", positions.data(), nv, nullptr, nullptr, indices.data(), nt, nullptr, floor_mat, &mesh), "mesh");
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  check(rdv_scene_add_instance(scene, mesh, identity, &inst), "instance");
  // A closed unit cube, outward winding: it can hold a medium.
  const float cube[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  const uint32_t cube_idx[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                               1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  check(rdv_scene_add_mesh(scene, "Box", cube, 8, nullptr, nullptr, cube_idx, 12, nullptr, ball_mat, &box), "mesh");
  const float raised[16] = {0.3f, 0, 0, 0, 0, 0.3f, 0, 0, 0, 0, 0.3f, 0.5f, 0, 0, 0, 1};
  check(rdv_scene_add_instance(scene, box, raised, &box_inst), "instance");
  check(rdv_scene_add_light(scene, "Lamp", R"({"type":"point","position":[0.5,-0.5,2],"power":300})", &lamp), "light");
  check(rdv_scene_set_world(scene, R"({"color":[0.05,0.05,0.08]})"), "world");
  check(rdv_scene_set_camera(scene, R"({"transform":{"look_at":{"from":[0,-3,2],"to":[0,0,0]}}})"), "camera");
  const char *settings = R"({"width":96,"height":64,"samples":16,"integrator":"path","max_bounces":6})";
  std::vector<float> film(96 * 64 * 4);
  const double start_mib = resident_mib();
  std::printf("viewport soak: %d edits, each followed by a progressive 96x64 render (read while running, every "
              "third cancelled)\n  start: %.1f MiB\n", edits, start_mib);
  auto t0 = Clock::now();
  int cancelled = 0;
  double at_10 = 0;
  for (int i = 1; i <= edits; ++i) {
    char text[256];
    switch (i % 6) {
      case 0:
        std::snprintf(text, sizeof text, R"({"type":"diffuse","color":[%.3f,0.8,0.8]})", 0.2 + 0.6 * ((i * 37) % 100) / 100.0);
        check(rdv_scene_set_material(scene, floor_mat, text), "set material");
        break;
      case 1:
        std::snprintf(text, sizeof text, R"({"type":"point","position":[0.5,-0.5,2],"power":%d})", 100 + (i * 53) % 500);
        check(rdv_scene_set_light(scene, lamp, text), "set light");
        break;
      case 2:  // the world's fog on and off: media come and go
        check(rdv_scene_set_world(scene, (i / 6) % 2 ? R"({"color":[0.05,0.05,0.08],"volume":{"density":0.02}})"
                                                     : R"({"color":[0.05,0.05,0.08]})"),
              "set world");
        break;
      case 3:
        grid(32, 0.01f * i, positions, indices);
        check(rdv_scene_set_mesh(scene, mesh, positions.data(), nv, nullptr, nullptr, indices.data(), nt, nullptr, floor_mat),
              "set mesh");
        break;
      case 4: {
        float moved[16];
        std::memcpy(moved, raised, sizeof moved);
        moved[3] = 0.3f * std::sin(0.1f * i);
        check(rdv_scene_set_instance_transform(scene, box_inst, moved), "set transform");
        break;
      }
      case 5:  // the material that fills the box with fog and back (a medium per edit)
        check(rdv_scene_set_material(scene, ball_mat, (i / 6) % 2 ? R"({"type":"diffuse","color":[0.5,0.5,0.5],"volume":{"density":1}})"
                                                                  : R"({"type":"principled","base_color":[0.8,0.2,0.1],"roughness":0.3})"),
              "set material");
        std::snprintf(text, sizeof text, R"({"transform":{"look_at":{"from":[%.3f,-3,2],"to":[0,0,0]}}})", 0.5 * std::sin(0.05 * i));
        check(rdv_scene_set_camera(scene, text), "set camera");
        break;
    }
    rdv_session *session = nullptr;
    check(rdv_session_create(scene, settings, &session), "session");
    check(rdv_session_start(session), "start");
    rdv_progress p{};
    for (int polls = 0;; ++polls) {
      rdv_session_progress(session, &p);
      rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 96, 64, 1, film.data());
      if (p.finished) break;
      if (i % 3 == 0 && polls == 2) {
        rdv_session_cancel(session);
        ++cancelled;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    check(rdv_session_wait(session), "wait");
    check(rdv_session_destroy(session), "destroy");
    if (i == 10) at_10 = resident_mib();
    if (i == 10 || i == 100 || i == 250 || i == 500 || i == edits)
      std::printf("  after %4d edits: %.1f MiB (%+.1f MiB since edit 10), %.1f s\n", i, resident_mib(),
                  resident_mib() - at_10, seconds_since(t0));
  }
  uint32_t scenes = 0, sessions = 0;
  rdv_live_objects(&scenes, &sessions);
  std::printf("  %d renders cancelled mid-run; live objects at the end: %u scenes, %u sessions\n", cancelled, scenes, sessions);
  rdv_scene_destroy(scene);
}

void final_soak(int renders) {
  const std::string path = std::string(RDV_SOURCE_DIR) + "/scenes/cornell_box.json";
  std::printf("final-render soak: %d x (load %s into a new scene, BDPT 128x128 8 spp, read every pass, destroy)\n",
              renders, "scenes/cornell_box.json");
  const double start_mib = resident_mib();
  double at_1 = 0;
  auto t0 = Clock::now();
  std::vector<float> film(128 * 128 * 4);
  for (int i = 1; i <= renders; ++i) {
    rdv_scene *scene = nullptr;
    check(rdv_scene_create(&scene), "scene");
    rdv_tools::load_scene_file(path, scene);
    rdv_session *session = nullptr;
    check(rdv_session_create(scene, R"({"width":128,"height":128,"samples":8,"integrator":"bdpt"})", &session), "session");
    check(rdv_session_start(session), "start");
    check(rdv_session_wait(session), "wait");
    for (rdv_pass pass : {RDV_PASS_COMBINED, RDV_PASS_DEPTH, RDV_PASS_NORMAL, RDV_PASS_ALBEDO})
      check(rdv_session_read_film(session, pass, 0, 0, 128, 128, 1, film.data()), "read");
    check(rdv_session_destroy(session), "destroy");
    check(rdv_scene_destroy(scene), "destroy scene");
    if (i == 1) at_1 = resident_mib();
    if (i == 1 || i == 10 || i == 50 || i == renders)
      std::printf("  after %3d renders: %.1f MiB (%+.1f MiB since the first; %.1f before it), %.1f s\n", i,
                  resident_mib(), resident_mib() - at_1, start_mib, seconds_since(t0));
  }
}

void cancel_latency(int per_integrator) {
  const std::string path = std::string(RDV_SOURCE_DIR) + "/scenes/fog_door.json";
  rdv_scene *scene = nullptr;
  check(rdv_scene_create(&scene), "scene");
  rdv_tools::load_scene_file(path, scene);
  std::printf("cancel latency under load (scenes/fog_door.json 320x240, both cores busy; cancel at 0.3-1.0 s):\n");
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt"}) {
    std::vector<double> ms;
    for (int k = 0; k < per_integrator; ++k) {
      char settings[256];
      std::snprintf(settings, sizeof settings,
                    R"({"width":320,"height":240,"samples":0,"time_limit":60,"integrator":"%s","seed":%d})", integrator, k);
      rdv_session *session = nullptr;
      check(rdv_session_create(scene, settings, &session), "session");
      check(rdv_session_start(session), "start");
      std::this_thread::sleep_for(std::chrono::milliseconds(300 + (k * 137) % 700));
      const auto c0 = Clock::now();
      check(rdv_session_cancel(session), "cancel");
      rdv_progress p{};
      do {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        rdv_session_progress(session, &p);
      } while (!p.finished);
      ms.push_back(seconds_since(c0) * 1e3);
      check(rdv_session_wait(session), "wait");
      check(rdv_session_destroy(session), "destroy");
    }
    std::sort(ms.begin(), ms.end());
    std::printf("  %-6s %2d cancels: median %.1f ms, worst %.1f ms\n", integrator, per_integrator, ms[ms.size() / 2],
                ms.back());
  }
  rdv_scene_destroy(scene);
}

}  // namespace

int main(int argc, char **argv) {
  int edits = 1000, finals = 100, cancels = 10;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--edits")) edits = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--finals")) finals = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--cancels")) cancels = std::atoi(argv[i + 1]);
  }
  if (edits > 0) viewport_soak(edits);
  if (finals > 0) final_soak(finals);
  if (cancels > 0) cancel_latency(cancels);
  return 0;
}
