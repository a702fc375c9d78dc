#include "media_grids.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include "lcg.h"

namespace rdv::test {

// A cloud of Gaussian puffs on an n^3 grid over `bounds`, zero in its outer shell
// (so majorant cells there are empty).
nlohmann::json puff_grid(int n, const nlohmann::json &bounds) {
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5, z = (k + 0.5) / n - 0.5;
        auto puff = [&](double cx, double cy, double cz, double r) {
          return std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) / (r * r));
        };
        double d = puff(0, 0, 0, 0.18) + 0.7 * puff(0.15, -0.1, 0.12, 0.1) + 0.5 * puff(-0.2, 0.1, -0.05, 0.08);
        v.push_back(std::max(x * x, std::max(y * y, z * z)) > 0.16 ? 0.0f : float(d));
      }
  return {{"resolution", {n, n, n}}, {"values", v}, {"bounds", bounds}};
}

nlohmann::json varied_grid(int nx, int ny, int nz, const nlohmann::json &bounds) {
  std::vector<float> v;
  Lcg random{12345};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double noise = random.next();
        const double wave = std::sin(1.3 * i + 0.4) * std::cos(0.9 * j - 0.3) * std::sin(1.7 * k + 1.1);
        v.push_back(float(std::clamp(1.0 + 0.5 * wave + 0.8 * (noise - 0.5), 0.1, 1.9)));
      }
  return {{"resolution", {nx, ny, nz}}, {"values", v}, {"bounds", bounds}};
}

nlohmann::json cornell_grid_fog(const nlohmann::json &cornell_box, double density, const nlohmann::json &volume) {
  nlohmann::json j = cornell_box;
  nlohmann::json params = {{"density", density},
                           {"color", {0.9, 0.9, 0.9}},
                           {"anisotropy", 0.3},
                           {"grid", varied_grid(7, 6, 5, {{-0.9, -0.9, 1.3}, {0.9, 0.9, 1.9}})}};
  params.update(volume);
  j["materials"].push_back({{"name", "grid_fog"}, {"type", "volume"}, {"volume", params}});
  j["meshes"].push_back({{"name", "grid_fog_box"},
                         {"shape", {{"type", "box"}, {"size", {1.8, 1.8, 0.6}}}},
                         {"materials", {"grid_fog"}},
                         {"transform", {{"translate", {0, 0, 1.6}}}}});
  return j;
}

}  // namespace rdv::test
