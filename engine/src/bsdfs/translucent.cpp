#include "bsdfs/translucent.h"
#include "core/sampling.h"

namespace rdv::translucent {

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z >= 0) return Color(0.0f);
  return lobe.color * kInvPi;
}

float pdf(const Lobe &, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z >= 0) return 0;
  return cosine_hemisphere_pdf(-wi.z);
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  wi = cosine_hemisphere(u);
  wi.z = -wi.z;
  pdf_out = cosine_hemisphere_pdf(-wi.z);
  if (pdf_out <= 0) return false;
  weight = lobe.color;
  return true;
}

}  // namespace rdv::translucent
