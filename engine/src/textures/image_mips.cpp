#include "textures/image_mips.h"
#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

namespace rdv {

namespace {

// Level 0 averaged over each texel's square as a lookup without a footprint sees it. Where
// the file's colour space is not linear, such a lookup interpolates the file's values and
// converts the result, as Cycles does, so where neighbours differ the mean over a texel's
// square is not the texel's converted value (over a one-texel checker of sRGB 0 and 255 the
// mean is 0.246, not the texels' 0.5). Each square is integrated by 2 x 2 Gauss points in each
// of its four quarters (the interpolant is smooth within each); texels whose neighbours are
// all within 2/255 of them keep their converted value (a checker of +-1/255: the mean 2e-3
// off at sRGB 0.05, 7e-5 at 0.5). Borders as Repeat (Blender's default; the levels serve
// every extension alike).
class InterpolatedTexelMeans {
 public:
  explicit InterpolatedTexelMeans(const MipSource &source) : s_(source) {}

  // The means along one row, from it and the rows above and below (the file's values).
  void row(const float *above, const float *centre, const float *below, float *out) const {
    const float *rows[3] = {above, centre, below};
    for (int x = 0; x < s_.w; ++x) mean(rows, x, out + size_t(x) * size_t(s_.channels));
  }

 private:
  // Scene-linear colour channels and the alpha of texel x's mean.
  void mean(const float *const rows[3], int x, float *out) const {
    const int nc = s_.channels;
    float nb[3][3][4];  // the texel and its neighbours, nb[1 + dy][1 + dx]
    bool flat = true;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (s_.nonlinear || (dx == 0 && dy == 0)) texel(rows[1 + dy], x + dx, nb[1 + dy][1 + dx]);
    const float *centre = nb[1][1];
    if (s_.nonlinear)
      for (int i = 0; i < 9 && flat; ++i)
        for (int c = 0; c < std::min(nc, 3); ++c) flat = flat && std::fabs(nb[i / 3][i % 3][c] - centre[c]) <= 2.0f / 255.0f;
    Color mean;
    if (flat) {
      mean = s_.to_scene_linear(centre);
    } else {
      // Gauss-Legendre points along one axis, two in each half of the square: the offset of
      // the neighbour bilinear interpolation blends in there and its weight in the blend (a
      // one-texel checker's mean within 1e-4 of its exact 0.24627).
      constexpr float g = 0.14433757f;  // 0.25 / sqrt(3)
      constexpr int kD[4] = {-1, -1, 1, 1};
      constexpr float kA[4] = {0.25f + g, 0.25f - g, 0.25f - g, 0.25f + g};
      for (int ky = 0; ky < 4; ++ky)
        for (int kx = 0; kx < 4; ++kx) {
          const float *v10 = nb[1][1 + kD[kx]], *v01 = nb[1 + kD[ky]][1], *v11 = nb[1 + kD[ky]][1 + kD[kx]];
          const float ax = kA[kx], ay = kA[ky];
          float r[4];
          for (int c = 0; c < 4; ++c)
            r[c] = (1 - ax) * (1 - ay) * centre[c] + ax * (1 - ay) * v10[c] + (1 - ax) * ay * v01[c] + ax * ay * v11[c];
          mean += s_.to_scene_linear(r) * (1.0f / 16.0f);
        }
    }
    out[0] = mean.x;
    if (nc == 2) out[1] = centre[1];
    if (nc >= 3) {
      out[1] = mean.y;
      out[2] = mean.z;
    }
    if (nc == 4) out[3] = centre[3];
  }

  // Texel x of a row (x wrapping), channels as filtered: the rest 0, alpha 1.
  void texel(const float *row, int x, float r[4]) const {
    x = x < 0 ? x + s_.w : (x >= s_.w ? x - s_.w : x);
    const float *t = row + size_t(x) * size_t(s_.channels);
    r[0] = r[1] = r[2] = 0;
    r[3] = 1;
    for (int c = 0; c < s_.channels; ++c) r[c] = t[c];
  }

