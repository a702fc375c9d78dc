#include "lights/volume_light.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>

namespace rdv {

namespace {

// The grid part takes this share of its samples uniformly over the grid box.
constexpr double kDefensiveShare = 0.05;

bool inside(Vec3 p, Vec3 lo, Vec3 hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// u in [lo, hi) as a uniform number in [0, 1).
double remap(double u, double lo, double hi) {
  return hi > lo ? std::clamp((u - lo) / (hi - lo), 0.0, std::nextafter(1.0, 0.0)) : 0.0;
}

size_t sample_cdf(const std::vector<double> &cdf, double u) {
  size_t i = std::upper_bound(cdf.begin(), cdf.end(), u * cdf.back()) - cdf.begin();
  return std::min(i, cdf.size() - 1);
}

// Maximum over each voxel's 3x3x3 neighbourhood (separable): the trilinear value
// anywhere in a voxel is bounded by the voxel centres around it.
std::vector<float> neighbourhood_max(const std::vector<float> &f, int nx, int ny, int nz) {
  std::vector<float> a = f, b(f.size());
  const int n[3] = {nx, ny, nz};
  const size_t stride[3] = {1, size_t(nx), size_t(nx) * ny};
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          size_t idx = (size_t(k) * ny + j) * nx + i;
          int c = axis == 0 ? i : axis == 1 ? j : k;
          float m = a[idx];
          if (c > 0) m = std::max(m, a[idx - stride[axis]]);
          if (c + 1 < n[axis]) m = std::max(m, a[idx + stride[axis]]);
          b[idx] = m;
        }
    std::swap(a, b);
  }
  return a;
}

}  // namespace

VolumeEmitter::VolumeEmitter(const Medium &medium, int medium_index, const std::vector<Region> &regions)
    : medium_(&medium), medium_index_(medium_index) {
  std::vector<double> part_power;
  // (a) The uniform part, per region.
  const float uniform = luminance(medium.uniform_emission());
  if (uniform > 0) {
    for (const Region &r : regions) {
      Vec3 size = r.hi - r.lo;
      if (!(size.x > 0 && size.y > 0 && size.z > 0) || !(r.volume > 0)) continue;
      boxes_.push_back(r);
      part_power.push_back(double(uniform) * r.volume);
      lo_ = vmin(lo_, r.lo);
      hi_ = vmax(hi_, r.hi);
    }
  }
  // (b) The part that varies with a grid, on the lattice of that grid.
  double grid_power = 0;
  if (medium.has_emission_grids()) {
    lattice_ = medium.emission_shape();
    const DensityGrid &g = *lattice_;
    const int nx = g.nx(), ny = g.ny(), nz = g.nz();
    const Color base = medium.uniform_emission();
    std::vector<float> centre(size_t(nx) * ny * nz);
    tbb::parallel_for(0, nz, [&](int k) {
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          Vec3 p = g.grid_to_world().point(Vec3(i + 0.5f, j + 0.5f, k + 0.5f));
          centre[(size_t(k) * ny + j) * nx + i] = std::max(luminance(medium.emission_at(p) - base), 0.0f);
        }
    });
    voxel_weight_ = neighbourhood_max(centre, nx, ny, nz);
    for (size_t v = 0; v < voxel_weight_.size(); ++v) {
      if (!(voxel_weight_[v] > 0)) continue;
      voxel_total_ += voxel_weight_[v];
      voxel_index_.push_back(uint32_t(v));
      voxel_cdf_.push_back(voxel_total_);
    }
    voxel_volume_ = std::fabs(g.grid_to_world().det3());
    grid_box_volume_ = voxel_volume_ * float(nx) * float(ny) * float(nz);
    if (voxel_total_ > 0 && voxel_volume_ > 0) {
      grid_power = voxel_total_ * voxel_volume_;
      for (int c = 0; c < 8; ++c) {  // the grid box's corners
        Vec3 p = g.grid_to_world().point(Vec3(c & 1 ? nx : 0, c & 2 ? ny : 0, c & 4 ? nz : 0));
        lo_ = vmin(lo_, p);
        hi_ = vmax(hi_, p);
      }
    } else {
      lattice_.reset();  // the grids hold no emission
    }
  }
  double total = grid_power;
  for (double p : part_power) total += p;
  if (!(total > 0)) return;
  double running = 0;
  for (double p : part_power) part_cdf_.push_back(running += p / total);
  grid_share_ = grid_power / total;
  if (grid_power > 0) part_cdf_.push_back(1.0);
  else if (!part_cdf_.empty()) part_cdf_.back() = 1.0;
  power_ = float(4 * kPi * total);
}

Vec3 VolumeEmitter::sample(Vec2 u, Vec3 u_point, float *pdf_out) const {
  *pdf_out = 0;
  if (empty()) return Vec3(0.0f);
  // One number of 48 bits for the choices (voxel CDFs may have millions of entries),
  // led by u.x: a small change of u is a small change of the choice.
  const double c = double(u.x) + double(u.y) * 0x1p-24;
  size_t part = std::min<size_t>(std::lower_bound(part_cdf_.begin(), part_cdf_.end(), c) - part_cdf_.begin(),
                                 part_cdf_.size() - 1);
  const double within = remap(c, part > 0 ? part_cdf_[part - 1] : 0.0, part_cdf_[part]);
  Vec3 p;
  if (part < boxes_.size()) {
    const Region &b = boxes_[part];
    p = b.lo + (b.hi - b.lo) * u_point;
  } else {
    const DensityGrid &g = *lattice_;
    Vec3 cell;
    if (within < kDefensiveShare) {
      cell = Vec3(u_point.x * g.nx(), u_point.y * g.ny(), u_point.z * g.nz());
    } else {
      uint32_t v = voxel_index_[sample_cdf(voxel_cdf_, remap(within, kDefensiveShare, 1.0))];
      int i = int(v % uint32_t(g.nx())), j = int(v / uint32_t(g.nx()) % uint32_t(g.ny())),
          k = int(v / (uint32_t(g.nx()) * uint32_t(g.ny())));
      cell = Vec3(i + u_point.x, j + u_point.y, k + u_point.z);
    }
    p = g.grid_to_world().point(cell);
  }
  *pdf_out = pdf(p);
  return p;
}

float VolumeEmitter::grid_pdf(Vec3 p) const {
  const DensityGrid &g = *lattice_;
  Vec3 c = g.world_to_grid().point(p);
  if (!(c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < g.nx() && c.y < g.ny() && c.z < g.nz())) return 0;
  size_t v = (size_t(int(c.z)) * g.ny() + size_t(int(c.y))) * g.nx() + size_t(int(c.x));
  double p_voxel = voxel_weight_[v] / voxel_total_ / voxel_volume_;
  return float((1 - kDefensiveShare) * p_voxel + kDefensiveShare / grid_box_volume_);
}

float VolumeEmitter::pdf(Vec3 p) const {
  if (empty() || !inside(p, lo_, hi_)) return 0;
  double pdf = 0, previous = 0;
  for (size_t i = 0; i < boxes_.size(); ++i) {
    double share = part_cdf_[i] - previous;
    previous = part_cdf_[i];
    const Region &b = boxes_[i];
    if (inside(p, b.lo, b.hi)) {
      Vec3 s = b.hi - b.lo;
      pdf += share / (double(s.x) * s.y * s.z);
    }
  }
  if (lattice_) pdf += grid_share_ * grid_pdf(p);
  return float(pdf);
}

}  // namespace rdv
