#include "bsdfs/transparent.h"

namespace rdv::transparent {

bool sample(const Lobe &lobe, Vec3 wo, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  wi = -wo;
  weight = lobe.color;
  pdf_out = 1;
  return true;
}

}  // namespace rdv::transparent
