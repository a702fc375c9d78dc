// Free flights through media for path-space MLT (path_space.h), with densities that are
// exact functions of the path: a mutation's acceptance ratio needs the density of the
// distance it sampled in both directions, and f needs the transmittance, so both must be
// computed, not estimated.
//
// Everything is a function of the segment's column: the integral of the medium's density
// along it (homogeneous media: density 1, the column is the length). Grid media
// (media/density_grid.h) are trilinear in the voxel centres, so along a ray the density is
// a cubic polynomial between the planes through the voxel centres: each piece's integral
// is exact with two-point Gauss-Legendre quadrature, and the column of a segment is the
// sum over the pieces it crosses (a DDA over the voxel-centre lattice). The free flight
// picks one colour channel c uniformly and an optical depth E ~ Exp(1), and stops where
// sigma_t,c x column(t) = E (the column inverted piece by piece, Newton's method with
// bisection inside the piece); its density at t is avg_c(sigma_t,c rho(t) exp(-sigma_t,c
// column(t))), the pass probability avg_c(exp(-sigma_t,c column)). The same field that
// BDPT's delta and ratio tracking sample without bias (media/grid_tracking.cpp), so mlt
// and BDPT agree in expectation; BDPT's random-offset ray marching is a quadrature of
// it (biased where the density changes within a step), which mlt does not reproduce.
#pragma once
#include "core/hash.h"
#include "media/medium.h"

namespace rdv::mlt {

// The integral of the density along o + t d (d unit, world units), t in [0, length].
double medium_column(const Medium &m, Vec3 o, Vec3 d, float length);
// The density at a world point (homogeneous: 1).
float medium_density(const Medium &m, Vec3 p);
// A free flight from o along d: its distance, or -1 when it passes the segment (a medium
// that does not scatter is always passed). Two random numbers.
float sample_free_flight(const Medium &m, Vec3 o, Vec3 d, float segment, Pcg32 &rng);

inline bool medium_scatters(const Medium &m) { return max_component(m.sigma_s) > 0; }
inline Color column_transmittance(const Medium &m, double column) {
  if (std::isinf(column)) return m.transmittance(kInf);
  return {float(std::exp(-double(m.sigma_t.x) * column)), float(std::exp(-double(m.sigma_t.y) * column)),
          float(std::exp(-double(m.sigma_t.z) * column))};
}
// The free flight's probability of passing a segment of that column.
inline double pass_probability(const Medium &m, double column) {
  return medium_scatters(m) ? average(column_transmittance(m, column)) : 1.0;
}
// Its density of stopping after that column at a point of that density.
inline double stop_density(const Medium &m, double column, float density) {
  return medium_scatters(m) ? double(density) * average(m.sigma_t * column_transmittance(m, column)) : 0.0;
}

}  // namespace rdv::mlt
