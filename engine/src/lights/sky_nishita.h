// Blender's Sky Texture of type Nishita, as Cycles 3.4 renders it: sunlight scattered once
// by air (Rayleigh) and dust (Mie) and absorbed by ozone in a spherical atmosphere (Nishita
// et al. 1993), at 21 wavelengths from 380 to 780 nm, to XYZ and scene-linear Rec.709; seen
// from `altitude` above the ground, with the sun's disc (limb darkened) in it.
//
// Cycles tabulates the sky in 512 x 128 texels over longitude and a latitude that packs
// rows toward the horizon, looks them up bilinearly, and draws the disc from two spectra
// (its lower and upper rim). We tabulate the same, then bake the whole sky into an
// equirectangular environment map (lights/environment.h), importance sampled as an HDRI:
// the disc's pixels are supersampled, so its power is kept and it is sampled where it is.
#pragma once
#include <array>
#include <vector>
#include "core/math.h"
#include "core/params.h"

namespace rdv {

class NishitaSky {
 public:
  // Blender's node settings (radians, metres, densities as multipliers of Earth's).
  struct Settings {
    float sun_elevation = 0.261799f;  // 15 degrees
    float sun_rotation = 0;
    float altitude = 0;
    float air_density = 1, dust_density = 1, ozone_density = 1;
    bool sun_disc = true;
    float sun_size = 0.009512f;  // angular diameter, 0.545 degrees
    float sun_intensity = 1;
  };
  // The world's "sky" object (docs/scene-format.md); fails naming the key on bad values.
  static Settings from_params(Params &p);

  explicit NishitaSky(const Settings &s);  // tabulates the sky (about 0.1 s)

  // Radiance toward direction d (unit, world: z up), as Cycles' sky_radiance_nishita.
  Color radiance(Vec3 d) const;
  // The sky in an equirectangular image of width x width / 2 pixels (rows from the zenith,
  // Blender's mapping as EnvironmentMap's), RGB floats: each pixel its centre's radiance,
  // or the mean over 16 x 16 points where the sun's disc may fall in it.
  std::vector<float> bake(int width) const;
  // The sun's direction (unit, world).
  Vec3 sun_direction() const { return sun_dir_; }

  static constexpr int kWidth = 512, kHeight = 128;  // Cycles' texels

 private:
  Color texel_xyz(float x, float y) const;  // bilinear, clamped at the edges (EXTEND)
  Settings s_;
  float rotation_;  // Cycles' internal 2 pi - rotation, in [0, 2 pi)
  Vec3 sun_dir_;
  std::vector<Color> xyz_;  // kWidth x kHeight, row 0 at the horizon
  Color sun_bottom_{0.0f}, sun_top_{0.0f};  // XYZ of the disc's lower and upper rim
};

}  // namespace rdv
