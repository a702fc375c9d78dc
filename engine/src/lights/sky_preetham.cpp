#include "lights/sky_preetham.h"
#include <cmath>
#include "core/cie_1931.h"
#include "core/error.h"
#include "lights/sky_bake.h"

namespace rdv {

namespace {

// Perez et al.'s sky distribution: (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma).
float perez(const float c[5], float theta, float gamma) {
  const float cg = std::cos(gamma);
  return (1.0f + c[0] * std::exp(c[1] / std::cos(theta))) * (1.0f + c[2] * std::exp(c[3] * gamma) + c[4] * cg * cg);
}

// Zenith angle and azimuth as Cycles measures them (azimuth from +y toward +x).
void spherical(Vec3 d, float &theta, float &phi) {
  theta = std::acos(clampf(d.z, -1.0f, 1.0f));
  phi = std::atan2(d.x, d.y);
}

}  // namespace

PreethamSky::Settings PreethamSky::from_params(Params &p) {
  Settings s;
  const std::string type = p.get_string("type", "preetham");
  if (type != "preetham") fail(p.what() + ": 'type' must be preetham here, got '" + type + "'");
  const Vec3 d = p.get_vec3("sun_direction", s.sun_direction);
  const float l = length(d);
  if (!is_finite(d) || !(l > 0)) fail(p.what() + ": 'sun_direction' must be a finite, non-zero vector");
  s.sun_direction = d / l;
  s.turbidity = p.get_float("turbidity", s.turbidity);
  if (!std::isfinite(s.turbidity) || s.turbidity < 1 || s.turbidity > 30)
    fail(p.what() + ": 'turbidity' must be in [1, 30], got " + std::to_string(s.turbidity));
  return s;
}

PreethamSky::PreethamSky(const Settings &s) {
  spherical(s.sun_direction, sun_theta_, sun_phi_);
  const float t = sun_theta_, t2 = t * t, t3 = t2 * t, T = s.turbidity, T2 = T * T;
  // The paper's zenith luminance (kcd / m^2, times Cycles' 0.06) and chromaticity (its appendix).
  const float chi = (4.0f / 9.0f - T / 120.0f) * (kPi - 2.0f * t);
  zenith_Y_ = ((4.0453f * T - 4.9710f) * std::tan(chi) - 0.2155f * T + 2.4192f) * 0.06f;
  zenith_x_ = (0.00166f * t3 - 0.00375f * t2 + 0.00209f * t) * T2 +
              (-0.02903f * t3 + 0.06377f * t2 - 0.03202f * t + 0.00394f) * T +
              (0.11693f * t3 - 0.21196f * t2 + 0.06052f * t + 0.25886f);
  zenith_y_ = (0.00275f * t3 - 0.00610f * t2 + 0.00317f * t) * T2 +
              (-0.04214f * t3 + 0.08970f * t2 - 0.04153f * t + 0.00516f) * T +
              (0.15346f * t3 - 0.26756f * t2 + 0.06670f * t + 0.26688f);
  // The distribution coefficients A..E of Y, x and y, linear in the turbidity (the appendix).
  const float Y[5][2] = {{0.1787f, -1.4630f}, {-0.3554f, 0.4275f}, {-0.0227f, 5.3251f}, {0.1206f, -2.5771f},
                         {-0.0670f, 0.3703f}};
  const float x[5][2] = {{-0.0193f, -0.2592f}, {-0.0665f, 0.0008f}, {-0.0004f, 0.2125f}, {-0.0641f, -0.8989f},
                         {-0.0033f, 0.0452f}};
  const float y[5][2] = {{-0.0167f, -0.2608f}, {-0.0950f, 0.0092f}, {-0.0079f, 0.2102f}, {-0.0441f, -1.6537f},
                         {-0.0109f, 0.0529f}};
  for (int i = 0; i < 5; ++i) {
    perez_Y_[i] = Y[i][0] * T + Y[i][1];
    perez_x_[i] = x[i][0] * T + x[i][1];
    perez_y_[i] = y[i][0] * T + y[i][1];
  }
  // The zenith (theta 0) seen gamma = the sun's zenith angle away from the sun.
  zenith_Y_ /= perez(perez_Y_, 0, t);
  zenith_x_ /= perez(perez_x_, 0, t);
  zenith_y_ /= perez(perez_y_, 0, t);
}

Color PreethamSky::radiance(Vec3 d) const {
  float theta, phi;
  spherical(d, theta, phi);
  const float cos_gamma = std::sin(theta) * std::sin(sun_theta_) * std::cos(sun_phi_ - phi) +
                          std::cos(theta) * std::cos(sun_theta_);
  const float gamma = std::acos(clampf(cos_gamma, -1.0f, 1.0f));
  theta = std::min(theta, kPi / 2 - 0.001f);  // below the horizon: the horizon
  const float cx = zenith_x_ * perez(perez_x_, theta, gamma), cy = zenith_y_ * perez(perez_y_, theta, gamma);
  const float Y = zenith_Y_ * perez(perez_Y_, theta, gamma);
  const float X = cy != 0 ? cx / cy * Y : 0.0f, Z = cy != 0 && Y != 0 ? (1.0f - cx - cy) / cy * Y : 0.0f;
  double r, g, b;
  cie::xyz_to_rec709(X, Y, Z, r, g, b);
  return vmax(Color(float(r), float(g), float(b)), Color(0.0f));
}

std::vector<float> PreethamSky::bake(int width) const {
  return bake_sky(width, [&](int i, int j) { return radiance(sky_direction(width, i + 0.5, j + 0.5)); });
}

}  // namespace rdv
