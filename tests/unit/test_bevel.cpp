// The Bevel node (textures/bevel.h) against what its normal must be.
// Its sampling (three disk axes, the cubic falloff's radii, local rays, the power heuristic
// over the axes) estimates the integral of the object's normals weighted by the falloff at
// each point's true distance, I = integral of N(x) (1 - |x - P| / R)^3 dA(x), whatever the
// axes' weights (they sum to one); the node's normal is I's direction. So:
// - on a face farther than the radius from any edge, the face's normal, exactly;
// - beside a box's edge, I from quadrature over the two faces (the mean over points along
//   the edge, 128 samples each, within 5 standard errors of that mean and 0.5 degrees);
// - on the edge, 45 degrees by symmetry;
// at 1 mm, 1 m and 1 km, 1 km from the origin, and with another object lying on the box's
// side face (its own surfaces only: Cycles' local intersection). Deterministic (each point's sample set is a fixed function of its
// position), so the outcome is reproducible; were the points' sets independent draws, the
// 5-standard-error bound would fail by chance about once in 1.7 million runs.
// Its agreement with Cycles in an image is blender.brightness.bevel.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "render_helpers.h"
#include "scene_file.h"
#include "textures/bevel.h"
#include "textures/shading_point.h"

namespace test_bevel {

using namespace rdv;
using nlohmann::json;

namespace {

struct LoadedScene {
  rdv_scene *handle = nullptr;
  ~LoadedScene() { rdv_scene_destroy(handle); }
  const Scene &scene() const { return *handle->scene; }
};

// A flat-shaded box 2 s wide around (far, far, 0), seen from above; with `lid`, another
// object's quad lying on its side x = far + s (the local rays must still find the box's face).
void load_box(LoadedScene &s, double scale, bool lid, double far) {
  json doc = {
      {"camera", {{"transform", {{"look_at", {{"from", {0, 0, 10 * scale}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}}}},
      {"world", {{"color", {1, 1, 1}}}},
      {"materials", {{{"name", "grey"}, {"type", "diffuse"}, {"color", {0.5, 0.5, 0.5}}}}},
      {"meshes", {{{"name", "box"}, {"shape", {{"type", "box"}, {"size", {2 * scale, 2 * scale, 2 * scale}}, {"smooth", false}}},
                   {"materials", {"grey"}}, {"transform", {{"translate", {far, far, 0}}}}}}}};
  if (lid)
    doc["meshes"].push_back({{"name", "lid"}, {"materials", {"grey"}},
                             {"positions", {scale, -2 * scale, -2 * scale, scale, 2 * scale, -2 * scale,
                                            scale, 2 * scale, 2 * scale, scale, -2 * scale, 2 * scale}},
                             {"indices", {0, 1, 2, 0, 2, 3}}, {"transform", {{"translate", {far, far, 0}}}}});
  rdv_scene_create(&s.handle);
  rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), s.handle);
  ASSERT_EQ(rdv_scene_commit(s.handle), RDV_OK);
}

// The box's top face (z = s) at (far + x, far + y), as a camera ray from above finds it.
ShadingPoint top_point(const Scene &scene, float x, float y, float s, double far) {
  Ray ray{{float(far + x), float(far + y), 3 * s}, {0, 0, -1}};
  SurfaceHit hit;
  EXPECT_TRUE(scene.intersect(ray, hit));
  return scene.shading_point(hit, ray.d);
}

// Beside an edge, d from it on one face: the angle (radians) of I from that face's normal
// toward the other face's, I's two parts by the midpoint rule.
double reference_angle(double d, double radius) {
  const int n = 1200;
  const double h = 2 * radius / n;
  auto falloff = [&](double r2) {
    const double f = 1 - std::sqrt(r2) / radius;
    return f > 0 ? f * f * f : 0.0;
  };
  double own = 0, other = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = -radius + (i + 0.5) * h, b = -radius + (j + 0.5) * h;
      if (a <= d) own += falloff(a * a + b * b);        // this face: offsets (a, b) up to the edge
      if (a <= 0) other += falloff(d * d + a * a + b * b);  // the other face: depth a below the edge
    }
  return std::atan2(other, own);
}

}  // namespace

TEST(Bevel, FalloffRadiiInvertItsDistribution) {
  EXPECT_LT(bevel_falloff_radius(0.0f), 1e-3f);  // the CDF is 10 x^2 there: x to within its tolerance
  float last = 0;
  for (int i = 1; i < 1000; ++i) {
    const float u = i / 1000.0f, x = bevel_falloff_radius(u);
    const float cdf = x * x * (10 - 20 * x + 15 * x * x - 4 * x * x * x);
    ASSERT_NEAR(cdf, u, 2e-6f) << "u " << u;
    ASSERT_GT(x, last);
    last = x;
  }
  EXPECT_LE(bevel_falloff_radius(0.99999994f), 1.0f);
}

TEST(Bevel, NormalIsTheFalloffWeightedMeanOfTheObjectsNormals) {
  struct Case { double scale; bool lid; double far; };
  for (const Case c : {Case{1e-3, false, 0}, Case{1, false, 0}, Case{1e3, false, 0}, Case{1, true, 0}, Case{1, false, 1e3}}) {
    const double scale = c.scale, far = c.far;
    SCOPED_TRACE("scale " + std::to_string(scale) + (c.lid ? ", a lid on the side" : "") + ", " + std::to_string(far) +
                 " from the origin");
    LoadedScene box;
    load_box(box, scale, c.lid, far);
    const Scene &scene = box.scene();
    const float s = float(scale), radius = 0.1f * s;

    // Farther than the radius from every edge: only the top face is within reach.
    for (float x : {-0.5f, 0.0f, 0.85f}) {
      const ShadingPoint sp = top_point(scene, x * s, 0.1f * s, s, far);
      const Vec3 n = bevel_normal(sp, radius, 8);
      EXPECT_NEAR(n.x, 0.0f, 1e-6f);
      EXPECT_NEAR(n.y, 0.0f, 1e-6f);
      EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    }
    // Nothing to sample: the shading normal.
    const ShadingPoint edge_point = top_point(scene, 0.97f * s, 0, s, far);
    EXPECT_EQ(bevel_normal(edge_point, radius, 0).z, 1.0f);
    EXPECT_EQ(bevel_normal(edge_point, 0.0f, 8).z, 1.0f);
    EXPECT_EQ(bevel_normal(edge_point, std::nanf(""), 8).z, 1.0f);
    ShadingPoint no_scene = edge_point;
    no_scene.rays = nullptr;
    EXPECT_EQ(bevel_normal(no_scene, radius, 8).z, 1.0f);

    // Beside the edge x = s, and on it: the mean angle over points along the edge.
    for (double d_over_r : {0.0, 0.3, 0.7}) {
      SCOPED_TRACE("d / R " + std::to_string(d_over_r));
      const int points = 64;
      double sum = 0, sum2 = 0;
      for (int k = 0; k < points; ++k) {
        const float y = (-0.5f + (k + 0.5f) / points) * s;
        const float x = d_over_r == 0 ? s * (1 - 1e-4f) : float(s - d_over_r * radius);
        const Vec3 n = bevel_normal(top_point(scene, x, y, s, far), radius, 128);
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.z));
        ASSERT_NEAR(length(n), 1.0f, 1e-5f);
        EXPECT_NEAR(n.y, 0.0f, 0.05f);  // along the edge: no turn but noise
        const double angle = std::atan2(double(n.x), double(n.z));
        sum += angle;
        sum2 += angle * angle;
      }
      const double mean = sum / points, se = std::sqrt(std::max(sum2 / points - mean * mean, 0.0) / (points - 1));
      const double expected = d_over_r == 0 ? M_PI / 4 : reference_angle(d_over_r * radius, radius);
      EXPECT_LT(std::fabs(mean - expected), std::max(5 * se, 0.5 * M_PI / 180))
          << "mean " << mean * 180 / M_PI << " deg, expected " << expected * 180 / M_PI << " deg, se "
          << se * 180 / M_PI;
    }
  }
}

TEST(Bevel, ParsedAsAMaterialsNormal) {
  // As a BSDF's normal, under a bump's, with a normal map for its own; bad samples named.
  const json bevel = {{"node", "bevel"}, {"radius", 0.2}, {"samples", 4},
                      {"normal", {{"node", "normal_map"}, {"color", {0.5, 0.6, 1.0}}}}};
  json doc = test::load_scene("cornell_box.json");
  doc["settings"] = {{"width", 16}, {"height", 16}, {"samples", 2}};
  doc["materials"][0]["normal"] = bevel;
  test::Image img = test::render_json(doc.dump());
  EXPECT_TRUE(img.all_finite());
  EXPECT_EQ(img.warnings.find("bevel"), std::string::npos) << img.warnings;
  doc["materials"][0]["normal"] = {{"node", "bump"}, {"height", 0.0}, {"normal", bevel}};
  EXPECT_TRUE(test::render_json(doc.dump()).all_finite());
  doc["materials"][0]["normal"]["normal"]["samples"] = 129;
  img = test::render_json(doc.dump());
  EXPECT_NE(img.warnings.find("'samples' must be 0 to 128"), std::string::npos) << img.warnings;
}

}  // namespace test_bevel
