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
// Lafortune & Willems' weights (mis = lafortune_willems) are checked the same way against
// their definition, evaluated here forwards along the path from the camera, for every
// strategy including s = 1 and t = 1 (their weights depend only on the path's vertices).
// Deterministic (fixed seeds), so nothing here can fail by chance.
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "api/handles.h"
#include "core/ray_offset.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/filter_glossy.h"
#include "lights/light.h"
#include "lights/rectangle_lamp.h"
#include "lights/sphere_lamp.h"
#include "render_helpers.h"
#include "samplers/sampler.h"

namespace test_bdpt_mis {

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
// Filter Glossy (filter_glossy > 0, integrators/filter_glossy.h): each vertex's BSDF is the
// one the blur by the path's camera-side densities gives it (camera vertices hold it; light
// vertices are blurred here), the camera walk samples with it and the light walk with the
// unblurred one, and a strategy whose light walk sampled at a vertex the blur changed has
// density 0.
// Mixed ray visibility (Scene::has_mixed_visibility; integrators/bdpt/bdpt.h): a light walk
// meets what any kind of ray but the camera's sees and passes no surface of mixed visibility
// nor makes a vertex on a look copy of it (Instance::look_copy), so a strategy whose light
// walk would have to make a segment with one on it (or, from a lamp that casts no shadows,
// any surface seen after a scattering), or such a vertex, has density 0; here each segment
// is asked afresh, between the path's two points.
double brute_force_weight(const Scene &scene, const std::vector<const PathVertex *> &y, int s,
                          float filter_glossy = 0) {
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
  // The path's BSDF at each scattering vertex, and whether the blur changed it.
  std::vector<Bsdf> path_bsdf(n);
  std::vector<bool> changed(n, false);
  const FilterGlossy filter(filter_glossy);
  float min_pdf = kInf;
  for (int i = n - 2; i >= 1; --i) {
    path_bsdf[i] = y[i]->bsdf;
    const float alpha = filter.alpha_after(min_pdf);
    if (i >= s) {
      changed[i] = y[i]->blurred;  // a camera vertex: blurred by its walk
    } else if (filter.on() && y[i]->type == VertexType::Surface && y[i]->bsdf.blur_changes(alpha)) {
      changed[i] = true;
      path_bsdf[i].blur(alpha);
    }
    const bool delta_on_path = (i < s - 1 || i > s) && y[i]->delta;  // (the connection ends scatter by it)
    if (filter.on() && y[i]->type == VertexType::Surface && !delta_on_path)
      min_pdf = std::min(min_pdf, path_bsdf[i].pdf(dir(i, i + 1), dir(i, i - 1)));
  }
  const Light &light = scene.lights()[y[0]->light];
  float pdf_pos, pdf_dir;
  emission_pdf(light, y[0]->p, y[0]->ng, dir(0, 1), scene.bounding_radius(), pdf_pos, pdf_dir);
  const double pmf = scene.light_distribution().pmf(y[0]->light);
  from_light[0] = pmf * pdf_pos;
  // A lamp's sphere, a square or rectangle: next-event estimation (one light vertex) samples
  // the point in the cone the sphere subtends at y[1] (lights/sphere_lamp.h), by the solid
  // angle of the lamp's part that lights y[1] (lights/rectangle_lamp.h), not as the emission does.
  const double nee_origin =
      is_sphere_lamp(light)      ? pmf * sphere_lamp_cone_pdf(light, y[1]->p) * to_area(1.0, *y[1], *y[0])
      : is_rectangle_lamp(light) ? pmf * rectangle_lamp_pdf(light, y[1]->p, y[0]->p) * to_area(1.0, *y[1], *y[0])
                                 : from_light[0];
  from_light[1] = to_area(pdf_dir, *y[0], *y[1]);
  for (int i = 2; i < n; ++i)
    from_light[i] = to_area(y[i - 1]->bsdf.pdf(dir(i - 1, i - 2), dir(i - 1, i)), *y[i - 1], *y[i]);
  float cam_pos, cam_dir;
  scene.camera().importance_pdf(Ray{y[n - 1]->p, dir(n - 1, n - 2), kInf}, cam_pos, cam_dir);
  from_camera[n - 2] = to_area(cam_dir, *y[n - 1], *y[n - 2]);
  for (int i = n - 3; i >= 0; --i)
    from_camera[i] = to_area(path_bsdf[i + 1].pdf(dir(i + 1, i + 2), dir(i + 1, i)), *y[i + 1], *y[i]);
  // Which segments y[i] -> y[i + 1] a light walk can make.
  std::vector<bool> light_walk_makes(n, true);
  if (scene.has_mixed_visibility()) {
    for (int i = 0; i + 2 < n; ++i) {
      const ShadowRay segment = shadow_ray(y[i]->p, y[i]->ng, y[i]->error, y[i + 1]->p, y[i + 1]->ng, y[i + 1]->error);
      const uint32_t passed = i == 0 && !light.occluders() ? visibility::kNonCamera : visibility::kMixed;
      light_walk_makes[i] = !scene.occluded(segment.o, segment.d, segment.tmax, passed);
    }
  }
  // Strategies with 0 .. n-1 light vertices (at least the camera vertex comes from
  // the camera; t = 1 connects to the lens, which the pinhole camera allows).
  auto density = [&](int k) {
    for (int i = 0; i <= k - 2; ++i)
      if (!light_walk_makes[i]) return 0.0;  // the light walk would pass a surface it cannot
    for (int i = 1; i <= k - 1; ++i)
      if (y[i]->look_copy) return 0.0;  // nor make a vertex on a look copy of mixed visibility
    for (int i = 1; i <= k - 2; ++i)
      if (changed[i]) return 0.0;  // the light walk sampled at a vertex the blur changed
    double p = k == 1 ? nee_origin : 1.0;
    for (int i = k == 1 ? 1 : 0; i < k; ++i) p *= from_light[i];
    for (int i = k; i < n; ++i) p *= from_camera[i];
    return p;
  };
  double sum = 0;
  for (int k = 0; k < n; ++k) sum += density(k) * density(k);
  return density(s) * density(s) / sum;
}

// Lafortune & Willems' weight of the strategy with t camera vertices on the path y (y[0]
// on the lamp, y[n-1] the camera), from their definition: walking from the camera, each
// vertex z_k (= y[n-1-k]) where a connection can make the path gives the connections
// there 1 - W_k of the share still left and passes W_k on; where none can (z_k or z_(k+1)
// scatters by a delta lobe), all of it passes on. What reaches the lamp goes to the camera
// path that finds it (s = 0); a delta lamp cannot be found, so to next-event estimation at
// z_m, or, where z_m is delta too, to light tracing (t = 1). The vertices a strategy
// joins scatter by the connection (path_delta false there).
double lafortune_willems_brute_force(const std::vector<const PathVertex *> &y, int t, bool delta_light,
                                     const std::vector<bool> &path_delta) {
  const int n = int(y.size()), m = n - 2;
  auto z_delta = [&](int k) { return bool(path_delta[n - 1 - k]); };
  std::vector<double> weight(n + 1, 0.0);  // by number of camera vertices
  double left = 1;
  for (int k = 1; k <= m; ++k) {
    bool connectible = !z_delta(k) && (k == m || !z_delta(k + 1));
    if (!connectible) continue;
    double W = y[n - 1 - k]->specularity;
    weight[k + 1] += (1 - W) * left;
    left *= W;
  }
  if (!delta_light) weight[n] += left;
  else if (!z_delta(m)) weight[m + 1] += left;
  else weight[1] += left;
  return weight[t];
}

// min_light_tracing: Lafortune & Willems only, how many checked weights must be light
// tracing's share of a path no other strategy makes (a weight wrongly 0 would hide them:
// connect() reports no contribution then).
void expect_weights_match_brute_force(const nlohmann::json &doc, int min_checks,
                                      MisHeuristic mis = MisHeuristic::Power, bool delta_light = false,
                                      int min_light_tracing = 0, float filter_glossy = 0) {
  LoadedScene loaded;
  load(loaded, doc);
  const Scene &scene = loaded.scene();
  const int width = 32, height = 32;
  loaded.handle->scene->camera().set_resolution(width, height);
  BdptSettings settings;
  settings.max_bounces = 6;
  settings.mis = mis;
  settings.limits.filter_glossy = filter_glossy;
  const bool lw = mis == MisHeuristic::LafortuneWillems;
  Bdpt bdpt(scene, settings);
  SobolSampler sampler(7);
  std::vector<PathVertex> camera_path(settings.max_bounces + 2), light_path(settings.max_bounces + 2);
  RayStats stats;
  int checks = 0, mismatches = 0, light_tracing = 0;
  double worst = 0;
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px)
      for (uint32_t index = 0; index < 4; ++index) {
        sampler.start_sample(px, py, index);
        CameraRay cr;
        Vec2 raster(px + sampler.get_1d(), py + sampler.get_1d());
        cr.ray = scene.camera().generate_ray(raster, sampler.get_2d(), &cr.lens_point);
        std::vector<Color> emitted(camera_path.size(), Color(0.0f));  // per segment (Bdpt::camera_subpath)
        int nc = bdpt.camera_subpath<false>(cr, sampler, stats, camera_path.data(), emitted.data());
        int nl = bdpt.light_subpath<false>(sampler, stats, light_path.data());
        for (int t = lw ? 1 : 2; t <= nc; ++t)
          for (int s = 0; s <= nl; ++s) {
            // Inner connections, and camera paths that found the lamp: strategies whose
            // whole path lies in the two subpaths (for Lafortune & Willems every strategy).
            bool inner = s >= 2, found_lamp = s == 0 && t >= 3;
            if (!inner && !found_lamp && !(lw && s + t >= 3)) continue;
            if (s + t - 2 > settings.max_bounces) continue;
            float w = 0;
            Vec2 unused;
            Color c = bdpt.connect<false>(light_path.data(), camera_path.data(), s, t, sampler, stats, &unused, &w);
            if (is_black(c)) continue;
            std::vector<const PathVertex *> y;
            std::vector<bool> path_delta;  // scattered by a delta lobe on this path
            if (s == 1) {  // the lamp point connect() sampled; L&W reads only whether it is delta
              y.push_back(&light_path[0]);
              path_delta.push_back(false);
            } else {
              for (int i = 0; i < s; ++i) {
                y.push_back(&light_path[i]);
                path_delta.push_back(i > 0 && i < s - 1 && light_path[i].delta);
              }
            }
            if (t == 1) {  // the lens point connect() sampled (the pinhole: camera_path[0])
              y.push_back(&camera_path[0]);
              path_delta.push_back(false);
            } else {
              for (int i = t - 1; i >= 0; --i) {
                y.push_back(&camera_path[i]);
                path_delta.push_back(i > 0 && i < t - 1 && camera_path[i].delta);
              }
            }
            double expected = lw ? lafortune_willems_brute_force(y, t, delta_light, path_delta)
                                 : brute_force_weight(scene, y, found_lamp ? 0 : s, filter_glossy);
            if (t == 1 && expected > 0) ++light_tracing;
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
  std::printf("[ bdpt mis ] %d weights checked (%d light tracing with weight > 0), %d mismatches, worst |difference| %.2e\n",
              checks, light_tracing, mismatches, worst);
  EXPECT_GE(checks, min_checks);
  EXPECT_GE(light_tracing, min_light_tracing);
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

// Filter Glossy 1 in a box of diffuse white walls and nearly smooth glossy red and green
// ones (GGX 0.05): after a diffuse bounce the coloured walls are blurred (alpha about 0.41),
// on camera vertices and at connections; strategies whose light walk sampled at a blurred
// vertex must have no share, and the reverse densities at blurred light vertices are the
// blurred BSDF's (filter_glossy.h).
TEST(BdptMisWeights, FilterGlossyCornellBoxMatchesBruteForce) {
  nlohmann::json doc = cornell_box();
  for (auto &m : doc["materials"])
    if (m["name"] == "red" || m["name"] == "green")
      m = {{"name", m["name"]}, {"type", "glossy"}, {"color", m["color"]}, {"roughness", 0.05}};
  expect_weights_match_brute_force(doc, 2000, MisHeuristic::Power, false, 0, 1.0f);
}

// Lafortune & Willems' weights against their definition. Glossy walls (W = 0.6 at each
// wall vertex) under the area lamp: a factor 1 - W dropped or misplaced changes most
// weights. The lamp also reflects as a mirror, so a camera path that finds it may go on
// by a delta lobe: the emitter still ends the path of s = 0 (no delta there). A mirror block, a smooth glass block and a point lamp: the shares that pass on
// over delta vertices, next-event estimation taking the share of a lamp that cannot be
// found, and light tracing taking what no other strategy can make.
TEST(BdptMisWeights, LafortuneWillemsGlossyCornellBoxMatchesDefinition) {
  nlohmann::json doc = cornell_box();
  for (auto &m : doc["materials"])
    if (m["name"] == "white") m = {{"name", "white"}, {"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.4}};
  for (auto &m : doc["materials"])
    if (m["name"] == "lamp") {
      nlohmann::json emission = m, mirror = {{"type", "glossy"}, {"color", {0.5, 0.5, 0.5}}, {"roughness", 0}};
      emission.erase("name");
      m = {{"name", "lamp"}, {"type", "add"}, {"shader1", emission}, {"shader2", mirror}};
    }
  expect_weights_match_brute_force(doc, 2000, MisHeuristic::LafortuneWillems);
}

TEST(BdptMisWeights, LafortuneWillemsMirrorGlassAndPointLampMatchDefinition) {
  nlohmann::json doc = cornell_box();
  doc["materials"].push_back({{"name", "mirror"}, {"type", "glossy"}, {"color", {0.9, 0.9, 0.9}}, {"roughness", 0}});
  doc["materials"].push_back({{"name", "glass"}, {"type", "glass"}, {"color", {1, 1, 1}}, {"ior", 1.5}, {"roughness", 0}});
  auto &meshes = doc["meshes"];
  for (auto &mesh : meshes) {
    if (mesh["name"] == "tall_block") mesh["materials"] = {"mirror"};
    if (mesh["name"] == "short_block") mesh["materials"] = {"glass"};
  }
  meshes.erase(meshes.end() - 1);  // the lamp quad
  doc["lights"] = {{{"name", "bulb"}, {"type", "point"}, {"position", {0.2, -0.2, 1.8}}, {"power", 100}, {"radius", 0}}};
  expect_weights_match_brute_force(doc, 2000, MisHeuristic::LafortuneWillems, true, 20);
}

// A point lamp with a radius is a sphere (lights/sphere_lamp.h), whose point next-event
// estimation samples in the cone it subtends (up to 4x the emission's uniform density on
// the visible cap): each strategy must weigh the point by its own density. With the
// emission's for next-event estimation too (pbrt's choice), or the cone's for light
// subpaths too, most weights of paths near the lamp differ here; a glossy floor and walls
// so that the light side's density matters.
// The Cornell box with glossy white surfaces and its lamp quad taken out, for lamps of
// other kinds.
static nlohmann::json glossy_cornell_box_without_its_lamp() {
  nlohmann::json doc = cornell_box();
  for (auto &m : doc["materials"])
    if (m["name"] == "white") m = {{"name", "white"}, {"type", "glossy"}, {"color", {0.8, 0.8, 0.8}}, {"roughness", 0.3}};
  auto &meshes = doc["meshes"];
  meshes.erase(meshes.end() - 1);  // the lamp quad
  return doc;
}

TEST(BdptMisWeights, SphereLampCornellBoxMatchesBruteForce) {
  nlohmann::json doc = glossy_cornell_box_without_its_lamp();
  doc["lights"] = {{{"name", "bulb"}, {"type", "point"}, {"position", {0.1, -0.2, 1.5}}, {"power", 100}, {"radius", 0.3}}};
  expect_weights_match_brute_force(doc, 2000);
}

// Square and rectangular area lamps, whose point next-event estimation samples by the solid
// angle of the part that can light the point (lights/rectangle_lamp.h): near the walls and
// the ceiling far denser than the emission's uniform point. A square 1 m wide 5 cm under the
// ceiling and a 1.2 x 0.4 m rectangle with a 50-degree spread (only the square around the
// disk of points that reach the point is sampled) on the left wall; glossy walls and floor.
TEST(BdptMisWeights, RectangleLampsCornellBoxMatchesBruteForce) {
  nlohmann::json doc = glossy_cornell_box_without_its_lamp();
  doc["lights"] = {{{"name", "panel"}, {"type", "area"}, {"shape", "square"}, {"size", 1.0}, {"power", 60},
                    {"position", {0.0, 0.0, 1.95}}, {"direction", {0, 0, -1}}},
                   {{"name", "softbox"}, {"type", "area"}, {"shape", "rectangle"}, {"size", 1.2}, {"size_y", 0.4},
                    {"power", 40}, {"spread", 0.87}, {"position", {-0.9, 0.2, 1.0}}, {"direction", {1, 0, 0}}}};
  expect_weights_match_brute_force(doc, 2000);
}

// Mixed ray visibility (integrators/bdpt/bdpt.h): glossy walls (so scatterings are of both
// kinds), the tall block hidden from diffuse rays and the short one from glossy rays. Paths
// pass through a block where the kind of their ray does not see it; no light walk can make
// such a segment, so the strategies that would need one must have no share, whichever
// strategy made the path (the camera walk's segments, a connection's).
TEST(BdptMisWeights, MixedVisibilityCornellBoxMatchesBruteForce) {
  nlohmann::json doc = cornell_box();
  for (auto &m : doc["materials"])
    if (m["name"] == "white")
      m = {{"name", "white"}, {"type", "principled"}, {"base_color", {0.8, 0.8, 0.8}}, {"roughness", 0.3}};
  for (auto &mesh : doc["meshes"]) {
    if (mesh["name"] == "tall_block") mesh["visibility"] = {{"diffuse", false}};
    if (mesh["name"] == "short_block") mesh["visibility"] = {{"glossy", false}};
  }
  expect_weights_match_brute_force(doc, 2000);
  // The tall block as two look copies on one spot (Light Path's ray types), which light
  // walks do not make vertices on.
  for (auto &mesh : doc["meshes"])
    if (mesh["name"] == "tall_block") {
      mesh["visibility"] = {{"camera", false}, {"glossy", false}};
      mesh["look_copy"] = true;
      nlohmann::json copy = mesh;
      copy["name"] = "tall_block_other_rays";
      copy["visibility"] = {{"diffuse", false}, {"transmission", false}, {"shadow", false}, {"volume_scatter", false}};
      doc["meshes"].push_back(copy);
      break;
    }
  expect_weights_match_brute_force(doc, 2000);
}

}  // namespace test_bdpt_mis
