// Reading a float grid from an OpenVDB file (Blender's Volume objects and fluid caches)
// into a dense DensityGrid over the grid's active voxels (plus a one-voxel margin of
// background, so the density falls to zero at the edges). Empty tiles become zeros,
// whose majorant cells the tracking steps over.
#pragma once
#include <memory>
#include <string>
#include "media/density_grid.h"

namespace rdv {

// The grid named grid_name, placed by the file's voxel transform and then to_world.
// On failure returns null and says why in `error` (missing file, no such grid, ...).
std::shared_ptr<DensityGrid> load_vdb_density(const std::string &path, const std::string &grid_name,
                                              const Transform &to_world, std::string &error);

}  // namespace rdv
