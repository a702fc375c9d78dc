#include "film/light_passes.h"

namespace rdv {

Color safe_divide_even_color(const std::array<double, 3> &a, const std::array<double, 3> &b) {
  double r[3];
  for (int c = 0; c < 3; ++c) r[c] = b[c] != 0 ? a[c] / b[c] : 0.0;
  // Cycles (util/math_float3.h): try to stay grey where a colour channel is 0.
  if (b[0] == 0) {
    if (b[1] == 0) r[0] = r[1] = r[2];
    else if (b[2] == 0) r[0] = r[2] = r[1];
    else r[0] = 0.5 * (r[1] + r[2]);
  } else if (b[1] == 0) {
    if (b[2] == 0) r[1] = r[2] = r[0];
    else r[1] = 0.5 * (r[0] + r[2]);
  } else if (b[2] == 0) {
    r[2] = 0.5 * (r[0] + r[1]);
  }
  return Color(float(r[0]), float(r[1]), float(r[2]));
}

}  // namespace rdv
