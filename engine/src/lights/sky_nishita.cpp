#include "lights/sky_nishita.h"
#include "lights/sky_bake.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include "core/cie_1931.h"
#include "core/error.h"

namespace rdv {

namespace {

// The atmosphere (metres, per metre).
constexpr double kEarthRadius = 6360e3, kAtmosphereRadius = 6420e3;
constexpr double kRayleighScale = 8e3, kMieScale = 1.2e3;  // scale heights
constexpr double kMieScattering = 2e-5, kMieExtinction = 1.11 * kMieScattering;
constexpr double kMieG = 0.76;  // aerosols' anisotropy (Cornette-Shanks phase function)
constexpr int kViewSteps = 32;  // midpoint segments along the view ray

// 21 wavelengths from 380 to 780 nm.
constexpr int kWavelengths = 21;
constexpr double kFirstNm = 380, kStepNm = 20;
double wavelength(int i) { return kFirstNm + kStepNm * i; }

// Sunlight above the atmosphere, W / (m^2 nm): Planck's spectrum at 5778 K times the solid
// angle the sun's disc covers from Earth (pi (R_sun / 1 AU)^2, 6.790165e-5 sr).
double solar_irradiance(double nm) {
  const double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23, l = nm * 1e-9;
  const double radiance = 2 * h * c * c / (l * l * l * l * l) / (std::exp(h * c / (l * k * 5778.0)) - 1) * 1e-9;
  return radiance * 6.790165e-5;
}

// Rayleigh scattering of air at sea level: Rayleigh's lambda^-4 law, per metre (nm in).
double rayleigh_scattering(double nm) { return 1.1311487658e6 / (nm * nm * nm * nm); }

// Ozone's absorption at sea-level-equivalent density, per metre, at the 21 wavelengths:
// measured cross sections (no formula); the values of Blender's sky model.
constexpr double kOzoneAbsorption[kWavelengths] = {
    3.25126849861e-9, 5.85395365047e-9, 1.977191155085e-8, 7.309568762914e-8, 2.0084561514287e-7,
    4.0383958096161e-7, 6.3551335912363e-7, 9.670704118097e-7, 1.5479740042441e-6, 2.09038647223331e-6,
    2.46128056164565e-6, 2.73551299461512e-6, 2.15125863128643e-6, 1.59051840791988e-6, 1.12356197979857e-6,
    7.3527551487574e-7, 4.6450130357806e-7, 3.3096079921048e-7, 2.2512612292678e-7, 1.487912926649e-7,
    1.6828623364192e-7};

struct Spectra {
  double irradiance[kWavelengths], rayleigh[kWavelengths];
  Spectra() {
    for (int i = 0; i < kWavelengths; ++i) {
      irradiance[i] = solar_irradiance(wavelength(i));
      rayleigh[i] = rayleigh_scattering(wavelength(i));
    }
  }
};
const Spectra &spectra() {
  static const Spectra s;
  return s;
}

// Positions and directions in float, as Blender computes them (a double version differs by
// under 1e-4 relative); each Vec3 of densities holds (air, dust, ozone).
Vec3 geographic(float latitude, float longitude) {
  return Vec3(std::cos(latitude) * std::cos(longitude), std::cos(latitude) * std::sin(longitude), std::sin(latitude));
}

// Densities relative to sea level: air and dust fall off exponentially; ozone is a layer
// rising from 10 km to its peak at 25 km and gone at 40 km.
Vec3 densities(float height) {
  float ozone = 0;
  if (height >= 10000 && height < 25000) ozone = height / 15000 - 2.0f / 3.0f;
  else if (height >= 25000 && height < 40000) ozone = 8.0f / 3.0f - height / 15000;
  return Vec3(std::exp(-height / float(kRayleighScale)), std::exp(-height / float(kMieScale)), ozone);
}

// Whether the ray from p (inside the atmosphere) toward d (pointing down) meets the ground.
bool meets_ground(Vec3 p, Vec3 d) {
  if (d.z >= 0) return false;
  const float b = 2 * dot(d, p), c = dot(p, p) - float(kEarthRadius * kEarthRadius);
  return b * b - 4 * c >= 0;
}

// How far the ray from p toward d runs before it leaves the atmosphere.
float to_top(Vec3 p, Vec3 d) {
  const float b = 2 * dot(d, p), c = dot(p, p) - float(kAtmosphereRadius * kAtmosphereRadius);
  return (-b + std::sqrt(std::max(0.0f, b * b - 4 * c))) / 2;
}

// Gauss-Laguerre quadrature of order 8: the integral of g(x) e^-x over [0, inf) as the sum of
// weight_i g(node_i), the nodes the roots of the Laguerre polynomial L_8 (found by bisection
// on their sign changes), weight_i = x_i / (9 L_9(x_i))^2.
struct GaussLaguerre {
  static constexpr int kOrder = 8;
  double node[kOrder], weight[kOrder];
  static double laguerre(int n, double x) {
    double prev = 1, cur = 1 - x;
    if (n == 0) return prev;
    for (int k = 1; k < n; ++k) {
      const double next = ((2 * k + 1 - x) * cur - k * prev) / (k + 1);
      prev = cur;
      cur = next;
    }
    return cur;
  }
  GaussLaguerre() {
    int found = 0;
    const double step = 1e-3;
    for (double a = 0; found < kOrder && a < 40; a += step) {
      double lo = a, hi = a + step;
      if ((laguerre(kOrder, lo) < 0) == (laguerre(kOrder, hi) < 0)) continue;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        ((laguerre(kOrder, lo) < 0) == (laguerre(kOrder, mid) < 0) ? lo : hi) = mid;
      }
      const double x = 0.5 * (lo + hi), l = laguerre(kOrder + 1, x);
      node[found] = x;
      weight[found++] = x / ((kOrder + 1) * (kOrder + 1) * l * l);
    }
  }
};
const GaussLaguerre &gauss_laguerre() {
  static const GaussLaguerre q;
  return q;
}

// The optical depth factors (air, dust, ozone: metres of sea-level-equivalent density) from p
// toward d to the top of the atmosphere. Densities fall about exponentially along such a ray,
// so Blender's sky integrates them by Gauss-Laguerre quadrature: the ray's length mapped onto
// x in [0, 25] (the last node inside the atmosphere), each node's weight times e^x undoing the
// quadrature's own e^-x.
Vec3 column(Vec3 p, Vec3 d) {
  const GaussLaguerre &q = gauss_laguerre();
  constexpr double kEnd = 25;
  const float length = to_top(p, d);
  Vec3 sum(0.0f);
  for (int i = 0; i < GaussLaguerre::kOrder; ++i)
    sum += densities(rdv::length(p + d * float(q.node[i] / kEnd * length)) - float(kEarthRadius)) *
           float(q.weight[i] * std::exp(q.node[i]) / kEnd);
  return sum * length;
}

double phase_rayleigh(double mu) { return 3.0 / (16.0 * kPi) * (1 + mu * mu); }
double phase_mie(double mu) {
  const double g2 = kMieG * kMieG;
  return 3 * (1 - g2) * (1 + mu * mu) / (8 * kPi * (2 + g2) * std::pow(1 + g2 - 2 * kMieG * mu, 1.5));
}

Color spectrum_to_xyz(const double *spectrum) {
  double X = 0, Y = 0, Z = 0;
  for (int i = 0; i < kWavelengths; ++i) {
    const int c = cie::index_of(wavelength(i));
    X += cie::kX[c] * spectrum[i];
    Y += cie::kY[c] * spectrum[i];
    Z += cie::kZ[c] * spectrum[i];
  }
  return Color(float(X * kStepNm), float(Y * kStepNm), float(Z * kStepNm));
}

// Radiance scattered once toward the viewer at `eye` looking along `view`: along the view
// ray to the top of the atmosphere, each segment's in-scattering of sunlight (where the
// ground does not shadow it) attenuated on its way in and out.
void single_scattering(Vec3 view, Vec3 sun, Vec3 eye, Vec3 density_scale, double *spectrum) {
  const Spectra &sp = spectra();
  const float segment = to_top(eye, view) / kViewSteps;
  const double mu = dot(view, sun), phase_r = phase_rayleigh(mu), phase_m = phase_mie(mu);
  for (int i = 0; i < kWavelengths; ++i) spectrum[i] = 0;
  Vec3 depth(0.0f), p = eye + view * (0.5f * segment);
  for (int s = 0; s < kViewSteps; ++s, p += view * segment) {
    const Vec3 d = densities(length(p) - float(kEarthRadius)) * density_scale;
    depth += d * segment;
    if (meets_ground(p, sun)) continue;
    const Vec3 total = depth + column(p, sun) * density_scale;
    for (int i = 0; i < kWavelengths; ++i) {
      const double attenuation =
          std::exp(-(total.x * sp.rayleigh[i] + total.y * kMieExtinction + total.z * kOzoneAbsorption[i]));
      const double scattering = d.x * sp.rayleigh[i] * phase_r + d.y * kMieScattering * phase_m;
      spectrum[i] += attenuation * scattering * sp.irradiance[i] * segment;
    }
  }
}

// The sun's disc seen along d: its irradiance through the air and dust (no ozone, as
// Cycles) spread over the disc's solid angle.
Color sun_xyz(Vec3 eye, Vec3 d, double air, double dust, double solid_angle) {
  const Spectra &sp = spectra();
  const Vec3 c = column(eye, d);
  double spectrum[kWavelengths];
  for (int i = 0; i < kWavelengths; ++i)
    spectrum[i] = sp.irradiance[i] * std::exp(-(sp.rayleigh[i] * c.x * air + kMieExtinction * c.y * dust)) / solid_angle;
  return spectrum_to_xyz(spectrum);
}

float finite_setting(Params &p, const char *key, float fallback, float lo, float hi) {
  const float v = p.get_float(key, fallback);
  if (!std::isfinite(v) || v < lo || v > hi)
    fail(p.what() + ": '" + key + "' must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
         std::to_string(v));
  return v;
}

}  // namespace

