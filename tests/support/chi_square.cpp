#include "chi_square.h"
#include <algorithm>
#include <numeric>
#include <sstream>
#include "core/hash.h"

namespace rdv::test {

namespace {

Vec3 grid_direction(double cos_theta, double phi) {
  double s = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  return {float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta)};
}

// Integral of pdf over a (cos theta, phi) rectangle: Simpson on a 3x3 grid, refined
// adaptively, and never coarser than `min_depth` splits, so sharp peaks are found.
double integrate_cell(const std::function<float(Vec3)> &pdf, double c0, double c1, double p0, double p1,
                      int depth, int min_depth) {
  auto simpson = [&](double a0, double a1, double b0, double b1) {
    static const double w[3] = {1, 4, 1};
    double sum = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double c = a0 + (a1 - a0) * i / 2, p = b0 + (b1 - b0) * j / 2;
        sum += w[i] * w[j] * pdf(grid_direction(c, p));
      }
    return sum * (a1 - a0) * (b1 - b0) / 36.0;
  };
  double cm = 0.5 * (c0 + c1), pm = 0.5 * (p0 + p1);
  if (depth < min_depth)
    return integrate_cell(pdf, c0, cm, p0, pm, depth + 1, min_depth) +
           integrate_cell(pdf, cm, c1, p0, pm, depth + 1, min_depth) +
           integrate_cell(pdf, c0, cm, pm, p1, depth + 1, min_depth) +
           integrate_cell(pdf, cm, c1, pm, p1, depth + 1, min_depth);
  double whole = simpson(c0, c1, p0, p1);
  double parts = simpson(c0, cm, p0, pm) + simpson(cm, c1, p0, pm) + simpson(c0, cm, pm, p1) + simpson(cm, c1, pm, p1);
  if (depth >= 14 || std::fabs(parts - whole) <= 1e-6 * std::max(1.0, std::fabs(parts)) + 1e-12) return parts;
  return integrate_cell(pdf, c0, cm, p0, pm, depth + 1, min_depth) +
         integrate_cell(pdf, cm, c1, p0, pm, depth + 1, min_depth) +
         integrate_cell(pdf, c0, cm, pm, p1, depth + 1, min_depth) +
         integrate_cell(pdf, cm, c1, pm, p1, depth + 1, min_depth);
}

ChiSquareResult pearson(const std::vector<double> &observed, const std::vector<double> &expected, double total) {
  ChiSquareResult r;
  // Pool the cells expecting fewer than 5 samples into one.
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  double chi2 = 0, pooled_obs = 0, pooled_exp = 0;
  int cells = 0;
  std::vector<std::pair<double, size_t>> worst;
  for (size_t i : order) {
    if (expected[i] <= 0 && observed[i] > 0) {
      r.impossible_sample = true;
      std::ostringstream s;
      s << "cell " << i << " got " << observed[i] << " samples where the pdf integrates to 0; ";
      r.detail += s.str();
    }
    if (expected[i] < 5) { pooled_obs += observed[i]; pooled_exp += expected[i]; continue; }
    double d = observed[i] - expected[i];
    double term = d * d / expected[i];
    chi2 += term;
    worst.push_back({term, i});
    ++cells;
  }
  // Mass the pdf has but the sampler never produced (sample() returning false) counts too.
  double missing = total - std::accumulate(expected.begin(), expected.end(), 0.0);
  (void)missing;
  if (pooled_exp >= 5) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++cells;
  } else if (pooled_obs > 5 * std::max(pooled_exp, 1.0)) {
    r.impossible_sample = true;
    r.detail += "pooled low-density cells got " + std::to_string(pooled_obs) + " samples, expected " +
                std::to_string(pooled_exp) + "; ";
  }
  r.dof = std::max(cells - 1, 1);
  r.p_value = gamma_q(r.dof / 2.0, chi2 / 2.0);
  std::sort(worst.rbegin(), worst.rend());
  std::ostringstream s;
  s << "chi2=" << chi2 << " dof=" << r.dof << " p=" << r.p_value << "; worst cells:";
  for (size_t k = 0; k < std::min<size_t>(4, worst.size()); ++k)
    s << " [" << worst[k].second << ": observed " << observed[worst[k].second] << ", expected "
      << expected[worst[k].second] << "]";
  r.detail += s.str();
  return r;
}

}  // namespace

ChiSquareResult chi_square_directions(const std::function<bool(Vec2, Vec3 &)> &sample,
                                      const std::function<float(Vec3)> &pdf, int samples, uint64_t seed,
                                      int theta_res, int phi_res) {
  std::vector<double> observed(size_t(theta_res) * phi_res, 0.0), expected(observed.size(), 0.0);
  Pcg32 rng(seed);
  for (int i = 0; i < samples; ++i) {
    Vec3 d;
    float a = rng.next_float();
    Vec2 u{a, rng.next_float()};
    if (!sample(u, d)) continue;
    double c = std::clamp<double>(d.z, -1.0, 1.0);
    double phi = std::atan2(double(d.y), double(d.x));
    if (phi < 0) phi += 2 * M_PI;
    int ti = std::clamp(int((c + 1) * 0.5 * theta_res), 0, theta_res - 1);
    int pi = std::clamp(int(phi / (2 * M_PI) * phi_res), 0, phi_res - 1);
    observed[size_t(ti) * phi_res + pi] += 1;
  }
  for (int ti = 0; ti < theta_res; ++ti)
    for (int pi = 0; pi < phi_res; ++pi) {
      double c0 = -1 + 2.0 * ti / theta_res, c1 = -1 + 2.0 * (ti + 1) / theta_res;
      double p0 = 2 * M_PI * pi / phi_res, p1 = 2 * M_PI * (pi + 1) / phi_res;
      expected[size_t(ti) * phi_res + pi] = samples * integrate_cell(pdf, c0, c1, p0, p1, 0, 3);
    }
  return pearson(observed, expected, samples);
}

ChiSquareResult chi_square_1d(const std::function<float(float)> &sample, const std::function<double(double)> &pdf,
                              double lo, double hi, int samples, uint64_t seed, int bins) {
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  Pcg32 rng(seed);
  for (int i = 0; i < samples; ++i) {
    double x = sample(rng.next_float());
    int b = std::clamp(int((x - lo) / (hi - lo) * bins), 0, bins - 1);
    observed[b] += 1;
  }
  for (int b = 0; b < bins; ++b) {
    double a = lo + (hi - lo) * b / bins, c = lo + (hi - lo) * (b + 1) / bins, sum = 0;
    const int n = 64;
    for (int k = 0; k < n; ++k) sum += pdf(a + (c - a) * (k + 0.5) / n);
    expected[b] = samples * sum * (c - a) / n;
  }
  return pearson(observed, expected, samples);
}

}  // namespace rdv::test
