#include "textures/shading_point.h"
#include <algorithm>
#include <map>
#include <mutex>
#include "scene/mesh.h"

namespace rdv {

uint32_t attribute_id(const std::string &name) {
  static std::mutex mutex;
  static std::map<std::string, uint32_t> ids;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = ids.find(name);
  if (it != ids.end()) return it->second;
  uint32_t id = uint32_t(ids.size() + 1);  // 0 is never a name
  ids[name] = id;
  return id;
}

bool ShadingPoint::attribute(uint32_t id, float out[4], int &components) const {
  if (!mesh) return false;
  for (const MeshAttribute &a : mesh->attributes) {
    if (a.id != id) continue;
    components = a.components;
    for (int c = 0; c < a.components; ++c)
      out[c] = a.data[size_t(v[0]) * a.components + c] * b[0] + a.data[size_t(v[1]) * a.components + c] * b[1] +
               a.data[size_t(v[2]) * a.components + c] * b[2];
    return true;
  }
  return false;
}

bool ShadingPoint::object_attribute(uint32_t id, float out[4]) const {
  for (uint32_t i = 0; i < num_object_attributes; ++i)
    if (object_attributes[i].id == id) {
      std::copy(object_attributes[i].value, object_attributes[i].value + 4, out);
      return true;
    }
  std::fill(out, out + 4, 0.0f);
  return false;
}

}  // namespace rdv
