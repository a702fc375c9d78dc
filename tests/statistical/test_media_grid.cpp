// Grid (heterogeneous) media: delta tracking, ratio tracking and random-offset ray
// marching against closed forms and fine quadratures of the optical depth. Each check
// is a z-test at |z| < 4.5 (false alarm 6.8e-6 per check, < 1e-3 over this file);
// fixed seeds.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "core/hash.h"
#include "media/emission_gather.h"
#include "media/medium.h"

namespace test_media_grid {

using namespace rdv;
using nlohmann::json;

namespace {

// A medium whose density ramps linearly along x: voxel i (of 32) holds 0.2 + 2.8 (i+0.5)/32,
// so inside x in [0.5, 31.5]/32 of the unit box the trilinear density is exactly
// rho(x) = 0.2 + 2.8 x. Chromatic coefficients per unit density.
Medium ramp_medium(const std::string &method = "tracking", float scale = 1.0f) {
  std::vector<float> v;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 32; ++i) v.push_back(0.2f + 2.8f * (i + 0.5f) / 32.0f);
  json p = {{"sigma_a", {0.3 * scale, 0.8 * scale, 1.6 * scale}}, {"sigma_s", {1.2 * scale, 0.5 * scale, 0.1 * scale}},
            {"emission", {0.5, 0.2, 0.1}}, {"method", method},
            {"grid", {{"resolution", {32, 4, 4}}, {"values", v}}}};
  Params params(p.dump(), "ramp volume");
  Medium m = Medium::from_params(params, "ramp");
  params.check_all_used();
  return m;
}
double ramp_density(double x) { return 0.2 + 2.8 * x; }

struct Segment {
  Vec3 o, d;
  float length;
};
// Segments inside the exact-ramp region, in various directions.
std::vector<Segment> ramp_segments() {
  std::vector<Segment> s;
  auto add = [&](Vec3 a, Vec3 b) { s.push_back({a, normalize(b - a), length(b - a)}); };
  add(Vec3(0.05f, 0.5f, 0.5f), Vec3(0.95f, 0.5f, 0.5f));  // along the ramp
  add(Vec3(0.9f, 0.1f, 0.2f), Vec3(0.1f, 0.8f, 0.9f));    // diagonal, down the ramp
  add(Vec3(0.6f, 0.0f, 0.3f), Vec3(0.6f, 1.0f, 0.7f));    // across it (constant density)
  return s;
}
// Optical depth per unit sigma_t along a segment: the density is linear along it.
double ramp_depth(const Segment &s, double t) {
  double x0 = s.o.x, x1 = s.o.x + s.d.x * t;
  return t * 0.5 * (ramp_density(x0) + ramp_density(x1));
}

struct Stat {
  double sum = 0, sum2 = 0;
  int n = 0;
  void add(double v) { sum += v; sum2 += v * v; ++n; }
  double mean() const { return sum / n; }
  double se() const { return std::sqrt(std::max(0.0, sum2 / n - mean() * mean()) / n); }
};

void expect_z(const Stat &s, double expected, const std::string &what) {
  double z = (s.mean() - expected) / std::hypot(s.se(), 1e-6 * std::fabs(expected) + 1e-9);
  EXPECT_LT(std::fabs(z), 4.5) << what << ": mean " << s.mean() << " expected " << expected << " se " << s.se();
}

}  // namespace

// Ratio tracking: E[T_hat] = exp(-sigma_t tau) in every channel.
TEST(GridTracking, RatioTrackingIsUnbiasedOnARamp) {
  Medium m = ramp_medium();
  SampleRun rng{Pcg32(11)};
  int seg_index = 0;
  for (const Segment &s : ramp_segments()) {
    Stat st[3];
    for (int i = 0; i < 200000; ++i) {
      Color tr = m.transmittance(s.o, s.d, s.length, rng);
      for (int c = 0; c < 3; ++c) st[c].add(tr[c]);
    }
    for (int c = 0; c < 3; ++c)
      expect_z(st[c], std::exp(-m.sigma_t[c] * ramp_depth(s, s.length)),
               "segment " + std::to_string(seg_index) + " channel " + std::to_string(c));
    ++seg_index;
  }
}

