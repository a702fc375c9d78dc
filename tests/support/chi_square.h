// Chi-square goodness-of-fit for sampling routines (the method of Mitsuba's and
// pbrt's test suites, described in ../shared/guides/testing.md):
// histogram N sampled directions on a (cos theta, phi) grid, integrate the pdf over
// each cell for the expected counts, pool cells expecting < 5, and compare with
// Pearson's statistic. A sample in a cell whose expected count is 0 fails outright.
#pragma once
#include <cmath>
#include <functional>
#include <string>
#include <vector>
#include "core/math.h"

namespace rdv::test {

// Regularised upper incomplete gamma Q(a, x) (Numerical Recipes' series / continued fraction).
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  double gln = std::lgamma(a);
  if (x < a + 1) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 1000; ++n) {
      ap += 1; del *= x / ap; sum += del;
      if (std::fabs(del) < std::fabs(sum) * 1e-14) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b; if (std::fabs(d) < 1e-300) d = 1e-300;
    c = b + an / c; if (std::fabs(c) < 1e-300) c = 1e-300;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-14) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

// Significance for one of `tests` tests so that the whole suite has false-alarm rate alpha.
inline double sidak(double alpha, int tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / tests); }

struct ChiSquareResult {
  double p_value = 0;
  int dof = 0;
  bool impossible_sample = false;  // a sample where the pdf says 0
  std::string detail;              // worst cells, for the failure message
};

// sample(): returns false when no sample was produced (that probability mass is
// missing from the histogram and from integral(pdf), which must then be < 1).
ChiSquareResult chi_square_directions(const std::function<bool(Vec2 u, Vec3 &dir)> &sample,
                                      const std::function<float(Vec3 dir)> &pdf, int samples,
                                      uint64_t seed, int theta_res = 16, int phi_res = 32);

// Same over an interval [lo, hi] for 1D densities (the pixel filter).
ChiSquareResult chi_square_1d(const std::function<float(float u)> &sample, const std::function<double(double x)> &pdf,
                              double lo, double hi, int samples, uint64_t seed, int bins = 40);

}  // namespace rdv::test

namespace rdv {
// Uniform direction on the upper hemisphere, for tests that need arbitrary pairs.
inline Vec3 uniform_hemisphere_for_test(float u1, float u2) {
  float z = u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
}  // namespace rdv
