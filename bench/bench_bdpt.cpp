// Benchmark (prints numbers, asserts nothing): the speed-for-accuracy trade of BDPT
// against path tracing. For each scene, both integrators render for the same wall
// time at several budgets; their relative MSE is measured against a long reference.
// The reference is the mean of two independent BDPT renders; the relMSE of one against
// their mean estimates the reference's own noise, which every figure contains. The
// table shows raw relMSE against the reference (so the ratio is conservative: the
// shared reference noise pulls it toward 1) and that noise estimate.
// --mis a,b adds rows for BDPT with other weightings (balance, lafortune_willems) at the
// same budgets, against the same path-traced render and reference (power heuristic).
// --seeds N renders every cell N times (seeds 17, 18, ...): the table shows the mean
// relMSE over the seeds and the ratio of the means, and the lowest and highest per-seed
// ratio, since one seed's ratio at a short budget moves by 10-20%.
//   bench_bdpt [--budgets 5,20,60] [--reference 150] [--width 160] [--mis NAME,...] [--seeds N] [scene.json ...]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>
#include "rendezvous.h"
#include "bench_render.h"
#include "scene_file.h"

using nlohmann::json;
using namespace rdv_bench;

namespace {

// One table cell: an integrator's renders at one budget, one per seed.
struct Cell {
  std::vector<double> errors;  // relMSE per seed
  unsigned spp = 0;            // of the first seed
  double mean() const {
    double s = 0;
    for (double e : errors) s += e;
    return s / errors.size();
  }
};

// The lowest and highest per-seed ratio a/b, as text ("" for one seed).
std::string ratio_range(const Cell &a, const Cell &b) {
  if (a.errors.size() < 2) return "";
  double lo = 1e300, hi = 0;
  for (size_t k = 0; k < a.errors.size(); ++k) {
    double r = a.errors[k] / b.errors[k];
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, " | %.3f-%.3f", lo, hi);
  return buf;
}

}  // namespace

int main(int argc, char **argv) {
  std::vector<double> budgets = {5, 20, 60};
  double reference_seconds = 150;
  int width = 160, seeds = 1;
  std::vector<std::string> scenes, extra_mis;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--budgets") && i + 1 < argc) {
      budgets.clear();
      std::stringstream ss(argv[++i]);
      std::string item;
      while (std::getline(ss, item, ',')) budgets.push_back(std::stod(item));
    } else if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) {
      reference_seconds = std::stod(argv[++i]);
    } else if (!std::strcmp(argv[i], "--mis") && i + 1 < argc) {
      std::stringstream ss(argv[++i]);
      std::string item;
      while (std::getline(ss, item, ',')) extra_mis.push_back(item);
    } else if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) {
      seeds = std::max(1, std::stoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--width") && i + 1 < argc) {
      width = std::stoi(argv[++i]);
    } else {
      scenes.push_back(argv[i]);
    }
  }
  std::string dir = std::string(RDV_SOURCE_DIR) + "/scenes/";
  if (scenes.empty())
    for (const char *s : {"door_gap.json", "caustic.json", "cornell_box.json", "light_types.json"}) scenes.push_back(dir + s);

  std::printf("BDPT vs path tracing at equal time; relMSE against a reference of 2 x %.0f s BDPT; %d px wide; "
              "%d seed(s) per cell\n", reference_seconds, width, seeds);
  // "net": each relMSE minus the reference's own noise (independent of the renders, so
  // it adds to their expected error); printed after each scene's reference is known.
  std::printf("%-18s %7s | %12s %9s | %12s %9s | %10s | %10s%s\n", "scene", "budget", "PT relMSE", "PT spp", "BDPT relMSE",
              "BDPT spp", "BDPT/PT", "net ratio", seeds > 1 ? " | per-seed BDPT/PT" : "");
  for (const std::string &path : scenes) {
    BenchScene scene = load_bench_scene(path, width);
    const std::string &text = scene.text, &base = scene.base, &name = scene.name;
    const json &common = scene.common;
    Reference reference = bdpt_reference(scene, reference_seconds);
    const std::vector<double> &ref = reference.image;
    const double ref_noise = reference.noise;
    const Render &ra = reference.a, &rb = reference.b;
    for (double budget : budgets) {
      json s = common;
      s["time_limit"] = budget;
      auto measure = [&](const std::string &integrator, const std::string &mis) {
        Cell cell;
        s["integrator"] = integrator;
        s["mis"] = mis;
        for (int k = 0; k < seeds; ++k) {
          s["seed"] = 17 + k;
          Render r = render(text, base, s);
          if (k == 0) cell.spp = r.progress.samples_done;
          cell.errors.push_back(rel_mse(r.rgb, ref));
        }
        return cell;
      };
      Cell pt = measure("path", "power"), bd = measure("bdpt", "power");
      double e_pt = pt.mean(), e_bd = bd.mean();
      std::printf("%-18s %6.0fs | %12.3e %9u | %12.3e %9u | %10.3f | %10.3f%s\n", name.c_str(), budget, e_pt, pt.spp,
                  e_bd, bd.spp, e_bd / e_pt, (e_bd - ref_noise) / (e_pt - ref_noise), ratio_range(bd, pt).c_str());
      for (const std::string &mis : extra_mis) {
        Cell other = measure("bdpt", mis);
        double e = other.mean();
        std::string label = "  BDPT " + (mis == "lafortune_willems" ? std::string("L&W") : mis);
        std::printf("%-18s %6.0fs | %12s %9s | %12.3e %9u | %10.3f | %10.3f%s\n", label.c_str(), budget, "(same)", "", e,
                    other.spp, e / e_pt, (e - ref_noise) / (e_pt - ref_noise), ratio_range(other, pt).c_str());
      }
      std::fflush(stdout);
    }
    std::printf("%-18s reference noise (included in every figure) %.3e; BDPT %.2f Mrays/s, %.3f Msamples/s; reference spp %u + %u\n",
                name.c_str(), ref_noise, ra.progress.rays_per_second * 1e-6,
                double(width) * common["height"].get<int>() * ra.progress.samples_done / ra.progress.elapsed_seconds * 1e-6,
                ra.progress.samples_done, rb.progress.samples_done);
  }
  return 0;
}
