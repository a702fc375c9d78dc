// The Principled BSDF's diffuse lobe as Cycles 3.4 has it (bsdf_principled_diffuse.h,
// Disney 2015 without the subsurface part): Lambert darkened at grazing angles by
// (1 - FV/2)(1 - FL/2) plus a retro-reflection term growing with roughness,
//   f = color / pi * [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))],
//   FL = (1 - cos_i)^5, FV = (1 - cos_o)^5, RR = roughness (1 + wi.wo).
// Symmetric in wi and wo (reciprocal); cosine-weighted sampling. Roughness in `sigma`.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::principled_diffuse {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::principled_diffuse
