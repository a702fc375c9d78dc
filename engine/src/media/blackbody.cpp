#include "media/blackbody.h"
#include <array>
#include <mutex>

namespace rdv {

namespace {

// CIE 1931 2-degree standard observer (CIE 015:2018), the 1 nm colour matching functions
// sampled every 5 nm from 360 to 830 nm. A blackbody below 2000 K sends most of its
// visible light through the far-red tail, where analytic fits of these functions err
// by several per cent in green (0.003 in chromaticity y at 1700 K); the table puts the
// colours on the Planckian locus and within 1e-3 of Cycles' at 800 K and 12000 K.
constexpr int kCieSamples = 95;
constexpr double kCieFirstNm = 360, kCieStepNm = 5;
constexpr double kCieX[kCieSamples] = {
    0.0001299, 0.0002321, 0.0004149, 0.0007416, 0.001368, 0.002236, 0.004243, 0.00765, 0.01431, 0.02319,
    0.04351, 0.07763, 0.13438, 0.21477, 0.2839, 0.3285, 0.34828, 0.34806, 0.3362, 0.3187, 0.2908, 0.2511,
    0.19536, 0.1421, 0.09564, 0.05795001, 0.03201, 0.0147, 0.0049, 0.0024, 0.0093, 0.0291, 0.06327, 0.1096,
    0.1655, 0.2257499, 0.2904, 0.3597, 0.4334499, 0.5120501, 0.5945, 0.6784, 0.7621, 0.8425, 0.9163, 0.9786,
    1.0263, 1.0567, 1.0622, 1.0456, 1.0026, 0.9384, 0.8544499, 0.7514, 0.6424, 0.5419, 0.4479, 0.3608, 0.2835,
    0.2187, 0.1649, 0.1212, 0.0874, 0.0636, 0.04677, 0.0329, 0.0227, 0.01584, 0.01135916, 0.008110916,
    0.005790346, 0.004109457, 0.002899327, 0.00204919, 0.001439971, 0.0009999493, 0.0006900786, 0.0004760213,
    0.0003323011, 0.0002348261, 0.0001661505, 0.000117413, 8.307527e-05, 5.870652e-05, 4.150994e-05,
    2.935326e-05, 2.067383e-05, 1.455977e-05, 1.025398e-05, 7.221456e-06, 5.085868e-06, 3.581652e-06,
    2.522525e-06, 1.776509e-06, 1.251141e-06,
};
constexpr double kCieY[kCieSamples] = {
    3.917e-06, 6.965e-06, 1.239e-05, 2.202e-05, 3.9e-05, 6.4e-05, 0.00012, 0.000217, 0.000396, 0.00064,
    0.00121, 0.00218, 0.004, 0.0073, 0.0116, 0.01684, 0.023, 0.0298, 0.038, 0.048, 0.06, 0.0739, 0.09098,
    0.1126, 0.13902, 0.1693, 0.20802, 0.2586, 0.323, 0.4073, 0.503, 0.6082, 0.71, 0.7932, 0.862, 0.9148501,
    0.954, 0.9803, 0.9949501, 1, 0.995, 0.9786, 0.952, 0.9154, 0.87, 0.8163, 0.757, 0.6949, 0.631, 0.5668,
    0.503, 0.4412, 0.381, 0.321, 0.265, 0.217, 0.175, 0.1382, 0.107, 0.0816, 0.061, 0.04458, 0.032, 0.0232,
    0.017, 0.01192, 0.00821, 0.005723, 0.004102, 0.002929, 0.002091, 0.001484, 0.001047, 0.00074, 0.00052,
    0.0003611, 0.0002492, 0.0001719, 0.00012, 8.48e-05, 6e-05, 4.24e-05, 3e-05, 2.12e-05, 1.499e-05, 1.06e-05,
    7.4657e-06, 5.2578e-06, 3.7029e-06, 2.6078e-06, 1.8366e-06, 1.2934e-06, 9.1093e-07, 6.4153e-07,
    4.5181e-07,
};
constexpr double kCieZ[kCieSamples] = {
    0.0006061, 0.001086, 0.001946, 0.003486, 0.006450001, 0.01054999, 0.02005001, 0.03621, 0.06785001, 0.1102,
    0.2074, 0.3713, 0.6456, 1.03905, 1.3856, 1.62296, 1.74706, 1.7826, 1.77211, 1.7441, 1.6692, 1.5281,
    1.28764, 1.0419, 0.8129501, 0.6162, 0.46518, 0.3533, 0.272, 0.2123, 0.1582, 0.1117, 0.07824999,
    0.05725001, 0.04216, 0.02984, 0.0203, 0.0134, 0.008749999, 0.005749999, 0.0039, 0.002749999, 0.0021,
    0.0018, 0.001650001, 0.0014, 0.0011, 0.001, 0.0008, 0.0006, 0.00034, 0.00024, 0.00019, 0.0001,
    4.999999e-05, 3e-05, 2e-05, 1e-05, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
};

// Planck's law up to a constant factor (it cancels in the normalisation).
double planck(double lambda_nm, double kelvin) {
  const double c2 = 1.4387769e-2;  // h c / k_B, metre kelvin
  double l = lambda_nm * 1e-9;
  return 1.0 / (l * l * l * l * l * (std::exp(c2 / (l * kelvin)) - 1.0));
}

Color color_by_integration(double kelvin) {
  double X = 0, Y = 0, Z = 0;
  for (int i = 0; i < kCieSamples; ++i) {
    double p = planck(kCieFirstNm + kCieStepNm * i, kelvin);
    X += p * kCieX[i];
    Y += p * kCieY[i];
    Z += p * kCieZ[i];
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
