// Dense grids handed to the scene as binary arrays (rdv_scene_add_grid) and named by a
// medium's grid JSON ({"buffer": name}) instead of a "values" list: a simulation domain's
// voxels then cross the C ABI as floats, not as JSON text.
#pragma once
#include <string>
#include <vector>

namespace rdv {

struct GridBuffer {
  std::string name;
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> values;  // nx*ny*nz, x fastest (the layout of the JSON "values")
};

// The scene's grid buffers; an id is the index, stable for a name (re-adding replaces).
using GridBuffers = std::vector<GridBuffer>;

inline const GridBuffer *find_grid_buffer(const GridBuffers &buffers, const std::string &name) {
  for (const GridBuffer &b : buffers)
    if (b.name == name) return &b;
  return nullptr;
}

}  // namespace rdv
