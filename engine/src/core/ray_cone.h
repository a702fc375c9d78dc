// A ray's footprint as a cone (Akenine-Moller et al., "Improved Shader and Texture
// Level of Detail Using Ray Cones", JCGT 2021): the width a camera ray covers (one
// pixel) grows linearly with distance. At a hit it gives the surface footprint that
// image textures filter over (the MIP level), so a far or grazing surface shows the
// texture's average instead of aliasing.
//
// After a bounce the cone carries on from the hit and widens by the angular width of
// the lobe that scattered it (its `spread` grows by BsdfSample::cone_spread): 0 for
// mirrors and clear glass (then it is as if the surface were a flat mirror; curvature
// is ignored), about twice the GGX alpha for glossy lobes, kRoughConeSpread for
// diffuse-like lobes and media: a spread from the BSDF's roughness, as Akenine-Moller
// et al. 2021 propose, so a texture seen through a rough reflection is looked up at
// the blurrier MIP level it is seen at. The added width stays below the lobe's own
// blur, so prefiltering never blurs much more than the reflection itself. The path
// tracer and BDPT's camera subpaths widen their cones so. Light paths carry no cone
// (width 0: unfiltered lookups).
#pragma once

namespace rdv {

struct RayCone {
  float width = 0;   // footprint diameter at the ray's origin (scene units)
  float spread = 0;  // growth of the diameter per unit distance
  float width_at(float t) const { return width + spread * t; }
  RayCone after(float t) const { return {width_at(t), spread}; }  // continued from a hit at t
  RayCone scattered(float lobe_spread) const { return {width, spread + lobe_spread}; }  // at the hit
};

// The widest a scattering event makes the cone (radians, diameter per unit distance):
// diffuse-like lobes and phase functions, and the cap for glossy ones. Small next to a
// diffuse lobe's width (a wider prefilter would blur indirect texture detail that the
// path sampling still resolves), as the OptiX Toolkit's ray cones use for diffuse.
constexpr float kRoughConeSpread = 0.25f;

}  // namespace rdv