  const MipSource &s_;
};

// 2 x 2 box filtering, level after level, of rows that arrive in order: each level keeps one
// row of sums, so only the levels asked for are stored whole.
class MipCascade {
 public:
  MipCascade(int w, int h, int channels, int keep_from) : nc_(channels) {
    for (int k = 1; w > 1 || h > 1; ++k) {
      Stage s;
      s.in_w = w;
      s.in_h = h;
      s.w = std::max(w / 2, 1);
      s.h = std::max(h / 2, 1);
      s.sums.assign(size_t(s.w) * size_t(nc_), 0.0f);
      s.row.assign(s.sums.size(), 0.0f);
      if (k >= keep_from) {
        s.kept = int(levels_.size());
        levels_.push_back({s.w, s.h, std::vector<float>(size_t(s.w) * size_t(s.h) * size_t(nc_))});
      }
      stages_.push_back(std::move(s));
      w = stages_.back().w;
      h = stages_.back().h;
    }
  }

  // Level 0's rows (their texel means), top first.
  void add_row(const float *row) { feed(0, row); }
  std::vector<MipLevel> take() { return std::move(levels_); }

 private:
  struct Stage {
    int in_w = 0, in_h = 0, w = 0, h = 0;
    int rows_in = 0;           // rows of the level above received
    std::vector<float> sums;   // the row being summed
    std::vector<float> row;    // its means, handed on
    int kept = -1;             // index in levels_, or -1
  };

  void feed(size_t k, const float *in) {
    if (k >= stages_.size()) return;
    Stage &s = stages_[k];
    const int y = std::min(s.rows_in / 2, s.h - 1);
    for (int x = 0; x < s.w; ++x) {
      const int x1 = x == s.w - 1 ? s.in_w - 1 : 2 * x + 1;
      for (int xx = 2 * x; xx <= x1; ++xx)
        for (int c = 0; c < nc_; ++c) s.sums[size_t(x) * nc_ + c] += in[size_t(xx) * nc_ + c];
    }
    const bool done = s.rows_in == (y == s.h - 1 ? s.in_h - 1 : 2 * y + 1);
    ++s.rows_in;
    if (!done) return;
    const int rows = s.rows_in - 2 * y;
    for (int x = 0; x < s.w; ++x) {
      const int cols = (x == s.w - 1 ? s.in_w - 1 : 2 * x + 1) - 2 * x + 1;
      for (int c = 0; c < nc_; ++c) {
        float &sum = s.sums[size_t(x) * nc_ + c];
        s.row[size_t(x) * nc_ + c] = sum / float(rows * cols);
        sum = 0;
      }
    }
    if (s.kept >= 0) {
      auto &texels = levels_[size_t(s.kept)].texels;
      std::copy(s.row.begin(), s.row.end(), texels.begin() + ptrdiff_t(y) * s.w * nc_);
    }
    feed(k + 1, s.row.data());
  }

  int nc_;
  std::vector<Stage> stages_;
  std::vector<MipLevel> levels_;
};

}  // namespace

bool build_mip_levels(const MipSource &source, int keep_from, std::vector<MipLevel> &levels) {
  const int w = source.w, h = source.h;
  const size_t row = size_t(w) * size_t(source.channels);
  const InterpolatedTexelMeans means(source);
  MipCascade cascade(w, h, source.channels, std::max(keep_from, 1));
  // Bands of rows with one more above and below (wrapping, as Repeat): the texel means of a
  // band in parallel (~0.3 us a texel where neighbours differ), then down the levels in order.
  constexpr int kBand = 64;
  std::vector<float> rows(size_t(kBand + 2) * row), band(size_t(kBand) * row);
  for (int y0 = 0; y0 < h; y0 += kBand) {
    const int y1 = std::min(y0 + kBand, h);
    const int first = std::max(y0 - 1, 0), last = std::min(y1 + 1, h);  // rows read at once
    if (!source.read(first, last, &rows[size_t(first - (y0 - 1)) * row])) return false;
    if (y0 == 0 && !source.read(h - 1, h, rows.data())) return false;
    if (y1 == h && !source.read(0, 1, &rows[size_t(y1 - y0 + 1) * row])) return false;
    tbb::parallel_for(0, y1 - y0, [&](int i) {
      means.row(&rows[size_t(i) * row], &rows[size_t(i + 1) * row], &rows[size_t(i + 2) * row], &band[size_t(i) * row]);
    });
    for (int i = 0; i < y1 - y0; ++i) cascade.add_row(&band[size_t(i) * row]);
  }
  levels = cascade.take();
  return true;
}

}  // namespace rdv
