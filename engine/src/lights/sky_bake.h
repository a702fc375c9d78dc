// Baking a sky model into an equirectangular image for EnvironmentMap (rows from the zenith,
// Blender's mapping: +X at the image's centre), shared by the Nishita and Preetham skies.
#pragma once
#include <cmath>
#include <vector>
#include <tbb/parallel_for.h>
#include "core/math.h"

namespace rdv {

// The direction through (u, v), in pixels from the left and the top of a width x width / 2 image.
inline Vec3 sky_direction(int width, double u, double v) {
  const int height = width / 2;
  const double theta = v / height * kPi, phi = (0.5 - u / width) * 2 * kPi;
  return Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)));
}

// RGB floats, width x width / 2 pixels, pixel (i, j) = pixel(i, j) (a Color), rows in parallel.
template <class Pixel>
std::vector<float> bake_sky(int width, const Pixel &pixel) {
  const int height = width / 2;
  std::vector<float> rgb(size_t(width) * height * 3);
  tbb::parallel_for(0, height, [&](int j) {
    for (int i = 0; i < width; ++i) {
      const Color c = pixel(i, j);
      float *px = &rgb[(size_t(j) * width + size_t(i)) * 3];
      px[0] = c.x;
      px[1] = c.y;
      px[2] = c.z;
    }
  });
  return rgb;
}

}  // namespace rdv