// Delta (spectral) tracking: passing weight -> T, scattering weight -> albedo (1 - T)
// split into distance bins albedo (T(a) - T(b)); gathered emission (a volume light's
// random-offset points with ratio-tracked transmittance) -> integral of T emission.
TEST(GridTracking, DeltaTrackingIsUnbiasedOnARamp) {
  Medium m = ramp_medium();
  int seg_index = 0;
  for (const Segment &s : ramp_segments()) {
    const int bins = 4, n = 300000;
    Stat pass[3], scatter[bins][3], emitted[3];
    Medium light = m;  // as the scene makes it a volume light
    light.light = 0;
    light.emission_step = s.length / 7.3f;
    light.light_lo = vmin(s.o, s.o + s.d * s.length) - Vec3(1.0f);
    light.light_hi = vmax(s.o, s.o + s.d * s.length) + Vec3(1.0f);
    for (int i = 0; i < n; ++i) {
      SampleRun u{Pcg32(hash_u32(i) ^ (uint64_t(seg_index) << 40), 7)};
      MediumSample ms = m.sample_distance(s.o, s.d, s.length, u);
      Color gathered(0.0f);
      gather_emission(light, s.o, s.d, s.length, u, [&](Vec3, Color c, float) { gathered += c; });
      int bin = ms.scattered ? std::min(int(ms.t / s.length * bins), bins - 1) : -1;
      for (int c = 0; c < 3; ++c) {
        pass[c].add(ms.scattered ? 0.0 : ms.weight[c]);
        for (int b = 0; b < bins; ++b) scatter[b][c].add(bin == b ? ms.weight[c] : 0.0);
        emitted[c].add(gathered[c]);
      }
    }
    std::string what = "segment " + std::to_string(seg_index);
    for (int c = 0; c < 3; ++c) {
      auto T = [&](double t) { return std::exp(-m.sigma_t[c] * ramp_depth(s, t)); };
      expect_z(pass[c], T(s.length), what + " pass, channel " + std::to_string(c));
      double albedo = m.sigma_s[c] / m.sigma_t[c];
      for (int b = 0; b < bins; ++b) {
        double a = s.length * b / bins, e = s.length * (b + 1) / bins;
        expect_z(scatter[b][c], albedo * (T(a) - T(e)), what + " scatter bin " + std::to_string(b) + ", channel " + std::to_string(c));
      }
      double integral = 0;  // Simpson's rule, 2000 intervals (error << the test's se)
      for (int k = 0; k <= 2000; ++k) {
        double t = s.length * k / 2000, w = (k == 0 || k == 2000) ? 1 : (k % 2 ? 4 : 2);
        integral += w * T(t);
      }
      integral *= s.length / 2000 / 3 * m.emission[c];
      expect_z(emitted[c], integral, what + " emission, channel " + std::to_string(c));
    }
    ++seg_index;
  }
}

// A random sparse grid (not a multiple of the majorant cell size, with empty blocks
// and sharp peaks) placed by a rotation and scale: ratio tracking against a fine
// quadrature of the trilinear density along random rays. A majorant or DDA error
// (a cell whose bound is too low, a skipped cell) shows as bias here.
TEST(GridTracking, RatioTrackingThroughASparseRotatedGrid) {
  const int nx = 40, ny = 23, nz = 17;
  Pcg32 g(3);
  std::vector<float> v(size_t(nx) * ny * nz, 0.0f);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        bool empty_block = (i / 16 + j / 16) % 2 == 1;
        float r = g.next_float();
        v[(size_t(k) * ny + j) * nx + i] = empty_block ? 0.0f : (r > 0.97f ? 12.0f * r : 0.6f * r);
      }
  json p = {{"sigma_a", {0.5, 0.9, 1.4}}, {"sigma_s", {1.0, 0.4, 0.2}},
            {"grid", {{"resolution", {nx, ny, nz}}, {"values", v}, {"bounds", {{-1, -0.5, -0.4}, {1, 0.6, 0.45}}},
                      {"transform", {{"rotate", {20, -35, 50}}, {"scale", {1.3, 0.9, 1.1}}}}}}};
  Params params(p.dump(), "sparse volume");
  Medium m = Medium::from_params(params, "sparse");
  SampleRun rng{Pcg32(17)};
  for (int ray = 0; ray < 6; ++ray) {
    Vec3 o(4 * rng.next_float() - 2, 4 * rng.next_float() - 2, 4 * rng.next_float() - 2);
    Vec3 target(0.4f * rng.next_float() - 0.2f, 0.4f * rng.next_float() - 0.2f, 0.2f * rng.next_float() - 0.1f);
    Vec3 d = normalize(target - o);
    float len = 2 * length(target - o);
    // Optical depth per unit sigma_t by the midpoint rule on 200000 steps.
    double depth = 0;
    const int steps = 200000;
    Vec3 go = m.grid->world_to_grid().point(o), gd = m.grid->world_to_grid().vector(d);
    for (int k = 0; k < steps; ++k) depth += m.grid->density(go + gd * float(len * (k + 0.5) / steps));
    depth *= len / steps;
    Stat st[3];
    for (int i = 0; i < 100000; ++i) {
      Color tr = m.transmittance(o, d, len, rng);
      for (int c = 0; c < 3; ++c) st[c].add(tr[c]);
    }
    for (int c = 0; c < 3; ++c) {
      double expected = std::exp(-m.sigma_t[c] * depth);
      double z = (st[c].mean() - expected) / std::hypot(st[c].se(), 2e-4 * expected + 1e-7);  // + quadrature error
      EXPECT_LT(std::fabs(z), 4.5) << "ray " << ray << " channel " << c << ": " << st[c].mean() << " vs " << expected
                                   << " (depth " << depth << ")";
    }
  }
}

