// Point and spot lamps with a radius as a surface, for path-space MLT: a sphere of radius
// r about the lamp's position that emits the lamp's disk radiance L outward from every
// point (times the spot's falloff along the emitted direction).
//
// Why a sphere: BDPT's light tracing (light_emission.cpp) emits along a direction d from
// a point uniform on the disk of radius r through the centre perpendicular to d, with
// radiance L: L travels along every line that passes within r of the centre, away from
// the line's closest point. A sphere of radius r emitting L outward carries L along the
// same lines (a line meets the sphere exactly when it passes within r of the centre),
// from where it leaves the sphere: the same radiance everywhere outside the sphere, and
// the same power (L pi r^2 4 pi). But a point on the sphere has an area density that
// does not depend on the vertex it lights, so a Metropolis path may keep it while that
// vertex moves (a disk facing its neighbour turns with it). Inside the sphere (geometry
// or fog within r of the lamp's centre) the two differ: the sphere lights nothing there.
//
// Camera-side walks reach the sphere where a ray enters it (a lamp seen in a mirror or
// through glass has no other strategy in path space).
//
// Sampling, factored as a point then a direction from it (so the light-side density of a
// kept point's direction is the second factor alone):
//  - point lamp: the point uniform on the sphere, the direction cosine-distributed about
//    its normal (together BDPT's density of the same line, cos / (4 pi^2 r^2));
//  - spot lamp: the point uniform on the cap of points that can emit into the cone
//    (angle to the axis below pi/2 + the cone's half angle), the direction uniform in the
//    cone; a direction into the sphere (below the point's horizon) is a failed sample.
#pragma once
#include "lights/light.h"

namespace rdv {

// A point lamp or spot lamp with a radius > 0.
inline bool is_sphere_lamp(const Light &l) {
  return (l.type == LightType::Point || l.type == LightType::Spot) && l.radius > 0;
}

// A point on the sphere and its outward normal; returns its area density.
float sample_sphere_lamp_point(const Light &l, Vec2 u, Vec3 &p, Vec3 &n);
// The area density of sample_sphere_lamp_point at a point of normal n.
float sphere_lamp_point_pdf(const Light &l, Vec3 n);
// A direction leaving the point of normal n; false (no direction) below its horizon.
bool sample_sphere_lamp_direction(const Light &l, Vec3 n, Vec2 u, Vec3 &d);
// The solid-angle density of sample_sphere_lamp_direction at d (0 below the horizon).
float sphere_lamp_direction_pdf(const Light &l, Vec3 n, Vec3 d);
// Radiance leaving the point of normal n along d.
Color sphere_lamp_radiance(const Light &l, Vec3 n, Vec3 d);
// Where the ray o + t d (0 < t < tmax) enters the lamp's sphere (a ray from inside it
// never does: the sphere emits outward only).
bool intersect_sphere_lamp(const Light &l, Vec3 o, Vec3 d, float tmax, float &t);

}  // namespace rdv
