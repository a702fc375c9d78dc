#include "media/blackbody.h"
#include <array>
#include <mutex>

namespace rdv {

namespace {

// CIE 1931 2-degree colour matching functions, the multi-lobe Gaussian fit of Wyman,
// Sloan & Shirley (2013), accurate to a few 1e-3: plenty for a chromaticity.
double lobe(double lambda, double mu, double s1, double s2) {
  double t = (lambda - mu) / (lambda < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}
double cie_x(double l) { return 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2); }
double cie_y(double l) { return 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1); }
double cie_z(double l) { return 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8); }

// Planck's law up to a constant factor (it cancels in the normalisation).
double planck(double lambda_nm, double kelvin) {
  const double c2 = 1.4387769e-2;  // h c / k_B, metre kelvin
  double l = lambda_nm * 1e-9;
  return 1.0 / (l * l * l * l * l * (std::exp(c2 / (l * kelvin)) - 1.0));
}

Color color_by_integration(double kelvin) {
  double X = 0, Y = 0, Z = 0;
  for (double l = 360; l <= 830; l += 1.0) {
    double p = planck(l, kelvin);
    X += p * cie_x(l);
    Y += p * cie_y(l);
    Z += p * cie_z(l);
  }
  // XYZ -> linear Rec.709 (D65 white), then luminance 1.
  double r = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z;
  double g = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z;
  double b = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z;
  return Color(float(std::max(r / Y, 0.0)), float(std::max(g / Y, 0.0)), float(std::max(b / Y, 0.0)));
}

// The colour is smooth in 1/T: a table over 1/T from 1/800 to 1/12000, linearly
// interpolated, computed once.
constexpr float kMinKelvin = 800, kMaxKelvin = 12000;
constexpr int kTableSize = 256;
const std::array<Color, kTableSize> &table() {
  static std::array<Color, kTableSize> t;
  static std::once_flag once;
  std::call_once(once, [] {
    for (int i = 0; i < kTableSize; ++i) {
      double inv = 1.0 / kMaxKelvin + (1.0 / kMinKelvin - 1.0 / kMaxKelvin) * i / (kTableSize - 1);
      t[i] = color_by_integration(1.0 / inv);
    }
  });
  return t;
}

}  // namespace

Color blackbody_color(float kelvin) {
  const auto &t = table();
  float k = std::clamp(kelvin, kMinKelvin, kMaxKelvin);
  float x = (1.0f / k - 1.0f / kMaxKelvin) / (1.0f / kMinKelvin - 1.0f / kMaxKelvin) * (kTableSize - 1);
  int i = std::clamp(int(x), 0, kTableSize - 2);
  float f = std::clamp(x - i, 0.0f, 1.0f);
  return t[i] * (1.0f - f) + t[i + 1] * f;
}

Color Blackbody::radiance(float kelvin) const {
  float T = std::max(kelvin, 0.0f);
  float T4 = (T * T) * (T * T);
  const float sigma = 5.670373e-8f * 1e-6f / kPi;
  float power = sigma * ((1.0f - intensity) + intensity * T4);
  if (!(power > 1e-5f)) return Color(0.0f);  // Cycles' CLOSURE_WEIGHT_CUTOFF
  return tint * blackbody_color(T) * power;
}

}  // namespace rdv
