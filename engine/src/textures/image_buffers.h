// Images handed to the scene as binary arrays (rdv_scene_add_image) and named by an image
// texture node ({"node": "image", "buffer": name}) instead of a file: a Blender image
// without a file (generated, painted, made by a script) crosses the C ABI as floats.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "textures/image_texture.h"

namespace rdv {

struct ImageBuffer {
  std::string name;
  std::shared_ptr<const MemoryImage> image;  // shared with the texture nodes that use it
};

// The scene's image buffers; an id is the index, stable for a name (re-adding replaces).
using ImageBuffers = std::vector<ImageBuffer>;

inline const ImageBuffer *find_image_buffer(const ImageBuffers &buffers, const std::string &name) {
  for (const ImageBuffer &b : buffers)
    if (b.name == name) return &b;
  return nullptr;
}

}  // namespace rdv
