#include "media/density_grid.h"
#include "core/error.h"

namespace rdv {

DensityGrid::DensityGrid(int nx, int ny, int nz, std::vector<float> values, const Transform &grid_to_world)
    : n_{nx, ny, nz}, values_(std::move(values)), grid_to_world_(grid_to_world) {
  if (nx < 1 || ny < 1 || nz < 1 || values_.size() != size_t(nx) * ny * nz)
    fail("density grid: the resolution does not match the number of values");
  if (!(std::fabs(grid_to_world.det3()) > 0) || !grid_to_world.is_finite())
    fail("density grid: the transform is singular or not finite");
  world_to_grid_ = grid_to_world.inverse();
  for (float &v : values_) v = std::isfinite(v) ? std::max(v, 0.0f) : 0.0f;  // NaN / negative: empty

  // Majorants: a point in majorant cell [16a, 16a+16] interpolates voxels 16a-1 .. 16a+16.
  for (int a = 0; a < 3; ++a) m_[a] = (n_[a] + kMajorantCell - 1) / kMajorantCell;
  majorants_.assign(size_t(m_[0]) * m_[1] * m_[2], 0.0f);
  auto range = [&](int cell, int a, int &lo, int &hi) {
    lo = std::max(cell * kMajorantCell - 1, 0);
    hi = std::min((cell + 1) * kMajorantCell, n_[a] - 1);
  };
  for (int c = 0; c < m_[2]; ++c)
    for (int b = 0; b < m_[1]; ++b)
      for (int a = 0; a < m_[0]; ++a) {
        int i0, i1, j0, j1, k0, k1;
        range(a, 0, i0, i1);
        range(b, 1, j0, j1);
        range(c, 2, k0, k1);
        float m = 0;
        for (int k = k0; k <= k1; ++k)
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) m = std::max(m, voxel(i, j, k));
        majorants_[(size_t(c) * m_[1] + b) * m_[0] + a] = m;
        max_density_ = std::max(max_density_, m);
      }
}

float DensityGrid::density(Vec3 g) const {
  if (!(g.x >= 0 && g.y >= 0 && g.z >= 0 && g.x <= n_[0] && g.y <= n_[1] && g.z <= n_[2])) return 0;
  int i0[3], i1[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    float x = g[a] - 0.5f;  // voxel centres at integer + 0.5
    float fl = std::floor(x);
    f[a] = x - fl;
    int i = int(fl);
    i0[a] = std::clamp(i, 0, n_[a] - 1);
    i1[a] = std::clamp(i + 1, 0, n_[a] - 1);
  }
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  float c00 = lerp(voxel(i0[0], i0[1], i0[2]), voxel(i1[0], i0[1], i0[2]), f[0]);
  float c10 = lerp(voxel(i0[0], i1[1], i0[2]), voxel(i1[0], i1[1], i0[2]), f[0]);
  float c01 = lerp(voxel(i0[0], i0[1], i1[2]), voxel(i1[0], i0[1], i1[2]), f[0]);
  float c11 = lerp(voxel(i0[0], i1[1], i1[2]), voxel(i1[0], i1[1], i1[2]), f[0]);
  return lerp(lerp(c00, c10, f[1]), lerp(c01, c11, f[1]), f[2]);
}

bool DensityGrid::clip(Vec3 o, Vec3 d, float tmax, float &t0, float &t1) const {
  t0 = 0;
  t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < 0 || o[a] > n_[a]) return false;
      continue;
    }
    float inv = 1.0f / d[a];
    float ta = (0 - o[a]) * inv, tb = (n_[a] - o[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

}  // namespace rdv
