#include "bsdfs/ggx_albedo.h"
#include <mutex>
#include <vector>
#include "bsdfs/microfacet.h"

namespace rdv {

namespace {

constexpr int kMu = 32, kRough = 32, kStrata = 48;  // 48 x 48 stratified samples per entry

struct AlbedoTable {
  static float average(const std::vector<float> &t, int r);
  std::vector<float> e, eavg;  // e[r * kMu + m]; table axes: mu = m / (kMu - 1), sqrt(alpha) = r / (kRough - 1)
  std::vector<float> e1, e1avg;  // the Schlick (1 - wo.h)^5 part
  explicit AlbedoTable(bool separable) : e(kMu * kRough), eavg(kRough), e1(kMu * kRough), e1avg(kRough) {
    for (int r = 0; r < kRough; ++r) {
      float rough = float(r) / (kRough - 1);
      float alpha = std::max(rough * rough, 1e-4f);
      GgxDistribution ggx{alpha, alpha, separable};
      for (int m = 0; m < kMu; ++m) {
        float mu = std::max(float(m) / (kMu - 1), 1e-3f);
        Vec3 wo(safe_sqrt(1 - mu * mu), 0, mu);
        double sum = 0, sum1 = 0;
        for (int i = 0; i < kStrata; ++i)
          for (int j = 0; j < kStrata; ++j) {
            Vec2 u{(i + 0.5f) / kStrata, (j + 0.5f) / kStrata};
            Vec3 h = ggx.sample_visible_normal(wo, u);
            float woh = dot(wo, h);
            if (woh <= 0) continue;
            Vec3 wi = h * (2.0f * woh) - wo;
            if (wi.z <= 0) continue;
            float w = ggx.G2(wo, wi) / ggx.G1(wo), s = 1.0f - woh, s2 = s * s;
            sum += w;
            sum1 += w * s2 * s2 * s;
          }
        e[r * kMu + m] = std::min(1.0f, float(sum / (kStrata * kStrata)));
        e1[r * kMu + m] = std::min(1.0f, float(sum1 / (kStrata * kStrata)));
      }
      // E_avg = 2 int_0^1 E(mu) mu dmu, exact for the piecewise-linear interpolant,
      // so the compensation lobe integrates to exactly 1 - E(wo) in the furnace.
      eavg[r] = average(e, r);
      e1avg[r] = average(e1, r);
    }
  }
};

float AlbedoTable::average(const std::vector<float> &t, int r) {
  double avg = 0, h = 1.0 / (kMu - 1);
  for (int m = 0; m + 1 < kMu; ++m) {
    double a = m * h, v0 = t[r * kMu + m], v1 = t[r * kMu + m + 1];
    // int_a^{a+h} (v0 + (v1 - v0)(x - a)/h) x dx
    avg += v0 * (a * h + h * h / 2) + (v1 - v0) * (a * h / 2 + h * h / 3);
  }
  return float(std::min(1.0, 2 * avg));
}

// One table per shadowing term (microfacet.h), each built on first use.
const AlbedoTable &table(bool separable) {
  if (separable) {
    static const AlbedoTable t(true);
    return t;
  }
  static const AlbedoTable t(false);
  return t;
}

void coords(float x, int n, int &i, float &f) {
  x = clamp_unit(x) * (n - 1);
  i = std::min(int(x), n - 2);
  f = x - i;
}


float lookup(const std::vector<float> &e, float mu, float alpha) {
  int m, r;
  float fm, fr;
  coords(mu, kMu, m, fm);
  coords(std::sqrt(std::max(alpha, 0.0f)), kRough, r, fr);
  auto at = [&](int rr, int mm) { return e[rr * kMu + mm]; };
  float e0 = at(r, m) * (1 - fm) + at(r, m + 1) * fm;
  float e1 = at(r + 1, m) * (1 - fm) + at(r + 1, m + 1) * fm;
  return e0 * (1 - fr) + e1 * fr;
}

float lookup_average(const std::vector<float> &avg, float alpha) {
  int r;
  float fr;
  coords(std::sqrt(std::max(alpha, 0.0f)), kRough, r, fr);
  return avg[r] * (1 - fr) + avg[r + 1] * fr;
}

}  // namespace

GgxAlbedoRows ggx_albedo_rows(float alpha, bool separable) {
  const AlbedoTable &t = table(separable);
  int r;
  GgxAlbedoRows rows;
  coords(std::sqrt(std::max(alpha, 0.0f)), kRough, r, rows.fr);
  rows.e = &t.e[size_t(r) * kMu];
  rows.e1 = &t.e1[size_t(r) * kMu];
  rows.eavg = t.eavg[r] * (1 - rows.fr) + t.eavg[r + 1] * rows.fr;
  rows.e1avg = t.e1avg[r] * (1 - rows.fr) + t.e1avg[r + 1] * rows.fr;
  return rows;
}

void GgxAlbedoRows::at(float mu, float &e_mu, float &e1_mu) const {
  int m;
  float fm;
  coords(mu, kMu, m, fm);
  auto interp = [&](const float *row) {
    float v0 = row[m] * (1 - fm) + row[m + 1] * fm;
    float v1 = row[kMu + m] * (1 - fm) + row[kMu + m + 1] * fm;
    return v0 * (1 - fr) + v1 * fr;
  };
  e_mu = interp(e);
  e1_mu = interp(e1);
}

float ggx_schlick_albedo(float mu, float alpha, bool separable) { return lookup(table(separable).e1, mu, alpha); }
float ggx_schlick_average_albedo(float alpha, bool separable) {
  return lookup_average(table(separable).e1avg, alpha);
}
float ggx_albedo(float mu, float alpha, bool separable) { return lookup(table(separable).e, mu, alpha); }
float ggx_average_albedo(float alpha, bool separable) { return lookup_average(table(separable).eavg, alpha); }

}  // namespace rdv
