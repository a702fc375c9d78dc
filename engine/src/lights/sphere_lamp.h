// Point and spot lamps with a radius as a surface, in every integrator: a sphere of
// radius r about the lamp's position that emits the lamp's disk radiance L outward from
// every point (times the spot's falloff along the emitted direction).
//
// Why a sphere: Blender 3.4's model, a disk of radius r facing the receiver, is not one
// emitter: its radiance field depends on who receives it, so light tracing cannot emit
// it. Far from the lamp every model agrees (intensity L pi r^2, power L pi r^2 4 pi), but
// within a few radii they differ at order r^2 / d^2: lit fog around a spot of radius 0.3
// was 15% brighter in BDPT (whose light subpaths emitted lines within r of the centre, the
// sphere's radiance field) than in the path tracer (the disk facing each fog point). A
// sphere is one emitter for next-event estimation, rays that hit it, light subpaths and
// path-space MLT (whose points must not depend on the vertex they light). Cycles 3.4
// itself is not consistent there (its next-event estimation and its hits of the disk
// differ at the same order); Cycles 4 made point lamps spheres.
//
// Camera-side walks reach the sphere where a ray enters it; points inside the sphere
// (geometry or fog within r of the centre) receive nothing from it.
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
// Radiance leaving the point of normal n along d toward a point `distance` from the lamp's
// centre (Light Falloff: Cycles 3.4's disk faces that point through the centre, so its rays
// are as long as the centre's distance, to (r / distance)^2).
Color sphere_lamp_radiance(const Light &l, Vec3 n, Vec3 d, float distance);
// That distance for a receiver (only a lamp whose emission depends on it pays the square root).
inline float sphere_lamp_distance(const Light &l, Vec3 receiver) {
  return l.by_distance ? length(receiver - l.position) : 1.0f;
}
// Next-event estimation from ref: a direction uniform in the cone of directions toward
// the sphere, the distance to where it enters it, the solid-angle density; false from
// inside the sphere.
bool sample_sphere_lamp_from(const Light &l, Vec3 ref, Vec2 u, Vec3 &wi, float &dist, float &pdf);
// The density of sample_sphere_lamp_from for a direction that meets the sphere (0 inside).
float sphere_lamp_cone_pdf(const Light &l, Vec3 ref);
// Where the ray o + t d (0 < t < tmax) enters the lamp's sphere (a ray from inside it
// never does: the sphere emits outward only).
bool intersect_sphere_lamp(const Light &l, Vec3 o, Vec3 d, float tmax, float &t);

}  // namespace rdv
