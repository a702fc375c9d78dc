#include "statistics.h"
#include <algorithm>
#include <cmath>
#include <sstream>

namespace rdv::test {

static double beta_continued_fraction(double a, double b, double x) {
  const double tiny = 1e-300;
  double qab = a + b, qap = a + 1, qam = a - 1, c = 1, d = 1 - qab * x / qap;
  if (std::fabs(d) < tiny) d = tiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m <= 300; ++m) {
    int m2 = 2 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1 + aa * d; if (std::fabs(d) < tiny) d = tiny;
    c = 1 + aa / c; if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1 + aa * d; if (std::fabs(d) < tiny) d = tiny;
    c = 1 + aa / c; if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-14) break;
  }
  return h;
}

double incomplete_beta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  double bt = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log(1 - x));
  if (x < (a + 1) / (a + b + 2)) return bt * beta_continued_fraction(a, b, x) / a;
  return 1 - bt * beta_continued_fraction(b, a, 1 - x) / b;
}

double student_t_two_sided(double t, double dof) {
  return incomplete_beta(dof / 2, 0.5, dof / (dof + t * t));
}

BrightnessComparison compare_brightness(const std::vector<std::vector<double>> &runs_a,
                                        const std::vector<std::vector<double>> &runs_b) {
  auto mean_and_variance = [](const std::vector<std::vector<double>> &runs, double &mean, double &variance) {
    double s = 0, s2 = 0;
    for (const auto &img : runs) {
      double m = 0;
      for (double v : img) m += v;
      m /= double(img.size());
      s += m;
      s2 += m * m;
    }
    const double k = double(runs.size());
    mean = s / k;
    variance = std::max(0.0, s2 / k - mean * mean) / (k - 1);  // of the mean
  };
  BrightnessComparison c;
  double va, vb;
  mean_and_variance(runs_a, c.mean_a, va);
  mean_and_variance(runs_b, c.mean_b, vb);
  c.error = std::sqrt(va + vb);
  c.error_a = std::sqrt(va);
  c.error_b = std::sqrt(vb);
  c.z = c.error > 0 ? (c.mean_a - c.mean_b) / c.error : 0.0;
  return c;
}

BlockComparison compare_blocks(const std::vector<std::vector<double>> &runs_a,
                               const std::vector<std::vector<double>> &runs_b, int width, int height, int block,
                               double alpha) {
  BlockComparison r;
  double sum_a = 0, sum_b = 0;
  std::ostringstream failures;
  for (int by = 0; by + block <= height; by += block)
    for (int bx = 0; bx + block <= width; bx += block) {
      auto block_means = [&](const std::vector<std::vector<double>> &runs) {
        std::vector<double> m;
        for (const auto &img : runs) {
          double s = 0;
          for (int y = by; y < by + block; ++y)
            for (int x = bx; x < bx + block; ++x) s += img[size_t(y) * width + x];
          m.push_back(s / (block * block));
        }
        return m;
      };
      auto stats = [](const std::vector<double> &v, double &mean, double &var) {
        mean = 0;
        for (double x : v) mean += x;
        mean /= v.size();
        var = 0;
        for (double x : v) var += (x - mean) * (x - mean);
        var /= (v.size() - 1);
      };
      double ma, va, mb, vb;
      stats(block_means(runs_a), ma, va);
      stats(block_means(runs_b), mb, vb);
      sum_a += ma;
      sum_b += mb;
      ++r.blocks;
      double na = double(runs_a.size()), nb = double(runs_b.size());
      double se2 = va / na + vb / nb;
      if (se2 <= 0) {
        if (std::fabs(ma - mb) > 1e-6 * std::max(std::fabs(ma), 1e-3)) { ++r.failed; r.worst_p = 0; }
        continue;
      }
      double t = (ma - mb) / std::sqrt(se2);
      // Welch-Satterthwaite degrees of freedom.
      double dof = se2 * se2 / ((va / na) * (va / na) / (na - 1) + (vb / nb) * (vb / nb) / (nb - 1));
      double p = student_t_two_sided(std::fabs(t), dof);
      if (p < r.worst_p) { r.worst_p = p; r.worst_t = t; }
      if (p < alpha) {
        ++r.failed;
        failures << " [block " << bx << "," << by << ": " << ma << " vs " << mb << ", t=" << t << ", p=" << p << "]";
      }
    }
  r.mean_ratio = sum_b > 0 ? sum_a / sum_b : 1;
  std::ostringstream s;
  s << r.failed << "/" << r.blocks << " blocks differ; worst p=" << r.worst_p << " (t=" << r.worst_t
    << "); mean ratio " << r.mean_ratio << failures.str();
  r.detail = s.str();
  return r;
}

}  // namespace rdv::test
