#include "media/vdb_file.h"
#include <filesystem>
#include <mutex>
#include <openvdb/openvdb.h>

namespace rdv {

std::shared_ptr<DensityGrid> load_vdb_density(const std::string &path, const std::string &grid_name,
                                              const Transform &to_world, std::string &error) {
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  if (!std::filesystem::is_regular_file(path)) {
    error = "VDB file '" + path + "' not found";
    return nullptr;
  }
  try {
    openvdb::io::File file(path);
    file.open(false);  // no delayed loading: the file is read once, here
    if (!file.hasGrid(grid_name)) {
      std::string names;
      for (auto it = file.beginName(); it != file.endName(); ++it) names += (names.empty() ? "" : ", ") + it.gridName();
      error = "VDB file '" + path + "' has no grid named '" + grid_name + "' (it has: " + (names.empty() ? "none" : names) + ")";
      return nullptr;
    }
    openvdb::GridBase::Ptr base = file.readGrid(grid_name);
    file.close();
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) {
      error = "grid '" + grid_name + "' in VDB file '" + path + "' is a " + base->valueType() + " grid, not float";
      return nullptr;
    }
    if (!grid->transform().isLinear()) {
      error = "grid '" + grid_name + "' in VDB file '" + path + "' has a non-linear (frustum) transform";
      return nullptr;
    }
    openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(0));  // no active voxels
    box.expand(1);  // a margin of background around the active voxels
    openvdb::Coord lo = box.min(), dim = box.dim();
    double voxels = double(dim.x()) * dim.y() * dim.z();
    if (voxels > 512.0 * 512 * 512) {
      error = "grid '" + grid_name + "' in VDB file '" + path + "' spans " + std::to_string(dim.x()) + "x" +
              std::to_string(dim.y()) + "x" + std::to_string(dim.z()) + " voxels, more than the dense limit of 512^3";
      return nullptr;
    }
    std::vector<float> values(size_t(dim.x()) * dim.y() * dim.z());
    auto acc = grid->getConstAccessor();
    size_t n = 0;
    for (int k = 0; k < dim.z(); ++k)
      for (int j = 0; j < dim.y(); ++j)
        for (int i = 0; i < dim.x(); ++i) values[n++] = acc.getValue(lo.offsetBy(i, j, k));
    // Our grid coordinate g (voxel centres at integer + 0.5) is VDB index g - 0.5 + lo
    // (VDB voxel centres at integers); the file's linear map takes index to its space.
    const openvdb::math::Transform &xf = grid->transform();
    auto index_to_file = [&](double x, double y, double z) {
      openvdb::Vec3d w = xf.indexToWorld(openvdb::Vec3d(x - 0.5 + lo.x(), y - 0.5 + lo.y(), z - 0.5 + lo.z()));
      return Vec3(float(w.x()), float(w.y()), float(w.z()));
    };
    Vec3 origin = index_to_file(0, 0, 0);
    Transform grid_to_file;
    Vec3 axes[3] = {index_to_file(1, 0, 0) - origin, index_to_file(0, 1, 0) - origin, index_to_file(0, 0, 1) - origin};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) grid_to_file.m[r][c] = axes[c][r];
      grid_to_file.m[r][3] = origin[r];
    }
    return std::make_shared<DensityGrid>(dim.x(), dim.y(), dim.z(), std::move(values), to_world * grid_to_file);
  } catch (const std::exception &e) {
    error = "cannot read VDB file '" + path + "': " + e.what();
    return nullptr;
  }
}

}  // namespace rdv
