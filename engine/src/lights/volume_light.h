// A volume light: a bounded emissive medium (the inside of the meshes whose material
// has an emitting volume, or a Blender Volume object with flame / temperature grids)
// sampled as a light source, so next-event estimation and light subpaths start from
// where a fire glows instead of waiting for camera paths to pass through it.
//
// Points are drawn by emitted power: a mixture of (a) uniform points in the world box
// of each mesh instance, for the part of the emission that is the same everywhere, and
// (b) voxels of the emission (or temperature) grid, chosen by the largest emission in
// their trilinear support, plus a small uniform share over the grid box so that every
// point that can emit has a positive density whatever the grid's shape.
// A sampled point may lie outside the medium (a box corner outside a sphere): the
// caller learns that from the media the connecting ray passes (MediumStack) and counts
// no emission there, which keeps the estimator unbiased.
#pragma once
#include <memory>
#include <vector>
#include "core/math.h"
#include "media/medium.h"

namespace rdv {

class VolumeEmitter {
 public:
  struct Region {
    Vec3 lo, hi;   // world box of one mesh instance holding the medium
    float volume;  // the enclosed volume (the mesh's, or the box's if unknown)
  };
  VolumeEmitter(const Medium &medium, int medium_index, const std::vector<Region> &regions);

  const Medium &medium() const { return *medium_; }
  int medium_index() const { return medium_index_; }
  // Radiant flux, 4 pi x the integral of the emission's luminance (for light selection).
  float power() const { return power_; }
  bool empty() const { return !(power_ > 0); }
  // The world box around everything this light can emit from.
  Vec3 bounds_lo() const { return lo_; }
  Vec3 bounds_hi() const { return hi_; }
  // The grid whose voxels the points are drawn by, or null (uniform emission only).
  const DensityGrid *lattice() const { return lattice_.get(); }
  // A point by emitted power: u chooses where (a region, a voxel), u_point the point
  // in it; pdf in volume measure.
  Vec3 sample(Vec2 u, Vec3 u_point, float *pdf) const;
  float pdf(Vec3 p) const;

 private:
  float grid_pdf(Vec3 p) const;
  const Medium *medium_;
  int medium_index_;
  std::vector<Region> boxes_;        // uniform part
  std::vector<double> part_cdf_;     // boxes, then the grid part
  double grid_share_ = 0;            // probability of the grid part
  // Grid part, on the lattice of `lattice_`.
  std::shared_ptr<const DensityGrid> lattice_;
  std::vector<float> voxel_weight_;  // per voxel (dense), normalised by voxel_total_
  std::vector<uint32_t> voxel_index_;  // voxels with weight > 0 ...
  std::vector<double> voxel_cdf_;      // ... and their cumulative weights
  double voxel_total_ = 0;
  float voxel_volume_ = 0, grid_box_volume_ = 0;
  float power_ = 0;
  Vec3 lo_{kInf}, hi_{-kInf};
};

}  // namespace rdv
