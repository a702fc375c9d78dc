// BDPT's MIS weights against a brute-force evaluation.
// For paths BDPT really builds (Cornell-box camera and light subpaths joined by an
// inner connection, or a camera subpath that found the lamp), the power-heuristic
// weight connect() reports must equal p_s^2 / sum_i p_i^2, where each strategy's
// density p_i is the full product of the path's vertex densities, computed here from
// scratch in double precision from the BSDFs, the lamp's emission and the camera.
// A wrong density anywhere (at the connection, its neighbours or along a subpath)
// changes the weight; the image tests could not see such an error where it is small
// (a forward density in place of a reverse one at q_(s-1) moved the door-gap and
// Cornell images by under 0.3%, and 3,039 of these 5,143 weights). The s = 1 and
// t = 1 strategies sample a fresh end vertex inside connect(), so their own weights
// are not checked here (they enter every other strategy's weight, which is).
// Deterministic (fixed seeds), so nothing here can fail by chance.
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "api/handles.h"
#include "integrators/bdpt/bdpt.h"
#include "lights/light.h"
#include "render_helpers.h"
#include "samplers/sampler.h"

using namespace rdv;
using namespace rdv::bdpt;

namespace {

struct LoadedScene {
  rdv_scene *handle = nullptr;
  ~LoadedScene() { rdv_scene_destroy(handle); }
  const Scene &scene() const { return *handle->scene; }
};

void load(LoadedScene &s, const nlohmann::json &doc) {
  rdv_scene_create(&s.handle);
  rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), s.handle);
  ASSERT_EQ(rdv_scene_commit(s.handle), RDV_OK);
}

nlohmann::json cornell_box() {
  std::ifstream f(test::source_path("scenes/cornell_box.json"));
  std::stringstream ss;
  ss << f.rdbuf();
  return nlohmann::json::parse(ss.str());
}

Vec3 unit(Vec3 from, Vec3 to) { return normalize(to - from); }

// Solid-angle density at a, toward b, as an area density at b.
double to_area(double pdf_solid_angle, const PathVertex &a, const PathVertex &b) {
  Vec3 w = b.p - a.p;
  double d2 = length_squared(w);
  double cos_b = b.on_surface() ? absdot(b.ng, normalize(w)) : 1.0;
  return pdf_solid_angle * cos_b / d2;
}

// The power-heuristic weight of strategy s on the path y (y[0] on the lamp, y[n-1]
// the camera), with every strategy's density as a full product. y[0 .. s-1] came from
// the light subpath, the rest from the camera subpath.
double brute_force_weight(const Scene &scene, const std::vector<const PathVertex *> &y, int s) {
  const int n = int(y.size());
  // Direction at y[i] toward its neighbour y[j]. Along a subpath it is the direction
  // the random walk sampled (stored as the later vertex's wo): from a surface point
  // the ray leaves from an offset origin, which matters for very short segments in
  // corners. Across the connection it is the direction between the two points.
  auto dir = [&](int i, int j) -> Vec3 {
    int lo = std::min(i, j), hi = std::max(i, j);
    if (hi < s) return i == lo ? -y[hi]->wo : y[hi]->wo;   // the light walk went lo -> hi
    if (lo >= s) return i == hi ? -y[lo]->wo : y[lo]->wo;  // the camera walk went hi -> lo
    return unit(y[i]->p, y[j]->p);
  };
  // Density of each vertex when the light subpath makes it (from_light) and when the
  // camera subpath makes it (from_camera).
  std::vector<double> from_light(n, 0.0), from_camera(n, 1.0);
  const Light &light = scene.lights()[y[0]->light];
  float pdf_pos, pdf_dir;
  emission_pdf(light, y[0]->p, y[0]->ng, dir(0, 1), scene.bounding_radius(), pdf_pos, pdf_dir);
  from_light[0] = double(scene.light_distribution().pmf(y[0]->light)) * pdf_pos;
  from_light[1] = to_area(pdf_dir, *y[0], *y[1]);
  for (int i = 2; i < n; ++i)
    from_light[i] = to_area(y[i - 1]->bsdf.pdf(dir(i - 1, i - 2), dir(i - 1, i)), *y[i - 1], *y[i]);
  float cam_pos, cam_dir;
  scene.camera().importance_pdf(Ray{y[n - 1]->p, dir(n - 1, n - 2), kInf}, cam_pos, cam_dir);
  from_camera[n - 2] = to_area(cam_dir, *y[n - 1], *y[n - 2]);
  for (int i = n - 3; i >= 0; --i)
    from_camera[i] = to_area(y[i + 1]->bsdf.pdf(dir(i + 1, i + 2), dir(i + 1, i)), *y[i + 1], *y[i]);
  // Strategies with 0 .. n-1 light vertices (at least the camera vertex comes from
  // the camera; t = 1 connects to the lens, which the pinhole camera allows).
  auto density = [&](int k) {
    double p = 1;
    for (int i = 0; i < k; ++i) p *= from_light[i];
    for (int i = k; i < n; ++i) p *= from_camera[i];
    return p;
  };
  double sum = 0;
  for (int k = 0; k < n; ++k) sum += density(k) * density(k);
  return density(s) * density(s) / sum;
}

