#include "scene/ray_visibility.h"

namespace rdv::visibility {

uint32_t parse(const nlohmann::json *value, const std::string &what, uint32_t fallback) {
  if (!value) return fallback;
  static constexpr struct { const char *key; uint32_t bit; } kKeys[] = {
      {"camera", kCamera}, {"diffuse", kDiffuse}, {"glossy", kGlossy},
      {"transmission", kTransmission}, {"shadow", kShadow}, {"volume_scatter", kScatter}};
  if (!value->is_object())
    fail(what + ": parameter 'visibility' must be an object of camera, diffuse, glossy, transmission, shadow, "
                "volume_scatter: true or false, got " + value->dump());
  uint32_t bits = fallback & kAll;
  for (auto it = value->begin(); it != value->end(); ++it) {
    uint32_t bit = 0;
    for (const auto &k : kKeys)
      if (it.key() == k.key) bit = k.bit;
    if (!bit)
      fail(what + ": 'visibility' has an unknown key '" + it.key() +
           "' (camera, diffuse, glossy, transmission, shadow, volume_scatter)");
    if (!it.value().is_boolean())
      fail(what + ": 'visibility." + it.key() + "' must be true or false, got " + it.value().dump());
    bits = it.value().get<bool>() ? bits | bit : bits & ~bit;
  }
  return bits;
}

}  // namespace rdv::visibility
