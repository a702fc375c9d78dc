// A dense voxel grid of density for heterogeneous media, with trilinear lookups and a
// coarse majorant grid (the maximum density of the trilinear support of each block of
// kMajorantCell^3 voxels). Tracking steps through the majorant grid with a 3D DDA, so
// empty and thin regions of a cloud cost one step per block instead of one per voxel.
//
// Grid coordinates: voxel (i, j, k) spans [i, i+1] x [j, j+1] x [k, k+1]; its value sits
// at its centre. Inside the box [0, n] the density is the trilinear interpolation of the
// voxel centres (clamped to the edge voxels); outside the box it is zero.
#pragma once
#include <vector>
#include "core/math.h"

namespace rdv {

class DensityGrid {
 public:
  static constexpr int kMajorantCell = 16;

  // values: nx*ny*nz densities, x fastest. grid_to_world maps grid coordinates to world.
  DensityGrid(int nx, int ny, int nz, std::vector<float> values, const Transform &grid_to_world);

  int nx() const { return n_[0]; }
  int ny() const { return n_[1]; }
  int nz() const { return n_[2]; }
  float max_density() const { return max_density_; }
  const Transform &world_to_grid() const { return world_to_grid_; }
  const Transform &grid_to_world() const { return grid_to_world_; }
  size_t memory_bytes() const { return (values_.size() + majorants_.size()) * sizeof(float); }

  // Density at a point in grid coordinates.
  float density(Vec3 g) const;

  // Calls f(t0, t1, majorant) for the pieces of the ray g(t) = o + d t (grid coordinates,
  // t in the caller's units) inside the grid box and [0, tmax], front to back, with an
  // upper bound of the density on each piece. Stops when f returns false.
  template <class F>
  void for_each_majorant_segment(Vec3 o, Vec3 d, float tmax, F &&f) const;
  // The part [t0, t1] of that ray inside the grid box and [0, tmax]; false if none.
  bool clip(Vec3 o, Vec3 d, float tmax, float &t0, float &t1) const;

 private:
  float voxel(int i, int j, int k) const { return values_[(size_t(k) * n_[1] + j) * n_[0] + i]; }
  int n_[3];
  int m_[3];  // majorant grid resolution
  std::vector<float> values_, majorants_;
  float max_density_ = 0;
  Transform grid_to_world_, world_to_grid_;
};

template <class F>
void DensityGrid::for_each_majorant_segment(Vec3 o, Vec3 d, float tmax, F &&f) const {
  float t_enter, t_exit;
  if (!clip(o, d, tmax, t_enter, t_exit)) return;
  // 3D DDA over majorant cells (Amanatides & Woo).
  Vec3 p = o + d * t_enter;
  int cell[3], step[3];
  float next_t[3], delta_t[3];
  const float size = float(kMajorantCell);
  for (int a = 0; a < 3; ++a) {
    cell[a] = std::clamp(int(std::floor(p[a] / size)), 0, m_[a] - 1);
    if (d[a] > 0) {
      step[a] = 1;
      next_t[a] = ((cell[a] + 1) * size - o[a]) / d[a];
      delta_t[a] = size / d[a];
    } else if (d[a] < 0) {
      step[a] = -1;
      next_t[a] = (cell[a] * size - o[a]) / d[a];
      delta_t[a] = -size / d[a];
    } else {
      step[a] = 0;
      next_t[a] = kInf;
      delta_t[a] = kInf;
    }
  }
  float t = t_enter;
  while (t < t_exit) {
    int axis = next_t[0] < next_t[1] ? (next_t[0] < next_t[2] ? 0 : 2) : (next_t[1] < next_t[2] ? 1 : 2);
    float t_next = std::min(std::max(next_t[axis], t), t_exit);
    float majorant = majorants_[(size_t(cell[2]) * m_[1] + cell[1]) * m_[0] + cell[0]];
    if (t_next > t && !f(t, t_next, majorant)) return;
    t = t_next;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= m_[axis]) return;
    next_t[axis] += delta_t[axis];
  }
}

}  // namespace rdv