void expect_weights_match_brute_force(const nlohmann::json &doc, int min_checks) {
  LoadedScene loaded;
  load(loaded, doc);
  const Scene &scene = loaded.scene();
  const int width = 32, height = 32;
  loaded.handle->scene->camera().set_resolution(width, height);
  BdptSettings settings;
  settings.max_bounces = 6;
  Bdpt bdpt(scene, settings);
  SobolSampler sampler(7);
  std::vector<PathVertex> camera_path(settings.max_bounces + 2), light_path(settings.max_bounces + 2);
  RayStats stats;
  int checks = 0, mismatches = 0;
  double worst = 0;
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px)
      for (uint32_t index = 0; index < 4; ++index) {
        sampler.start_sample(px, py, index);
        CameraRay cr;
        Vec2 raster(px + sampler.get_1d(), py + sampler.get_1d());
        cr.ray = scene.camera().generate_ray(raster, sampler.get_2d(), &cr.lens_point);
        Color emitted(0.0f);
        int nc = bdpt.camera_subpath<false>(cr, sampler, stats, camera_path.data(), &emitted);
        int nl = bdpt.light_subpath<false>(sampler, stats, light_path.data());
        for (int t = 2; t <= nc; ++t)
          for (int s = 0; s <= nl; ++s) {
            // Inner connections, and camera paths that found the lamp: strategies whose
            // whole path lies in the two subpaths.
            bool inner = s >= 2, found_lamp = s == 0 && t >= 3;
            if (!inner && !found_lamp) continue;
            if (s + t - 2 > settings.max_bounces) continue;
            float w = 0;
            Vec2 unused;
            Color c = bdpt.connect<false>(light_path.data(), camera_path.data(), s, t, sampler, stats, &unused, &w);
            if (is_black(c)) continue;
            std::vector<const PathVertex *> y;
            if (found_lamp) {
              for (int i = t - 1; i >= 0; --i) y.push_back(&camera_path[i]);
            } else {
              for (int i = 0; i < s; ++i) y.push_back(&light_path[i]);
              for (int i = t - 1; i >= 0; --i) y.push_back(&camera_path[i]);
            }
            double expected = brute_force_weight(scene, y, found_lamp ? 0 : s);
            double error = std::abs(w - expected);
            worst = std::max(worst, error);
            ++checks;
            if (error > 1e-4) {
              if (++mismatches <= 5)
                ADD_FAILURE() << "pixel (" << px << ", " << py << ") sample " << index << ", strategy s=" << s
                              << " t=" << t << ": weight " << w << ", brute force " << expected;
            }
          }
      }
  std::printf("[ bdpt mis ] %d weights checked, %d mismatches, worst |difference| %.2e\n", checks, mismatches, worst);
  EXPECT_GE(checks, min_checks);
  EXPECT_EQ(mismatches, 0);
}

}  // namespace

TEST(BdptMisWeights, DiffuseCornellBoxMatchesBruteForce) { expect_weights_match_brute_force(cornell_box(), 2000); }

// Glossy walls: the densities of scattering one way and the other differ, so a
// forward density used where the reverse one belongs (or the other way) shows.
TEST(BdptMisWeights, GlossyCornellBoxMatchesBruteForce) {
  nlohmann::json doc = cornell_box();
  for (auto &m : doc["materials"])
    if (m["name"] == "white") m = {{"name", "white"}, {"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.4}};
  expect_weights_match_brute_force(doc, 2000);
}
