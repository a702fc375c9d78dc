// Oren-Nayar diffuse reflection as Cycles implements it (Fujii's qualitative model):
// f = color * (A + B t), t = max(0, cos phi sin_i sin_o) / max(cos_i, cos_o),
// A = 1 / (pi + (3pi - 4)/6 sigma), B = sigma A. Cosine-weighted sampling.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::oren_nayar {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::oren_nayar