NishitaSky::Settings NishitaSky::from_params(Params &p) {
  Settings s;
  const std::string type = p.get_string("type", "nishita");
  if (type != "nishita")
    fail(p.what() + ": 'type' must be nishita or preetham (Hosek-Wilkie is not supported), got '" + type + "'");
  s.sun_elevation = finite_setting(p, "sun_elevation", s.sun_elevation, -kPi / 2, kPi / 2);
  s.sun_rotation = finite_setting(p, "sun_rotation", s.sun_rotation, -1e6f, 1e6f);
  s.altitude = finite_setting(p, "altitude", s.altitude, -1e9f, 1e9f);
  s.air_density = finite_setting(p, "air_density", s.air_density, 0, 1e6f);
  s.dust_density = finite_setting(p, "dust_density", s.dust_density, 0, 1e6f);
  s.ozone_density = finite_setting(p, "ozone_density", s.ozone_density, 0, 1e6f);
  s.sun_disc = p.get_bool("sun_disc", s.sun_disc);
  s.sun_size = finite_setting(p, "sun_size", s.sun_size, 0, kPi);
  s.sun_intensity = finite_setting(p, "sun_intensity", s.sun_intensity, 0, 1e9f);
  return s;
}

NishitaSky::NishitaSky(const Settings &s) : s_(s) {
  // Cycles clamps the altitude (below 1 m its numbers break down, above 60 km is space) and
  // keeps the rotation as 2 pi minus it.
  s_.altitude = clampf(s.altitude, 1.0f, 59999.0f);
  rotation_ = std::fmod(s.sun_rotation, 2 * kPi);
  if (rotation_ < 0) rotation_ += 2 * kPi;
  rotation_ = 2 * kPi - rotation_;
  sun_dir_ = geographic(s_.sun_elevation, rotation_ + kPi / 2);

  // The texels: longitudes over the full circle (the sky is symmetric about the sun's
  // meridian: one half is computed and mirrored), latitudes packed toward the horizon.
  const Vec3 eye(0, 0, float(kEarthRadius) + s_.altitude), sun_at_zero = geographic(s_.sun_elevation, 0);
  const Vec3 scale(s_.air_density, s_.dust_density, s_.ozone_density);
  const double lat_step = kPi / 2 / kHeight, lon_step = 2 * kPi / kWidth;
  xyz_.assign(size_t(kWidth) * kHeight, Color(0.0f));
  tbb::parallel_for(0, kHeight, [&](int y) {  // rows apart: each writes its own
    double spectrum[kWavelengths];
    const double t = double(y) / kHeight, latitude = (kPi / 2 + lat_step / 2) * t * t;
    for (int x = 0; x < kWidth / 2; ++x) {
      single_scattering(geographic(latitude, lon_step * x - kPi), sun_at_zero, eye, scale, spectrum);
      const Color c = spectrum_to_xyz(spectrum);
      xyz_[size_t(y) * kWidth + size_t(x)] = xyz_[size_t(y) * kWidth + size_t(kWidth - 1 - x)] = c;
    }
  });
  // The disc's lower and upper rim (above the horizon).
  // The disc's solid angle as Cycles takes it, in float: 1 - cos(0.27 degrees) keeps only about
  // three digits there, and the disc's radiance (its irradiance over this) with them.
  const float half = s_.sun_size / 2, solid_angle = 2 * kPi * (1.0f - std::cos(half));
  if (solid_angle > 0) {
    sun_bottom_ = sun_xyz(eye, geographic(std::max(0.0f, s_.sun_elevation - half), 0), s_.air_density,
                          s_.dust_density, solid_angle);
    sun_top_ = sun_xyz(eye, geographic(std::max(0.0f, s_.sun_elevation + half), 0), s_.air_density, s_.dust_density,
                       solid_angle);
  }
}

