// Benchmark (prints numbers, asserts nothing): Metropolis light transport (pssmlt,
// mmlt) against path tracing and BDPT at equal wall time. relMSE against a reference of
// two independent long BDPT renders (the relMSE of one against their mean is the
// reference's own noise, printed; it is in every figure). For the Metropolis rows also
// mutations per second and acceptance (small / large steps). "net" ratios take the
// reference's own noise out of both figures (it is independent of the renders, so it adds
// to their expected error). --study adds, at the first budget, pssmlt and mmlt rows with
// other large-step probabilities, chain counts and step sizes.
//   bench_mlt [--budgets 10,30,120] [--reference 300] [--reference-cache DIR] [--width 128]
//             [--integrators bdpt,path,pssmlt,mmlt] [--mlt '{"mlt_chains": 64}'] [--seed 17]
//             [--study] [--study-large 0.1,0.5] [--study-chains 32,2048] [--study-step 0.003,0.03]
//             [--point-lamps] [--without-equiangular] [scene.json ...]
// --without-equiangular: after the mlt row, one with mlt_equiangular 0 (camera-side
// distances in fog by free flights alone, mlt/equiangular.h).
// --point-lamps: the scenes' lamps get radius 0 (mlt samples no lamp with a radius). The
// "mean" column is the image's mean over the reference's, "scaled" the relMSE of the image
// scaled to the reference's mean (without the global brightness error), "blocks" the relMSE
// of the 8 x 8 pixel block means (noise averages out there, a bias in a region does not),
// "b err" the Metropolis normalisation's relative standard error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>
#include "bench_render.h"
#include "rendezvous.h"

using nlohmann::json;
using namespace rdv_bench;

namespace {

std::vector<std::string> split(const char *text) {
  std::vector<std::string> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(item);
  return v;
}

std::vector<double> parse_list(const char *text) {
  std::vector<double> v;
  for (const std::string &item : split(text)) v.push_back(std::stod(item));
  return v;
}

}  // namespace

