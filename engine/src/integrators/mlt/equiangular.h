// Equiangular distances toward point-like lamps (Kulla and Fajardo 2012) for path-space
// MLT's camera-side walks through scattering media.
//
// A path that scatters in fog and connects to a small lamp carries 1 / |x - lamp|^2 in f.
// Free flights place x with a density that knows nothing of the lamp, so f / density has
// infinite variance near it: on the point-lamp volume caustic single large steps carried
// 8% of the normalisation b (docs/mlt.md). An equiangular distance along a ray o + t d has
// density ~ 1 / (h^2 + (t - delta)^2) about the lamp's foot delta on the ray (h its
// distance from the ray), which cancels that factor. Camera-side flights draw from the
// one-sample mixture (1 - share) x free flight + share x equiangular toward a lamp chosen
// by power; the density of the mixture is a closed-form function of the path, so every
// acceptance ratio reads it exactly (path_space.cpp: trace_step samples, trace_edge
// evaluates). Light-side walks start at the lamp and keep plain free flights.
//
// Per segment (as free flights: a new draw after each medium boundary) the equiangular
// distance is over t in [0, inf) from the segment's start: with phi(t) = atan2(h, t -
// delta), the angle at the lamp between the ray's far end and the point, phi falls from
// phi(0) to 0, and phi is uniform over it. The flight passes the segment (reaches what ends
// it) when t is beyond the segment's end: probability phi(L) / phi(0).
#pragma once
#include <cmath>
#include <vector>
#include "core/math.h"

namespace rdv::mlt {

class EquiangularTargets {
 public:
  // A lamp's centre and its probability of being chosen (the weights are normalised).
  void add(Vec3 centre, double weight) {
    centres_.push_back(centre);
    weights_.push_back(weight);
  }
  // share: the mixture's probability of an equiangular draw; 0 or no lamps: free flights only.
  void finish(double share) {
    double sum = 0;
    for (double w : weights_) sum += w;
    if (!(sum > 0)) centres_.clear();
    for (double &w : weights_) w /= sum;
    share_ = centres_.empty() ? 0.0 : share;
  }
  bool on() const { return share_ > 0; }
  double share() const { return share_; }

  // The mixture's density of stopping at distance t and of passing a segment of length L,
  // given the free flight's (its stop density and pass probability).
  double stop_density(Vec3 o, Vec3 d, double t, double free_flight_stop) const {
    double eq = 0;
    for (size_t k = 0; k < centres_.size(); ++k) eq += weights_[k] * Line(o, d, centres_[k]).stop_density(t);
    return (1 - share_) * free_flight_stop + share_ * eq;
  }
  double pass_probability(Vec3 o, Vec3 d, double length, double free_flight_pass) const {
    double eq = 0;
    for (size_t k = 0; k < centres_.size(); ++k) eq += weights_[k] * Line(o, d, centres_[k]).pass(length);
    return (1 - share_) * free_flight_pass + share_ * eq;
  }
  // An equiangular distance toward a lamp chosen with u_lamp (kInf: beyond every segment).
  float sample(Vec3 o, Vec3 d, float u_lamp, float u) const {
    size_t k = 0;
    double cdf = weights_[0];
    while (k + 1 < centres_.size() && double(u_lamp) >= cdf) cdf += weights_[++k];
    return Line(o, d, centres_[k]).sample(u);
  }

 private:
  // The lamp seen from the ray o + t d: delta, the foot of the lamp on the ray; h, its
  // distance from the ray (kept off 0, where the ray passes through the lamp's centre, a
  // set of measure zero, the same way for sampling and densities); phi0 = phi(0).
  struct Line {
    double delta, h, phi0;
    Line(Vec3 o, Vec3 d, Vec3 c) {
      // In double: h from the cross product (sqrt(r^2 - delta^2) loses h's digits where the
      // ray passes close to the lamp, exactly where the density peaks).
      const double x = double(c.x) - o.x, y = double(c.y) - o.y, z = double(c.z) - o.z;
      const double dx = d.x, dy = d.y, dz = d.z, inv = 1 / std::sqrt(dx * dx + dy * dy + dz * dz);
      delta = (x * dx + y * dy + z * dz) * inv;
      const double cx = (y * dz - z * dy) * inv, cy = (z * dx - x * dz) * inv, cz = (x * dy - y * dx) * inv;
      h = std::max(std::sqrt(cx * cx + cy * cy + cz * cz), 1e-7 * std::sqrt(x * x + y * y + z * z) + 1e-12);
      phi0 = std::atan2(h, -delta);
    }
    double stop_density(double t) const { return h / ((h * h + (t - delta) * (t - delta)) * phi0); }
    double pass(double length) const { return std::isinf(length) ? 0.0 : std::atan2(h, length - delta) / phi0; }
    float sample(float u) const {
      const double phi = phi0 * (1 - double(u));
      const double s = std::sin(phi);
      if (!(s > 0)) return kInf;
      const double t = delta + h * std::cos(phi) / s;
      return t > 0 && t < double(kInf) ? float(t) : (t > 0 ? kInf : 0.0f);
    }
  };
  std::vector<Vec3> centres_;
  std::vector<double> weights_;
  double share_ = 0;
};

}  // namespace rdv::mlt
