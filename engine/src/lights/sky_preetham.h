// Blender's Sky Texture of type Preetham, as Cycles 3.4 renders it: Preetham, Shirley and
// Smits' analytic daylight (SIGGRAPH 1999): Perez et al.'s five-parameter luminance and
// chromaticity distributions, their coefficients linear in the turbidity, scaled so that the
// zenith takes the paper's zenith luminance and chromaticity; xyY to XYZ to scene-linear
// Rec.709, negatives clipped. Below the horizon it holds the horizon's value (Cycles clamps the
// zenith angle there). No sun disc. Baked into an environment map like the Nishita sky.
#pragma once
#include <vector>
#include "core/math.h"
#include "core/params.h"

namespace rdv {

class PreethamSky {
 public:
  struct Settings {
    Vec3 sun_direction{0, 0, 1};  // unit, world (z up)
    float turbidity = 2.2f;
  };
  // The world's "sky" of type "preetham" (docs/scene-format.md); fails naming the key.
  static Settings from_params(Params &p);
  explicit PreethamSky(const Settings &s);
  // Radiance toward direction d (unit, world), as Cycles' sky_radiance_preetham.
  Color radiance(Vec3 d) const;
  // Equirectangular, width x width / 2 pixels, each its centre's radiance (smooth: no disc).
  std::vector<float> bake(int width) const;

 private:
  float sun_theta_, sun_phi_;
  float zenith_Y_, zenith_x_, zenith_y_;      // over the Perez function at the zenith
  float perez_Y_[5], perez_x_[5], perez_y_[5];
};

}  // namespace rdv
