// Benchmark (prints numbers, asserts nothing): the cost of material evaluation.
//  1. samples/s on a scene where every object has a Principled BSDF with an image
//     texture (base colour) and a bump from a procedural noise, against the same scene
//     with plain diffuse materials (goal: under 1.5x slower), same settings, interleaved
//     runs, best of 2 each;
//  2. texture-cache memory with 50 4K textures (generated into /tmp at run time as
//     tiled, zip-compressed 8-bit TIFFs), looked up at random over all of them: the
//     cache stays under the limit the engine sets (RDV_TEXTURE_CACHE_MB, default 256).
#include <OpenImageIO/imageio.h>
#include <tbb/parallel_for.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include "core/hash.h"
#include "rendezvous.h"
#include "scene_file.h"
#include "textures/image_texture.h"

using Clock = std::chrono::steady_clock;
using nlohmann::json;

static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

static std::string bench_dir() {
  std::string d = (std::filesystem::temp_directory_path() / "rdv_bench_textures").string();
  std::filesystem::create_directories(d);
  return d;
}

// A w x w 8-bit RGB texture with a smooth pattern (compresses well), tiled 64 x 64.
static std::string write_texture(const std::string &name, int w, int variant) {
  std::string path = bench_dir() + "/" + name;
  if (std::filesystem::exists(path)) return path;
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(w, w, 3, OIIO::TypeDesc::UINT8);
  spec.tile_width = spec.tile_height = 64;
  spec.attribute("compression", "zip");
  if (!out->open(path, spec)) { std::printf("cannot write %s: %s\n", path.c_str(), out->geterror().c_str()); return path; }
  std::vector<uint8_t> px(size_t(w) * w * 3);
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t *p = &px[(size_t(y) * w + x) * 3];
      p[0] = uint8_t((x * 255) / w);
      p[1] = uint8_t((y * 255) / w);
      p[2] = uint8_t(((x / 64 + y / 64 + variant) & 1) * 200 + 20);
    }
  out->write_image(OIIO::TypeDesc::UINT8, px.data());
  out->close();
  return path;
}

// Every lobe of the Principled BSDF (pass-through, diffuse, sheen, specular,
// transmission, clearcoat: 6 lobes, 3 layers).
static json full_principled(const json &base_color, double roughness) {
  return {{"type", "principled"}, {"base_color", base_color}, {"subsurface", 0.3}, {"roughness", roughness},
          {"sheen", 0.5}, {"clearcoat", 0.5}, {"clearcoat_roughness", 0.1}, {"transmission", 0.3}, {"alpha", 0.9}};
}

// variant: 0 diffuse, 1 principled + image + bump, 2 principled + image, 3 principled (constant),
// 4 a Mix of two full Principled BSDFs (constant; 12 lobes, 6 layers)
static json scene(int variant, const std::string &texture) {
  bool principled = variant != 0;
  json mats = json::array(), meshes = json::array();
  json diffuse = {{"name", "m"}, {"type", "diffuse"}, {"color", {0.7, 0.6, 0.5}}};
  json fancy = {{"name", "m"}, {"type", "principled"},
                {"base_color", {{"node", "image"}, {"file", texture}}},
                {"roughness", 0.4}, {"specular", 0.5},
                {"normal", {{"node", "bump"}, {"distance", 0.05},
                            {"height", {{"node", "noise"}, {"scale", 8}, {"detail", 2}}}}}};
  if (variant >= 2) fancy.erase("normal");
  if (variant == 3) fancy["base_color"] = {0.7, 0.6, 0.5};
  if (variant == 4)
    fancy = {{"name", "m"}, {"type", "mix"}, {"fac", 0.4}, {"shader1", full_principled({0.7, 0.6, 0.5}, 0.3)},
             {"shader2", full_principled({0.3, 0.5, 0.7}, 0.6)}};
  mats.push_back(principled ? fancy : diffuse);
  json floor_mat = principled ? fancy : diffuse;
  floor_mat["name"] = "floor";
  mats.push_back(floor_mat);
  for (int i = 0; i < 16; ++i)
    meshes.push_back({{"name", "ball" + std::to_string(i)}, {"shape", {{"type", "sphere"}, {"radius", 0.4}, {"segments", 48}}},
                      {"materials", {"m"}}, {"transform", {{"translate", {(i % 4) - 1.5, (i / 4) - 1.5, 0.4}}}}});
  meshes.push_back({{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 10}}}, {"materials", {"floor"}}});
  return {{"settings", {{"width", 160}, {"height", 120}, {"samples", 16}, {"max_bounces", 6}}},
          {"camera", {{"type", "perspective"}, {"transform", {{"look_at", {{"from", {0, -6, 3}}, {"to", {0, 0, 0.3}}}}}}}},
          {"world", {{"color", {0.4, 0.45, 0.5}}}},
          {"materials", mats},
          {"meshes", meshes},
          {"lights", {{{"name", "key"}, {"type", "area"}, {"size", 2}, {"power", 400},
                       {"transform", {{"look_at", {{"from", {2, -2, 4}}, {"to", {0, 0, 0}}}}}}}}}};
}

