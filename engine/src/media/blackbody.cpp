#include "media/blackbody.h"
#include "core/cie_1931.h"
#include <array>
#include <mutex>

namespace rdv {

namespace {

// Planck's law up to a constant factor (it cancels in the normalisation).
double planck(double lambda_nm, double kelvin) {
  const double c2 = 1.4387769e-2;  // h c / k_B, metre kelvin
  double l = lambda_nm * 1e-9;
  return 1.0 / (l * l * l * l * l * (std::exp(c2 / (l * kelvin)) - 1.0));
}

Color color_by_integration(double kelvin) {
  double X = 0, Y = 0, Z = 0;
  for (int i = 0; i < cie::kSamples; ++i) {
    double p = planck(cie::kFirstNm + cie::kStepNm * i, kelvin);
    X += p * cie::kX[i];
    Y += p * cie::kY[i];
    Z += p * cie::kZ[i];
  }
  // Linear Rec.709, then luminance 1.
  double r, g, b;
  cie::xyz_to_rec709(X, Y, Z, r, g, b);
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
