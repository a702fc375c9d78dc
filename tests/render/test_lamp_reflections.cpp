// Lamps seen in glossy surfaces (issue 12, case 2): a point lamp's disk reflected by a GGX
// plate must have the radiance that integrating the plate's BSDF over the disk gives,
// whichever strategies found it (BSDF-sampled rays hitting the disk, light sampling of
// the disk, their MIS weights; PT and BDPT), and lamps are transparent as in Cycles 3.4.
// Each check is a z-test of the mean over pixels (independent estimates) at |z| < 4.5
// plus a 1% relative allowance for the quadrature: a false-alarm rate below 1e-5 per
// check; seeds are fixed, so verdicts are reproducible.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "bsdfs/microfacet.h"
#include "render_helpers.h"

namespace test_lamp_reflections {

using namespace rdv;
using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kView = 40 * kPiD / 180;  // the camera looks at the plate 40 degrees off its normal

struct Case {
  float lamp_radius, roughness;
  double offset;  // the lamp's angle off the mirror direction (radians, in the plane of incidence)
};

Vec3 lamp_centre(const Case &c) {
  double a = kView + c.offset;
  return Vec3(float(-2 * std::sin(a)), 0.0f, float(2 * std::cos(a)));  // 2 m from the plate's centre
}

// A tiny orthographic window on the plate's centre: every pixel sees the same radiance.
std::string plate_scene(const Case &c, const std::string &integrator, int samples) {
  Vec3 l = lamp_centre(c);
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", samples}, {"max_bounces", 1},
                          {"integrator", integrator}, {"seed", 3}}},
            {"camera", {{"type", "orthographic"}, {"ortho_scale", 2e-5}, {"clip_start", 0.01},
                        {"transform", {{"look_at", {{"from", {3 * std::sin(kView), 0, 3 * std::cos(kView)}},
                                                    {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "plate"}, {"type", "glossy"}, {"color", {1, 1, 1}}, {"roughness", c.roughness}}}},
            {"meshes", {{{"name", "plate"}, {"shape", {{"type", "quad"}, {"size", 0.01}}}, {"materials", {"plate"}}}}},
            {"lights", {{{"type", "point"}, {"position", {l.x, l.y, l.z}}, {"radius", c.lamp_radius}, {"power", 100}}}}};
  return j.dump();
}

// The radiance the plate's centre reflects toward the camera: the GGX BSDF (as the
// engine evaluates it: height-correlated Smith, no Fresnel for a Glossy BSDF of colour 1)
// integrated over the lamp's sphere (lights/sphere_lamp.h), radiance power / (4 pi * pi r^2):
// the cone of directions it subtends, which meets the plane through its centre facing the
// plate in a disk of radius r D / sqrt(D^2 - r^2) (D: the centre's distance), by quadrature in
// polar coordinates around the disk centre.
double reflected_radiance(const Case &c) {
  float alpha = c.roughness * c.roughness;
  GgxDistribution ggx{alpha, alpha};
  Vec3 wo(float(std::sin(kView)), 0.0f, float(std::cos(kView)));
  Vec3 centre = lamp_centre(c);
  Vec3 n = normalize(-centre);  // the disk faces the plate's centre (the origin)
  Vec3 s = normalize(cross(n, Vec3(0, 1, 0))), t = cross(n, s);
  const double D2 = length_squared(centre);
  double r = c.lamp_radius * std::sqrt(D2 / (D2 - double(c.lamp_radius) * c.lamp_radius)), sum = 0;
  const double Le = 100 / (4 * kPiD * kPiD * double(c.lamp_radius) * c.lamp_radius);
  // Radius as r u^2 (dense near the centre, where a sharp lobe peaks) and angle.
  const int nu = 3000, nphi = 720;
  for (int i = 0; i < nu; ++i) {
    double u = (i + 0.5) / nu, rho = r * u * u, drho = r * 2 * u / nu;
    for (int k = 0; k < nphi; ++k) {
      double phi = 2 * kPiD * (k + 0.5) / nphi;
      Vec3 y = centre + s * float(rho * std::cos(phi)) + t * float(rho * std::sin(phi));
      double d2 = length_squared(y);
      Vec3 wi = y / float(std::sqrt(d2));
      if (wi.z <= 0) continue;
      Vec3 h = normalize(wo + wi);
      double f = ggx.D(h) * ggx.G2(wo, wi) / (4.0 * wo.z * wi.z);
      double cos_l = dot(n, -wi);
      sum += f * wi.z * Le * cos_l / d2 * rho * drho * (2 * kPiD / nphi);
    }
  }
  return sum;
}

void expect_radiance(const Image &img, double expected, const std::string &what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  MeanEstimate m = pixel_mean(img, 1);
  double z = (m.mean - expected) / std::hypot(m.standard_error, 0.01 * expected);
  std::printf("[ lamp reflections ] %-40s rendered %.6g expected %.6g ratio %.4f (se %.2g%%)\n", what.c_str(),
              m.mean, expected, m.mean / expected, 100 * m.standard_error / expected);
  EXPECT_LT(std::fabs(z), 4.5) << what << ": mean " << m.mean << " expected " << expected << " (se "
                               << m.standard_error << ")";
}

}  // namespace

// The whole range of the Veach scene: lamps of 1 cm to 0.4 m in plates of roughness 0.02
// (GGX alpha 4e-4, just rough enough not to be a mirror) to 0.3, on the mirror direction
// and off it, by path tracing and BDPT.
TEST(LampReflections, DiskInGlossyPlateMatchesQuadrature) {
  const Case cases[] = {{0.01f, 0.02f, 0.0}, {0.01f, 0.05f, 0.0}, {0.01f, 0.05f, 0.004}, {0.01f, 0.3f, 0.0},
                        {0.4f, 0.02f, 0.0},  {0.4f, 0.05f, 0.0},  {0.4f, 0.3f, 0.0},     {0.4f, 0.3f, 0.3},
                        {0.13f, 0.1f, 0.05}};
  for (const Case &c : cases) {
    double expected = reflected_radiance(c);
    char what[96];
    for (const char *integrator : {"path", "bdpt"}) {
      std::snprintf(what, sizeof what, "%s r=%.2f m roughness %.2f offset %.3f", integrator, c.lamp_radius,
                    c.roughness, c.offset);
      expect_radiance(render_json(plate_scene(c, integrator, 256)), expected, what);
    }
  }
}

// Lamps are transparent (Cycles 3.4's shade_light continues the path): a lamp's disk
// seen in front of an emitting wall adds to the wall's radiance instead of hiding it.
TEST(LampReflections, LampsAreTransparent) {
  for (const char *integrator : {"path", "bdpt"}) {
    json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 16}, {"max_bounces", 2}, {"integrator", integrator}}},
              {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.01}, {"clip_start", 0.01},
                          {"transform", {{"look_at", {{"from", {0, 0, 3}}, {"to", {0, 0, 0}}}}}}}},
              {"world", {{"color", {0, 0, 0}}}},
              {"materials", {{{"name", "wall"}, {"type", "emission"}, {"color", {0.5, 0.5, 0.5}}, {"strength", 1}}}},
              {"meshes", {{{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 1}}}, {"materials", {"wall"}}}}},
              {"lights", {{{"type", "point"}, {"position", {0, 0, 1}}, {"radius", 0.1}, {"power", 10},
                           {"visible_camera", true}}}}};
    double lamp = 10 / (4 * kPiD * kPiD * 0.01);
    expect_radiance(render_json(j.dump()), lamp + 0.5, std::string(integrator) + " lamp in front of a wall");
  }
}

}  // namespace test_lamp_reflections
