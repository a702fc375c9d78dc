// Sheen as Blender 3.4's Principled BSDF has it (Cycles' principled_sheen):
// f = color * (1 - |wi.h|)^5 (no 1/pi, as Cycles), cosine-weighted sampling.
// A grazing-angle rim that adds a little energy on top of the diffuse lobe.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::sheen {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::sheen