Color NishitaSky::texel_xyz(float x, float y) const {
  const float px = x * kWidth - 0.5f, py = y * kHeight - 0.5f;
  const float fx = std::floor(px), fy = std::floor(py), tx = px - fx, ty = py - fy;
  auto at = [&](int i, int j) {
    i = std::clamp(i, 0, kWidth - 1);
    j = std::clamp(j, 0, kHeight - 1);
    return xyz_[size_t(j) * kWidth + size_t(i)];
  };
  const int ix = int(fx), iy = int(fy);
  return (at(ix, iy) * (1 - tx) + at(ix + 1, iy) * tx) * (1 - ty) + (at(ix, iy + 1) * (1 - tx) + at(ix + 1, iy + 1) * tx) * ty;
}

Color NishitaSky::radiance(Vec3 d) const {
  if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z))) return Color(0.0f);
  const float phi = std::atan2(d.x, d.y);  // Cycles' direction_to_spherical
  float x = (phi + kPi + rotation_) / (2 * kPi);
  if (x > 1) x -= 1;
  Color xyz(0.0f);
  if (d.z >= 0) {
    const float half = s_.sun_size / 2;
    const float angle = 2 * std::atan2(length(d - sun_dir_), length(d + sun_dir_));
    const float elevation = kPi / 2 - std::acos(std::min(d.z, 1.0f));
    if (s_.sun_disc && angle < half) {
      const float top = s_.sun_elevation + half, bottom = s_.sun_elevation - half;
      if (top > 0) {
        const float t = bottom > 0 ? (elevation - s_.sun_elevation) / s_.sun_size + 0.5f : elevation / top;
        xyz = (sun_bottom_ + (sun_top_ - sun_bottom_) * t) * s_.sun_intensity;
      }
      const float r = angle / half;
      xyz *= 1 - 0.6f * (1 - std::sqrt(std::max(0.0f, 1 - r * r)));  // limb darkening
    } else {
      xyz = texel_xyz(x, std::sqrt(std::max(0.0f, elevation / (kPi / 2))));
    }
  } else if (d.z >= -0.4f) {  // below the horizon the sky's lowest row fades to black ground
    const float fade = 1 + d.z * 2.5f;
    xyz = texel_xyz(x, -0.5f) * (fade * fade * fade);
  }
  double r, g, b;
  cie::xyz_to_rec709(xyz.x, xyz.y, xyz.z, r, g, b);
  return Color(float(std::max(r, 0.0)), float(std::max(g, 0.0)), float(std::max(b, 0.0)));
}

std::vector<float> NishitaSky::bake(int width) const {
  const int height = width / 2;
  // A pixel spans at most this angle (a column at the equator, plus a row).
  const float pixel = float(2 * kPi / width + kPi / height);
  const float disc = s_.sun_disc ? s_.sun_size / 2 + pixel : -1.0f;
  return bake_sky(width, [&](int i, int j) {
    const Vec3 centre = sky_direction(width, i + 0.5, j + 0.5);
    if (std::acos(clampf(dot(centre, sun_dir_), -1.0f, 1.0f)) >= disc) return radiance(centre);
    Color c(0.0f);
    const int n = 16;
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) c += radiance(sky_direction(width, i + (a + 0.5) / n, j + (b + 0.5) / n));
    return c / float(n * n);
  });
}

}  // namespace rdv
