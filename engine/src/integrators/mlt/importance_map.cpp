#include "integrators/mlt/importance_map.h"

namespace rdv::mlt {

ImportanceMap::ImportanceMap(const std::vector<float> &block_luminance, const std::vector<float> &block_hits,
                             int blocks_x, int blocks_y, Vec2 origin, double samples)
    : blocks_x_(blocks_x), blocks_y_(blocks_y), origin_(origin) {
  const size_t n = size_t(blocks_x) * size_t(blocks_y);
  // Levels of the pyramid: level k sums squares of 2^k x 2^k blocks, until one square
  // holds the image.
  struct Level {
    int w, h;
    std::vector<double> luminance, hits;
  };
  std::vector<Level> levels(1);
  levels[0] = {blocks_x, blocks_y, std::vector<double>(block_luminance.begin(), block_luminance.end()),
               std::vector<double>(block_hits.begin(), block_hits.end())};
  while (levels.back().w > 1 || levels.back().h > 1) {
    const Level &fine = levels.back();
    Level coarse{(fine.w + 1) / 2, (fine.h + 1) / 2, {}, {}};
    coarse.luminance.assign(size_t(coarse.w) * size_t(coarse.h), 0.0);
    coarse.hits.assign(coarse.luminance.size(), 0.0);
    for (int y = 0; y < fine.h; ++y)
      for (int x = 0; x < fine.w; ++x) {
        size_t from = size_t(y) * size_t(fine.w) + size_t(x), to = size_t(y / 2) * size_t(coarse.w) + size_t(x / 2);
        coarse.luminance[to] += fine.luminance[from];
        coarse.hits[to] += fine.hits[from];
      }
    levels.push_back(std::move(coarse));
  }
  // Mean luminance per pixel of each block (from its level), and of the image.
  std::vector<double> mean(n);
  for (int y = 0; y < blocks_y; ++y)
    for (int x = 0; x < blocks_x; ++x) {
      size_t k = 0, at = 0;
      for (; k < levels.size(); ++k) {
        at = size_t(y >> k) * size_t(levels[k].w) + size_t(x >> k);
        if (levels[k].hits[at] >= kMinHits) break;
      }
      k = std::min(k, levels.size() - 1);
      at = size_t(y >> k) * size_t(levels[k].w) + size_t(x >> k);
      const double pixels = double(kBlock << k) * double(kBlock << k);
      mean[size_t(y) * size_t(blocks_x) + size_t(x)] = levels[k].luminance[at] / (samples * pixels);
    }
  double image_mean = 0;
  for (double m : mean) image_mean += m / double(n);
  // The floor also keeps the weights finite where the pilot saw no light (the scale of
  // the weights does not matter: b takes it).
  const double floor = image_mean > 0 ? image_mean : 1.0;
  weights_.resize(n);
  size_t relative = 0;
  for (size_t i = 0; i < n; ++i) {
    relative += mean[i] > floor;
    weights_[i] = float(floor / std::max(mean[i], floor));
  }
  relative_share_ = n ? float(double(relative) / double(n)) : 0.0f;
}

}  // namespace rdv::mlt
