// Next-event estimation of a rectangular area lamp (square or rectangle) from a point:
//  - Only the part of the lamp that can light the point: with a spread (a soft box's slats)
//    light leaves each point within spread / 2 of the axis, so the point is lit from the disk
//    of radius h tan(spread / 2) about its foot on the lamp's plane, h its height over it;
//    the square around that disk, clamped to the lamp, is sampled (Cycles 3.4's
//    light_spread_clamp_area_light). Without it, a narrow spread wasted most samples on
//    points whose light cannot reach.
//  - That rectangle is sampled by solid angle (spherical_rectangle.h) where it subtends at
//    least kMinSphericalRectangle steradians; smaller, uniformly by area (then nearly uniform
//    in solid angle as well, and the point exact in world coordinates, where a frame at the
//    shaded point would round a millimetre lamp a kilometre away).
// Ellipses and disks stay uniform by area (lights/light.cpp), as Cycles 3.4 samples them.
#pragma once
#include "lights/light.h"

namespace rdv {

constexpr double kMinSphericalRectangle = 1e-4;  // steradians

// A square or rectangular area lamp: next-event estimation samples it as below.
inline bool is_rectangle_lamp(const Light &l) { return l.type == LightType::Area && !l.ellipse; }

// A point p of the lamp for the point ref and its solid-angle density there; false when no
// part of the lamp can light ref (behind it, or beyond its spread).
bool sample_rectangle_lamp_from(const Light &l, Vec3 ref, Vec2 u, Vec3 &p, float &pdf);
// The solid-angle density at ref of sample_rectangle_lamp_from choosing the lamp's point p
// (0 beyond the part that can light ref).
float rectangle_lamp_pdf(const Light &l, Vec3 ref, Vec3 p);

}  // namespace rdv
