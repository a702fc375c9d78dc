// The JSON scene file (docs/scene-format.md): replays its objects as C ABI calls, so
// the command-line renderer, the tests and the add-on's bug-report dumps all drive the
// engine exactly as Blender does.
#pragma once
#include <string>
#include <vector>
#include "rendezvous.h"

namespace rdv_tools {

struct LoadedScene {
  std::string settings_json;          // the file's "settings" object
  std::vector<std::string> problems;  // objects that were skipped or replaced, with reasons
};

// Loads `path` into `scene`. An object with bad data is reported in problems and
// left out (a bad material is replaced by Blender's magenta); a file that cannot be
// read or parsed throws std::runtime_error with a message naming the file.
struct LoadOptions {
  // false: the shutter stays closed (motion blur off: the camera's shutter and every
  // "motion" are ignored; objects render at their "transform").
  bool motion_blur = true;
};
LoadedScene load_scene_file(const std::string &path, rdv_scene *scene, const LoadOptions &options = {});
// Same, from JSON text; base_dir resolves "binary" side files.
LoadedScene load_scene_json(const std::string &text, const std::string &base_dir, rdv_scene *scene,
                            const LoadOptions &options = {});

}  // namespace rdv_tools
