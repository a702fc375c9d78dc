#include "bsdfs/layering.h"
#include <vector>
#include "bsdfs/ggx_albedo.h"
#include "bsdfs/sheen.h"

namespace rdv {

namespace {

// Albedo of the white sheen lobe, tabulated over mu by quadrature (lazily, ~1 ms).
struct SheenTable {
  static constexpr int kN = 33;
  float e[kN], avg = 0;
  SheenTable() {
    Lobe l;
    l.type = LobeType::Sheen;
    for (int i = 0; i < kN; ++i) {
      float mu = std::max(float(i) / (kN - 1), 1e-3f);
      Vec3 wo(safe_sqrt(1 - mu * mu), 0, mu);
      double sum = 0;
      const int n = 64;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {  // cosine-weighted stratified quadrature
          float r = std::sqrt((a + 0.5f) / n), phi = 2 * kPi * (b + 0.5f) / n;
          Vec3 wi(r * std::cos(phi), r * std::sin(phi), safe_sqrt(1 - r * r));
          sum += sheen::eval(l, wo, wi).x * kPi;  // f cos / (cos / pi)
        }
      e[i] = float(sum / (n * n));
    }
    double s = 0, h = 1.0 / (kN - 1);
    for (int i = 0; i + 1 < kN; ++i) {
      double a = i * h;
      s += e[i] * (a * h + h * h / 2) + (e[i + 1] - e[i]) * (a * h / 2 + h * h / 3);
    }
    avg = float(2 * s);
  }
  float at(float mu) const {
    float x = clamp_unit(mu) * (kN - 1);
    int i = std::min(int(x), kN - 2);
    float f = x - i;
    return e[i] * (1 - f) + e[i + 1] * f;
  }
};

const SheenTable &sheen_table() {
  static const SheenTable t;
  return t;
}

Color schlick_avg(Color f0) { return f0 + (Color(1.0f) - f0) * (1.0f / 21.0f); }

}  // namespace

LayerAbove schlick_ggx_layer(Color f0, float alpha, bool separable, bool multiscatter, Color weight) {
  LayerAbove l;
  l.kind = LayerAbove::SchlickGgx;
  l.f0 = f0;
  l.weight = weight;
  l.rows = ggx_albedo_rows(alpha, separable);
  if (multiscatter) {  // Kulla-Conty adds F_ms (1 - E(mu)) (conductor.cpp)
    float eavg = l.rows.eavg;
    Color favg = schlick_avg(f0);
    l.ms = favg * favg * eavg / (Color(1.0f) - favg * (1.0f - eavg));
  }
  l.norm = Color(1.0f) / (Color(1.0f) - layer_average_albedo(l));
  return l;
}

LayerAbove sheen_layer(Color weight) {
  LayerAbove l;
  l.kind = LayerAbove::Sheen;
  l.weight = weight;
  l.norm = Color(1.0f) / (Color(1.0f) - layer_average_albedo(l));
  return l;
}

Color layer_albedo(const LayerAbove &l, float mu) {
  if (l.kind == LayerAbove::Sheen) return l.weight * sheen_table().at(mu);
  float e, e1;
  l.rows.at(mu, e, e1);
  Color a = l.f0 * e + (Color(1.0f) - l.f0) * e1 + l.ms * (1.0f - e);
  return vmin(l.weight * a, Color(0.999f));
}

Color layer_average_albedo(const LayerAbove &l) {
  if (l.kind == LayerAbove::Sheen) return l.weight * sheen_table().avg;
  float eavg = l.rows.eavg;
  Color a = l.f0 * eavg + (Color(1.0f) - l.f0) * l.rows.e1avg + l.ms * (1.0f - eavg);
  return vmin(l.weight * a, Color(0.999f));
}

Color layer_scale(const LayerAbove &l, float mu_o, float mu_i) {
  if (mu_o != l.memo_mu) {
    l.memo_mu = mu_o;
    l.memo_albedo = layer_albedo(l, mu_o);
  }
  return (Color(1.0f) - l.memo_albedo) * (Color(1.0f) - layer_albedo(l, mu_i)) * l.norm;
}

}  // namespace rdv
