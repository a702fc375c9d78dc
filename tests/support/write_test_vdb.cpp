// Writes the .vdb files of the tests: the Blender volume tests' (Blender 3.4 on Debian has
// no pyopenvdb), with voxel size 0.05, and the grid media render test's. One tool, so that
// OpenVDB's headers (28 s of compiling) are compiled once:
//   write_test_vdb out.vdb        "density": a ball of smoke of radius 0.8 (density 1 at the
//                                 centre, falling to 0 at the rim), plus a block of active
//                                 empty (zero) tiles beside it.
//   write_test_vdb out.vdb fire   "density": two balls of radius 0.4 at x = -0.6 and x = +0.6;
//                                 "temperature": 1.5 (x 1000 K in Blender's default material)
//                                 in the left ball only; the right ball is cold (no voxels).
//   write_test_vdb out.vdb ball N "density": the first file's ball (radius 0.8, no empty
//                                 tiles) resolved by N voxels across its radius (benchmarks).
//   write_test_vdb out.vdb slab V0 .. V7
//                                 voxel size 0.1: "density" V0 .. V7 along y (j = -4 .. 3) over
//                                 x, z in [-15, 15) voxels, plus a far block of active zero tiles;
//                                 "smoke" a constant 0.5 over [-16, 15] x [-4, 3] x [-16, 15]
//                                 (the grid media render test, test_media_grid_render.cpp).
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <openvdb/openvdb.h>

namespace {

openvdb::FloatGrid::Ptr make_grid(const char *name, double voxel_size = 0.05) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  grid->setName(name);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size));
  return grid;
}

// Sets value(r) at the voxels of a ball of `radius` voxels around `centre`, r = distance / radius.
template <class F>
void ball(openvdb::FloatGrid &grid, openvdb::Coord centre, int radius, F value) {
  auto acc = grid.getAccessor();
  for (int i = -radius; i <= radius; ++i)
    for (int j = -radius; j <= radius; ++j)
      for (int k = -radius; k <= radius; ++k) {
        double r = std::sqrt(double(i * i + j * j + k * k)) / radius;
        if (r < 1) acc.setValue(centre.offsetBy(i, j, k), float(value(r)));
      }
}

}  // namespace

int main(int argc, char **argv) {
  bool fire = argc == 3 && std::strcmp(argv[2], "fire") == 0;
  bool slab = argc == 11 && std::strcmp(argv[2], "slab") == 0;
  int ball_voxels = argc == 4 && std::strcmp(argv[2], "ball") == 0 ? std::atoi(argv[3]) : 0;
  if (argc != 2 && !fire && !slab && ball_voxels < 1) {
    std::fprintf(stderr, "usage: write_test_vdb out.vdb [fire | ball N | slab V0 .. V7]\n");
    return 2;
  }
  openvdb::initialize();
  if (slab) {
    openvdb::FloatGrid::Ptr density = make_grid("density", 0.1);
    auto acc = density->getAccessor();
    for (int i = -15; i < 15; ++i)
      for (int k = -15; k < 15; ++k)
        for (int j = 0; j < 8; ++j) acc.setValue(openvdb::Coord(i, j - 4, k), float(std::atof(argv[3 + j])));
    density->fill(openvdb::CoordBBox(openvdb::Coord(64, 0, 0), openvdb::Coord(127, 63, 63)), 0.0f, true);
    openvdb::FloatGrid::Ptr smoke = make_grid("smoke", 0.1);
    smoke->fill(openvdb::CoordBBox(openvdb::Coord(-16, -4, -16), openvdb::Coord(15, 3, 15)), 0.5f, true);
    openvdb::io::File(argv[1]).write({density, smoke});
    return 0;
  }
  if (ball_voxels > 0) {
    openvdb::FloatGrid::Ptr grid = make_grid("density", 0.8 / ball_voxels);
    ball(*grid, openvdb::Coord(0), ball_voxels, [](double r) { return 1 - r * r; });
    openvdb::io::File(argv[1]).write({grid});
    return 0;
  }
  openvdb::FloatGrid::Ptr density = make_grid("density");
  if (!fire) {
    ball(*density, openvdb::Coord(0), 16, [](double r) { return 1 - r * r; });
    density->fill(openvdb::CoordBBox(openvdb::Coord(24, -8, -8), openvdb::Coord(39, 7, 7)), 0.0f, true);
    openvdb::io::File(argv[1]).write({density});
    return 0;
  }
  openvdb::FloatGrid::Ptr temperature = make_grid("temperature");
  ball(*density, openvdb::Coord(-12, 0, 0), 8, [](double) { return 1.0; });
  ball(*density, openvdb::Coord(12, 0, 0), 8, [](double) { return 1.0; });
  ball(*temperature, openvdb::Coord(-12, 0, 0), 8, [](double) { return 1.5; });
  openvdb::io::File(argv[1]).write({density, temperature});
  return 0;
}
