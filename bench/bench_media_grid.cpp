// Benchmark (prints numbers, asserts nothing): grid media by unbiased tracking
// (delta + ratio tracking over the majorant grid) against Pauly et al.'s random-offset
// ray marching at several step sizes, on scenes/smoke_spot.json with path tracing.
// Each method renders the same number of samples per pixel; the table gives the time
// and the relative MSE against a long tracking reference. Ray marching's error has a
// bias floor that more samples do not remove; tracking's falls as 1/spp. A quarter of
// the mutual relMSE of the reference's two halves estimates the reference's own
// noise, which every figure contains.
//   bench_media_grid [--spp 64] [--reference-spp 2048] [--width 160]
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>
#include "bench_render.h"

using nlohmann::json;

using namespace rdv_bench;

namespace {

std::vector<double> as_double(const std::vector<float> &v) { return {v.begin(), v.end()}; }

}  // namespace

int main(int argc, char **argv) {
  int spp = 64, reference_spp = 2048, width = 160;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--spp")) spp = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--reference-spp")) reference_spp = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--width")) width = std::atoi(argv[i + 1]);
  }
  std::ifstream f(RDV_SOURCE_DIR "/scenes/smoke_spot.json");
  std::stringstream file_text;
  file_text << f.rdbuf();
  json scene = json::parse(file_text.str());
  json &volume = scene["materials"][2]["volume"];
  const double voxel = 3.0 / 40;  // the scene's grid: 40 voxels over 3 units
  json settings = {{"width", width}, {"height", width * 3 / 4}, {"integrator", "path"}};

  // Reference: two independent halves of tracking.
  volume["method"] = "tracking";
  json rs = settings;
  rs["samples"] = reference_spp / 2;
  rs["seed"] = 1000;
  const std::string base = RDV_SOURCE_DIR "/scenes";
  const std::string text = scene.dump();
  Render ref_a = render(text, base, rs);
  rs["seed"] = 2000;
  Render ref_b = render(text, base, rs);
  std::vector<double> ref(ref_a.rgb.size());
  for (size_t i = 0; i < ref.size(); ++i) ref[i] = 0.5 * (double(ref_a.rgb[i]) + ref_b.rgb[i]);
  std::printf("smoke_spot %dx%d, path tracing; reference: tracking, %d spp in %.1f s; its own noise ~ relMSE %.2e\n",
              width, width * 3 / 4, reference_spp, ref_a.progress.elapsed_seconds + ref_b.progress.elapsed_seconds,
              0.25 * rel_mse(ref_a.rgb, as_double(ref_b.rgb)));
  std::printf("%-28s %6s %9s %11s %13s\n", "method", "spp", "time [s]", "relMSE", "1/(t relMSE)");

  struct Method { const char *name, *method; double step_voxels; };
  for (Method m : {Method{"tracking", "tracking", 0}, Method{"ray marching, step 0.5 voxel", "ray_marching", 0.5},
                   Method{"ray marching, step 1 voxel", "ray_marching", 1}, Method{"ray marching, step 2 voxels", "ray_marching", 2},
                   Method{"ray marching, step 4 voxels", "ray_marching", 4}}) {
    volume["method"] = m.method;
    if (m.step_voxels > 0) volume["step_size"] = m.step_voxels * voxel;
    else volume.erase("step_size");
    for (int n : {spp, spp * 4}) {
      json s = settings;
      s["samples"] = n;
      s["seed"] = 7;
      Render r = render(scene.dump(), base, s);
      double e = rel_mse(r.rgb, ref), t = r.progress.elapsed_seconds;
      std::printf("%-28s %6d %9.2f %11.3e %13.1f\n", m.name, n, t, e, 1.0 / (t * e));
    }
  }
  return 0;
}
