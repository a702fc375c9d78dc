#include "bsdfs/registry.h"

namespace rdv {

static Lobe lambert(Color c) {
  Lobe l;
  l.type = LobeType::Lambert;
  l.color = c;
  return l;
}

static Lobe ggx(float roughness_x, float roughness_y, bool gold_fresnel = false) {
  Lobe l;
  l.ggx = {roughness_x * roughness_x, roughness_y * roughness_y};
  l.type = l.ggx.is_smooth() ? LobeType::SpecularConductor : LobeType::GgxConductor;
  l.color = Color(1.0f);
  if (gold_fresnel) {
    l.use_conductor_fresnel = true;
    l.eta = {0.143f, 0.374f, 1.442f};
    l.k = {3.983f, 2.385f, 1.603f};
  }
  return l;
}

const std::vector<LobeTestCase> &lobe_test_cases() {
  static const std::vector<LobeTestCase> cases = {
      {"lambert_white", lambert(Color(1.0f)), true},
      {"lambert_grey", lambert(Color(0.5f)), false},
      {"ggx_r1e-4_mirror", ggx(1e-4f, 1e-4f), false},
      {"ggx_r0.05", ggx(0.05f, 0.05f), false},
      {"ggx_r0.1", ggx(0.1f, 0.1f), false},
      {"ggx_r0.3", ggx(0.3f, 0.3f), false},
      {"ggx_r0.6", ggx(0.6f, 0.6f), false},
      {"ggx_r1", ggx(1.0f, 1.0f), false},
      {"ggx_aniso_0.1x0.5", ggx(0.1f, 0.5f), false},
      {"ggx_gold_r0.3", ggx(0.3f, 0.3f, true), false},
  };
  return cases;
}

}  // namespace rdv