// A grid of one voxel is a homogeneous box: tracking matches Beer-Lambert.
TEST(GridTracking, OneVoxelGridIsHomogeneous) {
  json p = {{"density", 2.0}, {"color", 0.7}, {"grid", {{"resolution", {1, 1, 1}}, {"values", {1.5}}}}};
  Params params(p.dump(), "one voxel");
  Medium m = Medium::from_params(params, "one");
  SampleRun rng{Pcg32(5)};
  Stat tr, pass;
  Vec3 o(0.1f, 0.2f, 0.0f), d = normalize(Vec3(0.2f, 0.1f, 1.0f));
  float len = 1.0f / d.z;
  for (int i = 0; i < 100000; ++i) {
    tr.add(m.transmittance(o, d, len, rng).x);
    MediumSample s = m.sample_distance(o, d, len, rng);
    pass.add(s.scattered ? 0.0 : s.weight.x);
  }
  double expected = std::exp(-m.sigma_t.x * 1.5 * len);
  expect_z(tr, expected, "ratio tracking");
  expect_z(pass, expected, "delta tracking");
}

// Ray marching is approximate, but with a step of one voxel on a smooth ramp it is
// within 1% of the exact transmittance, and its distance sampling keeps the
// balance between passing and scattering (albedo (1 - T) + T).
TEST(GridRayMarching, CloseToExactOnARamp) {
  Medium m = ramp_medium("ray_marching");
  SampleRun rng{Pcg32(23)};
  for (const Segment &s : ramp_segments()) {
    Stat tr[3], pass[3];
    for (int i = 0; i < 20000; ++i) {
      Color t = m.transmittance(s.o, s.d, s.length, rng);
      MediumSample ms = m.sample_distance(s.o, s.d, s.length, rng);
      for (int c = 0; c < 3; ++c) {
        tr[c].add(t[c]);
        pass[c].add(ms.scattered ? 0.0 : ms.weight[c]);
      }
    }
    for (int c = 0; c < 3; ++c) {
      double exact = std::exp(-m.sigma_t[c] * ramp_depth(s, s.length));
      EXPECT_NEAR(tr[c].mean(), exact, 0.01 * exact + 1e-4) << "channel " << c;
      EXPECT_NEAR(pass[c].mean(), exact, 0.01 * exact + 4.5 * pass[c].se()) << "channel " << c;
    }
  }
}

// Extremes stay finite and bounded in work: densities 1e-6 .. 1e5, albedo 0 and 1.
TEST(GridTracking, ExtremesStayFinite) {
  for (const char *method : {"tracking", "ray_marching"})
    for (double density : {1e-6, 1.0, 1e5})
      for (double albedo : {0.0, 1.0}) {
        json p = {{"density", density}, {"color", albedo}, {"method", method},
                  {"grid", {{"resolution", {3, 2, 2}}, {"values", {0, 1, 0.5, 2, 0, 0, 1, 1, 3, 0, 0.1, 5}}}}};
        Params params(p.dump(), "extreme");
        Medium m = Medium::from_params(params, "x");
        SampleRun rng{Pcg32(1)};
        for (int i = 0; i < 300; ++i) {
          Vec3 o(rng.next_float(), rng.next_float(), -0.5f), d = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1));
          Color tr = m.transmittance(o, d, 3.0f, rng);
          MediumSample s = m.sample_distance(o, d, 3.0f, rng);
          ASSERT_TRUE(is_finite(tr) && is_finite(s.weight) && std::isfinite(s.t))
              << method << " density " << density << " albedo " << albedo;
          ASSERT_TRUE(min_component(tr) >= 0 && min_component(s.weight) >= 0);
        }
      }
}

// One dense voxel at the edge of a majorant cell (voxel 15 of 32 along x): its
// trilinear support reaches half a voxel into the next cell, whose majorant must
// cover it. Along the whole box (both directions) the optical depth is exactly
// voxel size x the sum of the values.
TEST(GridTracking, PeakAtAMajorantCellEdge) {
  std::vector<float> v(32, 0.0f);
  v[15] = 40.0f;
  json p = {{"sigma_a", 0.6}, {"sigma_s", 0.4}, {"grid", {{"resolution", {32, 1, 1}}, {"values", v}}}};
  Params params(p.dump(), "peak");
  Medium m = Medium::from_params(params, "peak");
  const double expected = std::exp(-1.0 * 40.0 / 32.0);
  SampleRun rng{Pcg32(31)};
  for (float dir : {1.0f, -1.0f}) {
    Vec3 o(dir > 0 ? -0.5f : 1.5f, 0.5f, 0.5f), d(dir, 0, 0);
    Stat tr, pass;
    for (int i = 0; i < 200000; ++i) {
      tr.add(m.transmittance(o, d, 2.0f, rng).x);
      MediumSample s = m.sample_distance(o, d, 2.0f, rng);
      pass.add(s.scattered ? 0.0 : s.weight.x);
    }
    expect_z(tr, expected, dir > 0 ? "ratio tracking +x" : "ratio tracking -x");
    expect_z(pass, expected, dir > 0 ? "delta tracking +x" : "delta tracking -x");
  }
}

}  // namespace test_media_grid
