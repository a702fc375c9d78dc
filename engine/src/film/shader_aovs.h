// Shader AOVs (Blender's View Layer > Shader AOV with the AOV Output node, as Cycles 3.4
// writes them, kernel/svm/aov.h): passes a material fills from its AOV Output nodes.
//
// A camera sample writes them along its see-through chain, at each surface up to and
// including the first that sets the Object / Material Index (film/data_passes.h: the first
// at or above View Layer > Alpha Threshold), whatever the throughput: a colour pass adds
// (r, g, b, 1), a value pass v. The pixel reads the sums over its samples, so a colour pass's
// alpha is the share of samples that wrote it. The world writes none. Each pass takes a
// material's AOV Output of its name (the Color input for a colour pass, the Value input for a
// value pass); a material without one leaves the pass at 0 there.
#pragma once
#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rdv {

struct ShaderAovs {
  static constexpr int kMaxPasses = 16, kMaxChannels = 4 * kMaxPasses;
  struct Pass {
    std::string name;
    uint32_t id = 0;     // attribute_id of the name (textures/shading_point.h), for lookups
    bool color = true;   // 4 channels (r, g, b, writes), or 1 (value)
    int offset = 0;      // of its first channel in a pixel's channels
  };
  std::vector<Pass> passes;
  int channels = 0;

  // From the render setting "aovs": [{"name": "mask", "type": "color" | "value"}, ...]
  // (null: none). Malformed input throws (fail()).
  static ShaderAovs parse(const nlohmann::json *j);
  nlohmann::json to_json() const;  // parse's input again (null: none; render parts)
  bool empty() const { return passes.empty(); }
  const Pass *find(uint32_t id) const {
    for (const Pass &p : passes)
      if (p.id == id) return &p;
    return nullptr;
  }
};

// One camera sample's writes (DataPassSample::aovs): `values` holds layout->channels numbers
// (the rest untouched: a render without shader AOVs neither clears nor copies them).
struct AovSample {
  const ShaderAovs *layout = nullptr;
  float values[ShaderAovs::kMaxChannels];
  void start(const ShaderAovs *aovs) {
    layout = aovs && !aovs->empty() ? aovs : nullptr;
    if (layout) std::fill_n(values, layout->channels, 0.0f);
  }
  bool active() const { return layout != nullptr; }
};

}  // namespace rdv
