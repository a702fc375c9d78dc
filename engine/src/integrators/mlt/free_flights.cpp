// Exact columns and free flights through grid media (free_flights.h).
#include "integrators/mlt/free_flights.h"
#include <cmath>

namespace rdv::mlt {

namespace {

// A bound on the pieces of one segment (a ray through a 1024^3 grid crosses about 3,000).
constexpr int kMaxPieces = 1 << 16;
// Two-point Gauss-Legendre nodes on [-1, 1]: exact for cubics.
const double kGauss = 1.0 / std::sqrt(3.0);

struct GridSegment {
  const DensityGrid &grid;
  Vec3 o, d;  // in grid coordinates; t is the world distance
  float rho(double t) const { return grid.density(o + d * float(t)); }
  // The integral of the density over [a, b] inside one piece (a cubic there).
  double piece(double a, double b) const {
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    return half * (double(rho(mid - half * kGauss)) + double(rho(mid + half * kGauss)));
  }
};

// Calls f(a, b) for the pieces [a, b] of [0, length] inside the grid box between the
// planes through the voxel centres (x = k + 1/2: the trilinear cells; outside the centres
// the density is clamped, constant along that axis), front to back; f returns false to stop.
template <class F>
void for_each_piece(const GridSegment &s, float length, F &&f) {
  float t_enter, t_exit;
  if (!s.grid.clip(s.o, s.d, length, t_enter, t_exit)) return;
  const int n[3] = {s.grid.nx(), s.grid.ny(), s.grid.nz()};
  double next[3], step[3];
  const double start = t_enter;
  for (int a = 0; a < 3; ++a) {
    const double da = s.d[a], p = double(s.o[a]) + da * start;
    if (da > 0) {
      const double k = std::floor(p - 0.5) + 1;  // the next plane k + 1/2 ahead
      next[a] = k > n[a] - 1 ? kInf : (k + 0.5 - s.o[a]) / da;
      step[a] = 1 / da;
    } else if (da < 0) {
      const double k = std::ceil(p - 0.5) - 1;
      next[a] = k < 0 ? kInf : (k + 0.5 - s.o[a]) / da;
      step[a] = -1 / da;
    } else {
      next[a] = step[a] = kInf;
    }
  }
  double t = start;
  for (int pieces = 0; t < t_exit && pieces < kMaxPieces; ++pieces) {
    const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const double b = std::min(std::max(next[axis], t), double(t_exit));
    if (b > t && !f(t, b)) return;
    t = b;
    next[axis] += step[axis];
  }
}

GridSegment grid_segment(const Medium &m, Vec3 o, Vec3 d) {
  const DensityGrid &g = *m.grid;
  return {g, g.world_to_grid().point(o), g.world_to_grid().vector(d)};
}

// The t in [a, b] at which the integral of the density from a reaches `target` (below
// the piece's integral): Newton's method on the cubic's integral, kept inside a bracket.
double invert_piece(const GridSegment &s, double a, double b, double target) {
  double lo = a, hi = b, t = a + (b - a) * 0.5;
  for (int k = 0; k < 60; ++k) {
    const double value = s.piece(a, t) - target;
    if (value > 0) hi = t;
    else lo = t;
    const double slope = s.rho(t);
    double next = slope > 0 ? t - value / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - t) <= 1e-7 * (b - a) || hi - lo <= 1e-9 * (b - a)) return next;
    t = next;
  }
  return t;
}

}  // namespace

double medium_column(const Medium &m, Vec3 o, Vec3 d, float length) {
  if (!m.is_heterogeneous() || !m.grid) return m.is_heterogeneous() ? 0.0 : double(length);
  const GridSegment s = grid_segment(m, o, d);
  double column = 0;
  for_each_piece(s, length, [&](double a, double b) {
    column += s.piece(a, b);
    return true;
  });
  return column;
}

float medium_density(const Medium &m, Vec3 p) {
  if (!m.is_heterogeneous()) return 1.0f;
  return m.grid ? m.grid->density(m.grid->world_to_grid().point(p)) : 0.0f;
}

float sample_free_flight(const Medium &m, Vec3 o, Vec3 d, float segment, Pcg32 &rng) {
  if (!medium_scatters(m)) return -1;
  const int c = std::min(int(rng.next_float() * 3.0f), 2);
  const float st = m.sigma_t[c];
  const float u = rng.next_float();
  if (!m.is_heterogeneous()) {
    const float t = st > 0 ? -std::log(1.0f - u) / st : kInf;
    return t < segment ? t : -1.0f;
  }
  if (!(st > 0) || !m.grid) return -1;
  // The column at which the flight stops in channel c, found piece by piece.
  double target = -std::log(1.0 - double(u)) / st, t_stop = -1;
  const GridSegment s = grid_segment(m, o, d);
  for_each_piece(s, segment, [&](double a, double b) {
    const double column = s.piece(a, b);
    if (column <= target) {
      target -= column;
      return true;
    }
    t_stop = invert_piece(s, a, b, target);
    return false;
  });
  return t_stop >= 0 && t_stop < segment ? float(t_stop) : -1.0f;
}

}  // namespace rdv::mlt
