#include "media_grids.h"
#include <cmath>

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

}  // namespace rdv::test