int main(int argc, char **argv) {
  std::vector<double> budgets = {10, 30, 120};
  double reference_seconds = 300;
  int width = 128;
  bool study = false;
  std::vector<double> study_large = {0.1, 0.5}, study_chains = {32, 2048}, study_step;
  std::vector<std::string> integrators = {"bdpt", "path", "pssmlt", "mmlt"};
  std::string reference_cache;
  json mlt_settings = json::object();  // for the Metropolis rows
  int seed = 17;
  bool point_lamps = false, without_equiangular = false;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--budgets") && i + 1 < argc) budgets = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) reference_seconds = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--reference-cache") && i + 1 < argc) reference_cache = argv[++i];
    else if (!std::strcmp(argv[i], "--integrators") && i + 1 < argc) integrators = split(argv[++i]);
    else if (!std::strcmp(argv[i], "--mlt") && i + 1 < argc) mlt_settings = json::parse(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = std::stoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--study-large") && i + 1 < argc) study_large = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--study-chains") && i + 1 < argc) study_chains = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--study-step") && i + 1 < argc) study_step = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--width") && i + 1 < argc) width = std::stoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--study")) study = true;
    else if (!std::strcmp(argv[i], "--point-lamps")) point_lamps = true;
    else if (!std::strcmp(argv[i], "--without-equiangular")) without_equiangular = true;
    else scenes.push_back(argv[i]);
  }
  std::string dir = std::string(RDV_SOURCE_DIR) + "/scenes/";
  if (scenes.empty())
    for (const char *s : {"door_gap.json", "fog_door.json", "door_ajar.json", "fog_ajar.json", "caustic.json",
                          "mirror_caustic.json", "cornell_box.json"})
      scenes.push_back(dir + s);

  std::printf("Equal-time relMSE against a reference of 2 x %.0f s BDPT; %d px wide\n", reference_seconds, width);
  std::printf("%-14s %6s %-22s | %11s | %8s | %8s | %6s | %9s | %9s | %9s | %12s | %6s | %s\n", "scene", "budget",
              "integrator", "relMSE", "vs BDPT", "net", "mean", "scaled", "blocks", "spp/mpp", "mutations/s", "b err",
              "acceptance small / large");
  for (const std::string &path : scenes) {
    BenchScene scene = load_bench_scene(path, width);
    if (point_lamps) {
      json j = json::parse(scene.text);
      if (j.contains("lights"))
        for (auto &light : j["lights"]) light["radius"] = 0;
      scene.text = j.dump();
    }
    const std::string &text = scene.text, &base = scene.base;
    const json &common = scene.common;
    const std::string name = scene.name.substr(0, scene.name.find('.'));
    Reference reference = bdpt_reference(scene, reference_seconds, reference_cache);
    const std::vector<double> &ref = reference.image;
    const double ref_noise = reference.noise;
    for (size_t bi = 0; bi < budgets.size(); ++bi) {
      double budget = budgets[bi];
      double e_bdpt = 0;
      auto row = [&](const std::string &label, json s) {
        if (s["integrator"] == "pssmlt" || s["integrator"] == "mmlt" || s["integrator"] == "mlt") {
          json m = mlt_settings;
          m.update(s);  // the row's own settings win
          s = m;
        }
        s.update(common);
        s["time_limit"] = budget;
        s["seed"] = seed;
        Render r = render(text, base, s);
        double e = rel_mse(r.rgb, ref);
        double sum = 0, ref_sum = 0;
        for (size_t i = 0; i < ref.size() && i < r.rgb.size(); ++i) {
          sum += r.rgb[i];
          ref_sum += ref[i];
        }
        // 8 x 8 block means of both (whole blocks only).
        const int w = common["width"].get<int>(), h = common["height"].get<int>(), bw = w / 8, bh = h / 8;
        std::vector<float> blocks(size_t(bw) * bh * 3, 0.0f);
        std::vector<double> ref_blocks(blocks.size(), 0.0);
        for (int y = 0; y < bh * 8; ++y)
          for (int x = 0; x < bw * 8; ++x)
            for (int c = 0; c < 3; ++c) {
              const size_t at = (size_t(y) * w + x) * 3 + c, b = (size_t(y / 8) * bw + x / 8) * 3 + c;
              if (at < r.rgb.size() && at < ref.size()) {
                blocks[b] += r.rgb[at] / 64.0f;
                ref_blocks[b] += ref[at] / 64.0;
              }
            }
        const double e_blocks = rel_mse(blocks, ref_blocks);
        // The error left at the reference's brightness: what a global scale error (b's,
        // or the chains' share of high- and low-weight regions) adds is the difference.
        std::vector<float> scaled(r.rgb);
        for (float &v : scaled) v *= sum > 0 ? float(ref_sum / sum) : 1.0f;
        const double e_scaled = rel_mse(scaled, ref);
        if (s["integrator"] == "bdpt") e_bdpt = e;
        std::string extra;
        char buf[160];
        if (r.stats.contains("mutations")) {
          const double b = r.stats.value("b", 0.0), b_error = r.stats.value("b_standard_error", 0.0);
          std::snprintf(buf, sizeof buf, "%12.3g | %6.4f | %.3f / %.3f (found %.3f)",
                        r.stats["mutations"].get<double>() / r.progress.elapsed_seconds, b > 0 ? b_error / b : 0.0,
                        r.stats["small_step_acceptance"].get<double>(), r.stats["large_step_acceptance"].get<double>(),
                        r.stats.value("large_step_found", 0.0));
          extra = buf;
        } else {
          extra = std::string(12, ' ') + " |        |";
        }
        std::printf("%-14s %5.0fs %-22s | %11.3e | %8.3f | %8.3f | %6.4f | %9.2e | %9.2e | %9u | %s\n", name.c_str(),
                    budget, label.c_str(), e, e_bdpt > 0 ? e / e_bdpt : 1.0,
                    e_bdpt > ref_noise ? (e - ref_noise) / (e_bdpt - ref_noise) : 1.0, ref_sum > 0 ? sum / ref_sum : 0.0,
                    e_scaled, e_blocks, r.progress.samples_done, extra.c_str());
        std::fflush(stdout);
      };
      for (const std::string &integrator : integrators) {  // bdpt first: the other rows' ratios are to it
        row(integrator, {{"integrator", integrator}});
        if (integrator == "mlt" && without_equiangular)
          row("mlt without equiangular", {{"integrator", "mlt"}, {"mlt_equiangular", 0.0}});
      }
      if (study && bi == 0) {
        for (const char *integrator : {"pssmlt", "mmlt"}) {
          if (std::find(integrators.begin(), integrators.end(), integrator) == integrators.end()) continue;
          for (double p : study_large) {
            char label[64];
            std::snprintf(label, sizeof label, "%s large %.1f", integrator, p);
            row(label, {{"integrator", integrator}, {"mlt_large_step", p}});
          }
          for (double chains : study_chains) {
            char label[64];
            std::snprintf(label, sizeof label, "%s chains %d", integrator, int(chains));
            row(label, {{"integrator", integrator}, {"mlt_chains", int(chains)}});
          }
          for (double step : study_step) {
            char label[64];
            std::snprintf(label, sizeof label, "%s step %g", integrator, step);
            row(label, {{"integrator", integrator}, {"mlt_step_size", step}});
          }
        }
      }
    }
    std::printf("%-14s reference noise (in every figure) %.3e; reference spp %u + %u\n", name.c_str(), ref_noise,
                reference.spp_a, reference.spp_b);
  }
  return 0;
}
