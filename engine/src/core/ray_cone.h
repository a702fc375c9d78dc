// A ray's footprint as a cone (Akenine-Moller et al., "Improved Shader and Texture
// Level of Detail Using Ray Cones", JCGT 2021): the width a camera ray covers (one
// pixel) grows linearly with distance. At a hit it gives the surface footprint that
// image textures filter over (the MIP level), so a far or grazing surface shows the
// texture's average instead of aliasing.
//
// After a bounce the cone carries on from the hit with the same spread, as if every
// surface were a flat mirror: exact for mirrors, too narrow after rough bounces (more
// noise there, never blur). Light paths carry no cone (width 0: unfiltered lookups).
#pragma once

namespace rdv {

struct RayCone {
  float width = 0;   // footprint diameter at the ray's origin (scene units)
  float spread = 0;  // growth of the diameter per unit distance
  float width_at(float t) const { return width + spread * t; }
  RayCone after(float t) const { return {width_at(t), spread}; }  // continued from a hit at t
};

}  // namespace rdv
