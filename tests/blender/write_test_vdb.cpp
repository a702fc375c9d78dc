// Writes the .vdb file of the Blender volume test (Blender 3.4 on Debian has no
// pyopenvdb): a "density" grid of voxel size 0.05 holding a ball of smoke of radius
// 0.8 (density 1 at the centre, falling to 0 at the rim), plus a block of active
// empty (zero) tiles beside it.
//   write_test_vdb out.vdb
#include <cmath>
#include <cstdio>
#include <openvdb/openvdb.h>

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_test_vdb out.vdb\n");
    return 2;
  }
  openvdb::initialize();
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->setTransform(openvdb::math::Transform::createLinearTransform(0.05));
  auto acc = grid->getAccessor();
  for (int i = -16; i <= 16; ++i)
    for (int j = -16; j <= 16; ++j)
      for (int k = -16; k <= 16; ++k) {
        double r = std::sqrt(double(i * i + j * j + k * k)) / 16.0;
        if (r < 1) acc.setValue(openvdb::Coord(i, j, k), float(1 - r * r));
      }
  grid->fill(openvdb::CoordBBox(openvdb::Coord(24, -8, -8), openvdb::Coord(39, 7, 7)), 0.0f, true);
  openvdb::io::File(argv[1]).write({grid});
  return 0;
}