static double samples_per_second(const json &j) {
  rdv_scene *s = nullptr;
  rdv_scene_create(&s);
  auto loaded = rdv_tools::load_scene_json(j.dump(), ".", s);
  for (auto &p : loaded.problems) std::printf("  problem: %s\n", p.c_str());
  json settings = j["settings"];
  settings["threads"] = 0;
  rdv_session *session = nullptr;
  if (rdv_session_create(s, settings.dump().c_str(), &session) != RDV_OK) {
    std::printf("session: %s\n", rdv_last_error());
    rdv_scene_destroy(s);
    return 0;
  }
  rdv_session_start(session);
  rdv_session_wait(session);
  rdv_progress p{};
  rdv_session_progress(session, &p);
  double sps = double(settings["width"].get<int>()) * settings["height"].get<int>() * p.samples_done / p.elapsed_seconds;
  rdv_session_destroy(session);
  rdv_scene_destroy(s);
  return sps;
}

// --materials-only: the first part alone (no 4K textures written or read).
int main(int argc, char **argv) {
  bool materials_only = argc > 1 && std::string(argv[1]) == "--materials-only";
  std::string tex = write_texture("albedo_1k.tif", 1024, 0);
  double best[5] = {0, 0, 0, 0, 0};
  for (int round = 0; round < 2; ++round)
    for (int v = 0; v < 5; ++v) best[v] = std::max(best[v], samples_per_second(scene(v, tex)));
  std::printf("materials (Msamples/s, 160x120, 16 spp, best of 2): diffuse %.3f | principled %.3f (%.2fx) | principled + image texture %.3f (%.2fx, goal < 1.5x) | + noise bump %.3f (%.2fx) | mix of two full principled %.3f (%.2fx)\n",
              best[0] * 1e-6, best[3] * 1e-6, best[0] / best[3], best[2] * 1e-6, best[0] / best[2], best[1] * 1e-6,
              best[0] / best[1], best[4] * 1e-6, best[0] / best[4]);
  if (materials_only) return 0;

  auto &ts = rdv::ImageTextures::instance();
  auto t0 = Clock::now();
  std::vector<int> ids;
  uintmax_t bytes_on_disk = 0;
  for (int i = 0; i < 50; ++i) {
    std::string path = write_texture("tex4k_" + std::to_string(i) + ".tif", 4096, i);
    bytes_on_disk += std::filesystem::file_size(path);
    std::string problem;
    int id = ts.load(path, "sRGB", problem);
    if (id < 0) std::printf("  %s\n", problem.c_str());
    else ids.push_back(id);
  }
  double gen = seconds_since(t0);
  t0 = Clock::now();
  const size_t lookups = 4'000'000;
  size_t peak = 0;
  for (int pass = 0; pass < 4; ++pass) {
    tbb::parallel_for(size_t(0), lookups / 4 / 4096, [&](size_t block) {
      rdv::Pcg32 rng(block * 977 + pass);
      for (int k = 0; k < 4096; ++k) {
        int id = ids[rng.next_u32() % ids.size()];
        float a = rng.next_float();
        ts.lookup(id, a, rng.next_float(), rdv::TexInterp::Linear, rdv::TexExtension::Repeat, nullptr);
      }
    });
    peak = std::max(peak, ts.cache_memory_bytes());
  }
  double look = seconds_since(t0);
  double full = 50.0 * 4096 * 4096 * 3 / 1048576.0;
  std::printf("texture cache: 50 x 4K textures (%.0f MB of texels, %.0f MB on disk, written in %.1f s); %zu random lookups in %.2f s (%.2f M/s); cache %.1f MB (peak seen %.1f MB) with a limit of %.0f MB\n",
              full, bytes_on_disk / 1048576.0, gen, lookups, look, lookups / look * 1e-6,
              ts.cache_memory_bytes() / 1048576.0, peak / 1048576.0, ts.cache_megabytes());
  return 0;
}
