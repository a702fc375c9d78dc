// Benchmark (prints numbers, asserts nothing): what Cycles' Filter Glossy
// (integrators/filter_glossy.h) costs BDPT and what it buys. Per scene, the filter off and
// on: BDPT's time at a fixed sample count (alternately, medians of 3), and its noise at
// equal time: K renders of T seconds each with their own seeds. Off and on converge to
// different images, so no common reference: the relative MSE of one render is estimated
// from pairs of renders, 2 x relMSE(a, (a + b) / 2) (= half that of a against b), averaged
// over the K (K - 1) / 2 pairs (a firefly shows in the spread, min .. max, printed too).
//   bench_filter_glossy [--seconds T] [--runs K] [--width W] [--filter F] [scene.json ...]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>
#include "bench_render.h"

using namespace rdv_bench;

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char **argv) {
  double seconds = 8, filter = 1;
  int runs = 4, width = 128;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc) seconds = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(2, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--width") && i + 1 < argc) width = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--filter") && i + 1 < argc) filter = std::atof(argv[++i]);
    else scenes.push_back(argv[i]);
  }
  if (scenes.empty())
    for (const char *s : {"caustic.json", "light_types.json", "mirror_caustic.json"})
      scenes.push_back(std::string(RDV_SOURCE_DIR) + "/scenes/" + s);

  std::printf("BDPT, Filter Glossy 0 vs %.2f, %d px wide: time at 256 spp (medians of 3), relMSE of one %.0f s render "
              "(%d seeds, pairs)\n", filter, width, seconds, runs);
  std::printf("%-16s %7s %7s %7s | %9s %9s %7s %11s %11s | %5s %5s\n", "scene", "off s", "on s", "on/off",
              "relMSE off", "relMSE on", "off/on", "off min..max", "on min..max", "spp", "spp");
  for (const std::string &path : scenes) {
    BenchScene scene = load_bench_scene(path, width);
    auto settings = [&](double f) {
      json s = scene.common;
      s["integrator"] = "bdpt";
      s["filter_glossy"] = f;
      return s;
    };
    std::vector<double> t_off, t_on;
    for (int r = 0; r < 3; ++r)
      for (double f : {0.0, filter}) {
        json s = settings(f);
        s["samples"] = 256;
        s["seed"] = 1;
        (f > 0 ? t_on : t_off).push_back(render(scene.text, scene.base, s).progress.elapsed_seconds);
      }
    double e[2], lo[2], hi[2];
    unsigned spp[2];
    for (int k = 0; k < 2; ++k) {
      std::vector<std::vector<float>> images;
      for (int r = 0; r < runs; ++r) {
        json s = settings(k ? filter : 0.0);
        s["time_limit"] = seconds;
        s["seed"] = 100 + r;
        Render out = render(scene.text, scene.base, s);
        spp[k] = out.progress.samples_done;
        images.push_back(std::move(out.rgb));
      }
      std::vector<double> pairs, mean(images[0].size());
      for (int a = 0; a < runs; ++a)
        for (int b = a + 1; b < runs; ++b) {
          for (size_t i = 0; i < mean.size(); ++i) mean[i] = 0.5 * (double(images[a][i]) + images[b][i]);
          pairs.push_back(2 * rel_mse(images[a], mean));
        }
      e[k] = 0;
      for (double p : pairs) e[k] += p / double(pairs.size());
      lo[k] = *std::min_element(pairs.begin(), pairs.end());
      hi[k] = *std::max_element(pairs.begin(), pairs.end());
    }
    const double off = median(t_off), on = median(t_on);
    std::printf("%-16s %7.2f %7.2f %7.3f | %9.2e %9.2e %7.2f %5.1e..%5.1e %5.1e..%5.1e | %5u %5u\n",
                scene.name.c_str(), off, on, on / off, e[0], e[1], e[0] / e[1], lo[0], hi[0], lo[1], hi[1], spp[0],
                spp[1]);
    std::fflush(stdout);
  }
  return 0;
}
