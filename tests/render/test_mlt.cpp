// Metropolis light transport (pssmlt, mmlt; path-space mlt) against BDPT, the integrator
// whose primary sample space the first two explore. Images are rendered K times with independent seeds (each
// run's own bootstrap, so the error of b is part of the run-to-run spread); every 8x8
// block is compared with Welch's t-test. False-alarm rate: 1% for the whole file's
// block comparisons (Sidak-corrected per block), 1e-3 for each brightness check; seeds
// are fixed, so each verdict is reproducible.
#include <gtest/gtest.h>
#include <cmath>
#include <chrono>
#include <cstring>
#include <thread>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include "media_grids.h"
#include "render_helpers.h"
#include "statistics.h"

namespace test_mlt {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kRuns = 8;
// 4 scenes x 2 integrators with the default (relative) target, the door gap with the
// luminance target, mlt on 17 scenes (luminance target) and the fog door twice more
// (relative target; direct light left to the path tracer), an alpha card with direct light
// left to the path tracer, pssmlt with a sample clamp, and pssmlt and mlt under Light
// Falloff and with lamp textures; 36 blocks each.
constexpr int kBlockTestsInFile = 35 * 36;
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / kBlockTestsInFile);

struct Runs {
  std::vector<std::vector<double>> images;  // RGB sum per pixel
  std::vector<double> means;                // mean luminance of each run
};

Runs render_runs(const json &scene, json settings, uint32_t first_seed) {
  Runs runs;
  for (int k = 0; k < kRuns; ++k) {
    settings["seed"] = first_seed + k;
    Image img = render_json(scene.dump(), settings.dump());
    EXPECT_TRUE(img.all_finite());
    EXPECT_EQ(img.progress.samples_dropped, 0u);
    std::vector<double> v(size_t(img.width) * img.height);
    double lum = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = double(img.rgba[4 * i]) + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
      lum += img.luminance(int(i % img.width), int(i / img.width));
    }
    runs.means.push_back(lum / double(v.size()));
    runs.images.push_back(std::move(v));
  }
  return runs;
}

void mean_and_error(const std::vector<double> &x, double &mean, double &error) {
  double s = 0, s2 = 0;
  for (double v : x) { s += v; s2 += v * v; }
  mean = s / double(x.size());
  error = std::sqrt(std::max(0.0, s2 / double(x.size()) - mean * mean) / double(x.size() - 1));
}

// BDPT's K runs of a scene, rendered once per process: a test that compares several
// Metropolis settings on one scene (the door gap's two targets, the fog door's three set-ups)
// compares each with the same reference.
const Runs &bdpt_runs(const json &scene, int samples) {
  static std::map<std::string, Runs> rendered;
  const json s = {{"width", 48}, {"height", 48}, {"max_bounces", 8}, {"integrator", "bdpt"}, {"samples", samples}};
  const std::string key = scene.dump() + '\n' + s.dump();
  auto it = rendered.find(key);
  if (it == rendered.end()) it = rendered.emplace(key, render_runs(scene, s, 1)).first;
  return it->second;
}

// Both Metropolis integrators against BDPT on one scene.
// variants: settings each integrator also runs with, against the one BDPT reference
// (named in the messages by their JSON).
// bdpt_samples: the reference's; its run means spread 3-30x less than the Metropolis
// integrators' at the mutations each test gives them (both printed), so its share of
// each comparison's variance is small.
void expect_same_image(const json &scene, const std::string &what, int bdpt_samples, int mutations,
                       const char *target = "relative",
                       std::initializer_list<const char *> integrators = {"pssmlt", "mmlt"},
                       const std::vector<json> &variants = {json::object()}) {
  const json s = {{"width", 48}, {"height", 48}, {"max_bounces", 8}};
  const Runs &bdpt = bdpt_runs(scene, bdpt_samples);
  double bdpt_mean, bdpt_error;
  mean_and_error(bdpt.means, bdpt_mean, bdpt_error);
  for (const char *name : integrators)
    for (const json &variant : variants) {
      const std::string integrator = variant.empty() ? name : std::string(name) + " " + variant.dump();
      json m = s;
      m["integrator"] = name;
      m["samples"] = mutations;
      m["mlt_bootstrap"] = 4;
      m["mlt_chains"] = 64;
      m["mlt_target"] = target;
      m.update(variant);
      Runs mlt = render_runs(scene, m, 2001);
      BlockComparison c = compare_blocks(mlt.images, bdpt.images, 48, 48, 8, kAlphaPerBlock);
      EXPECT_EQ(c.failed, 0) << what << " " << integrator << ": " << c.detail;
      // Brightness: Welch's t-test of the K runs' means against BDPT's, two-sided p > 1e-3.
      // (Student's t with the Welch-Satterthwaite degrees of freedom: a normal z with K = 8
      // errors estimated from the runs themselves alarms far more often than 1e-3; MMLT's
      // door gap failed |z| < 3.3 at z = 3.65, p = 0.008, its mean over 11 seeds 0.997.)
      double mean, error;
      mean_and_error(mlt.means, mean, error);
      const double va = error * error, vb = bdpt_error * bdpt_error;
      const double z = (mean - bdpt_mean) / std::sqrt(va + vb);
      const double dof = (va + vb) * (va + vb) / ((va * va + vb * vb) / (kRuns - 1));
      EXPECT_GT(student_t_two_sided(z, dof), 1e-3) << what << " " << integrator << ": mean " << mean << " vs bdpt "
                                                   << bdpt_mean << " (t " << z << ", " << dof << " dof)";
      std::printf("[ %-6s vs bdpt ] %-10s mean ratio %.4f +- %.4f (run means' errors: %.4f, bdpt %.4f); %s\n",
                  integrator.c_str(), what.c_str(), mean / bdpt_mean,
                  std::sqrt(error * error + bdpt_error * bdpt_error) / bdpt_mean, error / mean, bdpt_error / bdpt_mean,
                  c.detail.substr(0, 100).c_str());
    }
}

}  // namespace

TEST(MltVsBdpt, CornellBox) { expect_same_image(load_scene("cornell_box.json"), "cornell", 8, 64); }

// A glass ball under a 3 cm lamp: the caustic BDPT finds by light tracing.
TEST(MltVsBdpt, GlassCaustic) { expect_same_image(load_scene("caustic.json"), "caustic", 16, 64); }

// A room lit only through a door gap; and a spot lamp in fog (medium vertices, NEE and
// connections through the medium). The door gap also with Kelemen's and Hachisuka's own
// target (luminance), where it differs most from the relative one (the lit room seen
// through the gap).
TEST(MltVsBdpt, DoorGap) {
  expect_same_image(load_scene("door_gap.json"), "door gap", 16, 64);
  expect_same_image(load_scene("door_gap.json"), "door gap (luminance)", 16, 64, "luminance");
}
// The sample clamp (settings "clamp") caps a camera sample's value: pssmlt's state holds
// BDPT's camera sample, capped the same, so its chains render BDPT's clamped image. A
// clamp of 0.3 takes 15% of the caustic scene's light (48 px, 64 spp: BDPT's mean 0.284
// unclamped, 0.242 clamped; pssmlt unclamped would be 1.18x clamped BDPT's).
TEST(MltVsBdpt, GlassCausticWithSampleClamp) {
  json scene = load_scene("caustic.json");
  scene["settings"]["clamp"] = 0.3;
  expect_same_image(scene, "caustic, clamp", 16, 64, "relative", {"pssmlt"});
}
TEST(MltVsBdpt, FogAndSpot) { expect_same_image(load_scene("fog_spot.json"), "fog spot", 16, 32); }

// Path-space MLT (integrators/mlt/path_space.h): surfaces and a mesh lamp; fog (a
// homogeneous world volume) lit through a door gap by an area lamp, medium vertices and
// free-flight densities on both sides of every edge.
TEST(MltVsBdpt, PathSpaceCornellBox) {
  expect_same_image(load_scene("cornell_box.json"), "cornell", 16, 64, "luminance", {"mlt"});
}
// The path-space tests run Veach's target, the path's luminance, whose image mean is b
// itself (a sharp brightness check); the fog door also runs the default target, relative
// to a pilot's image (importance_map.h), whose mean spreads ~5x wider between runs at
// these lengths (48 px, volume caustic, 256 mutations per pixel, 16 seeds: 1.020 +- 0.025
// of BDPT against the luminance target's 1.005 +- 0.005). Last, direct light (paths of one
// and two edges) left to the path tracer's 16 samples per pixel, the chains' paths three
// edges or more (MltSettings::direct_samples, relative target).
TEST(MltVsBdpt, PathSpaceFogDoor) {
  const json scene = load_scene("fog_door.json");
  expect_same_image(scene, "fog door", 16, 64, "luminance", {"mlt"});
  expect_same_image(scene, "fog door (relative)", 16, 64, "relative", {"mlt"});
  expect_same_image(scene, "fog door (direct by path tracing)", 16, 64, "relative", {"mlt"},
                    {json{{"mlt_direct_samples", 16}}});
}
// The same over a floor seen and lit through a card half Transparent BSDF: the path tracer's
// direct light is every path with one scattering vertex, however many layers it passes, so
// the chains' paths need two scattering vertices, passes not counted (their vertices passed
// straight through counted, the direct light through the card was added twice: 1.38x and
// 1.32x the path tracer's mean in two 32 px CLI runs).
TEST(MltVsBdpt, PathSpaceDirectLightThroughAlphaByPathTracing) {
  const json scene = {
      {"settings", {{"mlt_direct_samples", 16}}},
      {"camera", {{"focal_length", 35}, {"transform", {{"look_at", {{"from", {0, -1.5, 3}}, {"to", {0, 0, 0}}}}}}}},
      {"world", {{"color", {0, 0, 0}}}},
      {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.8, 0.8, 0.8}}},
                     {{"name", "leaf"}, {"type", "mix"}, {"fac", 0.5},
                      {"shader1", {{"type", "diffuse"}, {"color", {0.2, 0.6, 0.1}}}},
                      {"shader2", {{"type", "transparent"}}}}}},
      {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}},
                  {{"name", "leaf"}, {"shape", {{"type", "quad"}, {"size", 3}}}, {"materials", {"leaf"}},
                   {"transform", {{"translate", {0, 0, 1.5}}}}}}},
      {"lights", {{{"type", "area"}, {"power", 300}, {"size", 0.5}, {"position", {0, 0, 2.5}}, {"direction", {0, 0, -1}}}}}};
  expect_same_image(scene, "alpha card (direct by path tracing)", 32, 64, "relative", {"mlt"});
}
// Plain transparent layers as parts of edges (path_space.h): a floor seen through a leaf (half
// diffuse, half Transparent BSDF) that covers the view, lit by a point lamp without a radius
// through a tinted Transparent BSDF sheet and the leaf. With the layers as path vertices no
// strategy made the lamp's light on the floor behind them (a fully transparent card over the
// floor: mlt 0.0088 against the path tracer's 0.609, docs/mlt.md).
TEST(MltVsBdpt, PathSpacePointLampThroughCards) {
  const json scene = {
      {"camera", {{"focal_length", 35}, {"transform", {{"look_at", {{"from", {0, -1.5, 3}}, {"to", {0, 0, 0}}}}}}}},
      {"world", {{"color", {0, 0, 0}}}},
      {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.8, 0.8, 0.8}}},
                     {{"name", "leaf"}, {"type", "mix"}, {"fac", 0.5},
                      {"shader1", {{"type", "diffuse"}, {"color", {0.2, 0.6, 0.1}}}},
                      {"shader2", {{"type", "transparent"}}}},
                     {{"name", "sheet"}, {"type", "transparent"}, {"color", {0.9, 0.6, 0.4}}}}},
      {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}},
                  {{"name", "leaf"}, {"shape", {{"type", "quad"}, {"size", 3}}}, {"materials", {"leaf"}},
                   {"transform", {{"translate", {0, 0, 1.5}}}}},
                  {{"name", "sheet"}, {"shape", {{"type", "quad"}, {"size", 1}}}, {"materials", {"sheet"}},
                   {"transform", {{"translate", {0.3, 0, 2.2}}}}}}},
      {"lights", {{{"type", "point"}, {"power", 300}, {"radius", 0}, {"position", {0, 0, 2.5}}}}}};
  expect_same_image(scene, "point lamp through cards", 8, 64, "luminance", {"mlt"});
}
// Specular vertices (delta lobes in paths): the caustic of a smooth glass ball seen directly
// and in a mirror, its lamp made a point (radius 0), and the volume caustic (the ball
// focusing a spot into fog). 4x the mutations of the others (the mirror caustic's mean then has
// a standard error of 0.5%; the volume caustic's run means spread about 2-3%; mlt refuses
// its 2 cm spot in fog, docs/mlt.md, so it is made a point here). The mirror
// caustic's own 3 cm lamp is not here: its image in the mirror and through the ball (paths
// E S+ L, 7% of this 48 px image in about 1e-6 of path space) is reached only when a
// camera-side walk hits the sphere, which mlt's chains rarely do (docs/mlt.md).
// Then the multi-chain perturbation and the lens subpath mutation doing most of the small
// steps (weight 3 each against 1 for the bidirectional mutation, lens and caustic
// perturbations) on the same scene: the floor seen through the ball and the caustic seen in
// the mirror (E D S S D L, E S D S S D L: the turned chains), every pixel swept by the lens
// subpath mutation's stratified positions.
TEST(MltVsBdpt, PathSpaceMirrorCaustic) {
  json scene = load_scene("mirror_caustic.json");
  for (auto &light : scene["lights"]) light["radius"] = 0;
  expect_same_image(scene, "mirror caustic", 16, 256, "luminance", {"mlt"});
  const json mutations = {{"bidirectional", 1}, {"lens", 1}, {"caustic", 1}, {"multi_chain", 3}, {"lens_subpath", 3}};
  expect_same_image(scene, "mirror caustic (multi-chain, lens subpath)", 16, 256, "luminance", {"mlt"},
                    {json{{"mlt_mutations", mutations}}});
}
TEST(MltVsBdpt, PathSpaceVolumeCaustic) {
  expect_same_image(load_scene("volume_caustic.json"), "volume caustic", 32, 256, "luminance", {"mlt"});
}
// Its spot made a point: the same paths without the lamp's sphere; and with equiangular
// distances toward the lamp (mlt/equiangular.h, off by default), against the same BDPT runs.
TEST(MltVsBdpt, PathSpaceVolumeCausticPointSpot) {
  json scene = load_scene("volume_caustic.json");
  for (auto &light : scene["lights"]) light["radius"] = 0;
  expect_same_image(scene, "volume caustic (point spot)", 32, 256, "luminance", {"mlt"},
                    {json::object(), json{{"mlt_equiangular", 0.25}}});
}
// Fog lit by a spot with a radius (fog_spot.json's 5 cm spot: a sphere lamp in a medium).
TEST(MltVsBdpt, PathSpaceFogSpot) {
  expect_same_image(load_scene("fog_spot.json"), "fog spot", 16, 32, "luminance", {"mlt"});
}
// Cameras (path_space.h): a thin lens with a hexagonal aperture focused on the back wall
// (the front of the boxes blurred), and an orthographic camera that sees the world around
// the box (E W along its axis: paths only the camera side makes).
TEST(MltVsBdpt, PathSpaceThinLens) {
  json scene = load_scene("cornell_box.json");
  scene["camera"].update({{"fstop", 0.5}, {"focus_distance", 4.9}, {"blades", 6}});
  expect_same_image(scene, "cornell (thin lens)", 32, 64, "luminance", {"mlt"});
}
TEST(MltVsBdpt, PathSpaceOrthographic) {
  json scene = load_scene("cornell_box.json");
  scene["camera"].update({{"type", "orthographic"}, {"ortho_scale", 2.8}});
  scene["world"] = {{"color", {0.2, 0.25, 0.3}}};
  expect_same_image(scene, "cornell (orthographic, world)", 8, 64, "luminance", {"mlt"});
}
// Orthographic with depth of field: x_0 a point of the image plane (path_space.h), the
// aperture 0.5 m wide (Blender's 1 / (2 fstop) at f/1), a pentagon, focused on the back wall.
TEST(MltVsBdpt, PathSpaceOrthographicLens) {
  json scene = load_scene("cornell_box.json");
  scene["camera"].update(
      {{"type", "orthographic"}, {"ortho_scale", 2.8}, {"fstop", 1.0}, {"focus_distance", 4.9}, {"blades", 5}});
  scene["world"] = {{"color", {0.2, 0.25, 0.3}}};
  expect_same_image(scene, "cornell (orthographic lens, world)", 32, 64, "luminance", {"mlt"});
}

// Lights at infinity and textured emission: the Cornell box with its lamp taken out of the
// ceiling (a window), lit through it by the sky HDRI and a sun 0.1 rad wide (their paths
// end at one vertex at infinity), and by a sun without an angle (a delta in direction,
// reached from the light side only); the Cornell box with its lamp's emission an image.
json cornell_window(double sun_angle) {
  json j = load_scene("cornell_box.json");
  json meshes = json::array();
  for (auto &m : j["meshes"])
    if (m["name"] != "lamp") meshes.push_back(m);
  j["meshes"] = meshes;
  j["world"] = {{"environment", {{"file", source_path("scenes/textures/sky_small.hdr")}}}, {"strength", 1.0}};
  j["lights"] = json::array(
      {{{"name", "sun"}, {"type", "sun"}, {"direction", {0.15, 0.1, -1}}, {"angle", sun_angle}, {"strength", 3}}});
  return j;
}
TEST(MltVsBdpt, PathSpaceWindowSkyAndSun) {
  expect_same_image(cornell_window(0.1), "window (sky, 0.1 rad sun)", 8, 64, "luminance", {"mlt"});
}
TEST(MltVsBdpt, PathSpaceWindowSkyAndDeltaSun) {
  expect_same_image(cornell_window(0.0), "window (sky, delta sun)", 16, 64, "luminance", {"mlt"});
}
// A box of fog under the window: medium vertices whose light-side neighbour is at infinity
// (the propagation perturbation moves them along its direction, the scattering one turns it).
TEST(MltVsBdpt, PathSpaceWindowFogBox) {
  json j = cornell_window(0.1);
  j["materials"].push_back(
      {{"name", "fog"}, {"type", "volume"}, {"volume", {{"density", 0.8}, {"color", {0.9, 0.9, 0.9}}, {"anisotropy", 0.3}}}});
  j["meshes"].push_back({{"name", "fog_box"}, {"shape", {{"type", "box"}, {"size", {1.6, 1.6, 0.5}}}},
                         {"materials", {"fog"}}, {"transform", {{"translate", {0, 0, 1.6}}}}});
  expect_same_image(j, "window fog box", 8, 64, "luminance", {"mlt"});
}
// Grid fog (integrators/mlt/free_flights.h): a box of it under the Cornell box's ceiling,
// its density varying from voxel to voxel; BDPT samples it by delta and ratio tracking.
TEST(MltVsBdpt, PathSpaceGridFog) {
  expect_same_image(cornell_grid_fog(load_scene("cornell_box.json"), 2.0), "grid fog", 32, 64, "luminance", {"mlt"});
}
// Emissive media (volume lights): the grid fog emitting through an emission grid, the
// Cornell box's lamp taken out, so the fog is the only light (seen directly, through itself
// and on the walls). BDPT reaches it by light subpaths and next-event estimation from the
// volume light and by gathering along camera segments.
TEST(MltVsBdpt, PathSpaceEmissiveGridFog) {
  json j = load_scene("cornell_box.json");
  json meshes = json::array();
  for (auto &m : j["meshes"])
    if (m["name"] != "lamp") meshes.push_back(m);
  j["meshes"] = meshes;
  const json emission = {{"emission_color", {1.0, 0.6, 0.3}},
                         {"emission_strength", 1.5},
                         {"emission_grid", varied_grid(5, 4, 6, {{-0.9, -0.9, 1.3}, {0.9, 0.9, 1.9}})}};
  expect_same_image(cornell_grid_fog(j, 2.0, emission), "emissive grid fog", 8, 64, "luminance", {"mlt"});
}
// The same with ray visibility elsewhere in the scene (the tall block hidden from the
// camera: the fog's emission and the walls behind the block seen through it): mlt refused
// any emissive volume in a scene with ray visibility before 2026-11-29; now only one whose
// own object has visibility settings.
TEST(MltVsBdpt, PathSpaceEmissiveGridFogWithRayVisibility) {
  json j = load_scene("cornell_box.json");
  json meshes = json::array();
  for (auto &m : j["meshes"]) {
    if (m["name"] == "lamp") continue;
    if (m["name"] == "tall_block") m["visibility"] = {{"camera", false}};
    meshes.push_back(m);
  }
  j["meshes"] = meshes;
  const json emission = {{"emission_color", {1.0, 0.6, 0.3}},
                         {"emission_strength", 1.5},
                         {"emission_grid", varied_grid(5, 4, 6, {{-0.9, -0.9, 1.3}, {0.9, 0.9, 1.9}})}};
  expect_same_image(cornell_grid_fog(j, 2.0, emission), "emissive grid fog, block hidden from the camera", 8, 64,
                    "luminance", {"mlt"});
}
TEST(MltVsBdpt, PathSpaceTexturedLamp) {
  json j = load_scene("cornell_box.json");
  for (auto &m : j["materials"])
    if (m["name"] == "lamp") m["color"] = {{"node", "image"}, {"file", source_path("scenes/textures/tiles.png")}};
  expect_same_image(j, "textured lamp", 16, 64, "luminance", {"mlt"});
}

// Emission by the distance its light travels (Light Falloff, test_light_falloff.cpp): a
// sphere lamp Linear, an area lamp with Smooth, an emissive panel Constant. pssmlt's states
// are BDPT's samples (light subpaths weighed once their first segment is traced); mlt's f
// takes each emitter's distance to the path's next vertex.
TEST(MltVsBdpt, LightFalloff) {
  expect_same_image(load_scene("light_falloff.json"), "light falloff", 16, 64, "relative", {"pssmlt", "mlt"});
}

// Lamps whose tree varies over them (test_lamp_textures.cpp): a checker over an area lamp, a
// spot's colour by direction, a sphere lamp's strength by position. mlt's f evaluates each at
// the path's vertex on the lamp.
TEST(MltVsBdpt, LampTextures) {
  expect_same_image(load_scene("lamp_textures.json"), "lamp textures", 32, 64, "relative", {"pssmlt", "mlt"});
}

// A fixed chain count gives the same image on any number of threads (chains seeded by
// (seed, chain), a deterministic pass schedule, splats applied in chain order).
TEST(MltDeterminism, SameImageOnOneAndTwoThreads) {
  json scene = load_scene("cornell_box.json");
  for (const char *integrator : {"pssmlt", "mmlt", "mlt"}) {
    json s = {{"width", 32}, {"height", 24}, {"integrator", integrator}, {"samples", 16}, {"seed", 5},
              {"mlt_chains", 16}};
    s["threads"] = 1;
    Image one = render_json(scene.dump(), s.dump());
    s["threads"] = 2;
    Image two = render_json(scene.dump(), s.dump());
    ASSERT_EQ(one.rgba.size(), two.rgba.size());
    EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float))) << integrator;
    EXPECT_EQ(one.stats, two.stats) << integrator;
    EXPECT_GT(one.channel_mean(0), 0.0f) << integrator;
  }
}

// The same with specular vertices and every perturbation (the volume caustic, a point spot).
TEST(MltDeterminism, VolumeCausticSameImageOnOneAndTwoThreads) {
  json scene = load_scene("volume_caustic.json");
  for (auto &light : scene["lights"]) light["radius"] = 0;
  json s = {{"width", 32}, {"height", 24}, {"integrator", "mlt"}, {"samples", 16}, {"seed", 5}, {"mlt_chains", 16}};
  s["threads"] = 1;
  Image one = render_json(scene.dump(), s.dump());
  s["threads"] = 2;
  Image two = render_json(scene.dump(), s.dump());
  ASSERT_EQ(one.rgba.size(), two.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float)));
  EXPECT_EQ(one.stats, two.stats);
  EXPECT_TRUE(one.all_finite());
  EXPECT_GT(json::parse(one.stats)["mutation_types"]["caustic"]["proposals"].get<uint64_t>(), 0u);
}

// A scene whose bootstrap finds no light: black, with a warning naming the cause;
// finishes (no hang), no NaN.
TEST(MltRobustness, NoLightRendersBlackWithAWarning) {
  json scene = load_scene("cornell_box.json");
  for (json &m : scene["materials"])
    if (m["name"] == "lamp") m = {{"name", "lamp"}, {"type", "diffuse"}, {"color", {0.5, 0.5, 0.5}}};
  for (const char *integrator : {"pssmlt", "mmlt", "mlt"}) {
    json s = {{"width", 16}, {"height", 16}, {"integrator", integrator}, {"samples", 4}};
    Image img = render_json(scene.dump(), s.dump());
    EXPECT_TRUE(img.all_finite());
    EXPECT_EQ(img.channel_mean(0), 0.0f);
    EXPECT_EQ(img.progress.finished, 1);
    json stats = json::parse(img.stats);
    ASSERT_TRUE(stats.contains("warning")) << img.stats;
    EXPECT_NE(stats["warning"].get<std::string>().find("no light"), std::string::npos) << img.stats;
  }
}

// Stats: acceptance per mutation type, chains, b and its error; samples = mutations per pixel.
TEST(MltStats, ReportedThroughTheCAbi) {
  json s = {{"width", 24}, {"height", 16}, {"integrator", "pssmlt"}, {"samples", 8}, {"mlt_chains", 32}};
  Image img = render_json(load_scene("cornell_box.json").dump(), s.dump());
  json stats = json::parse(img.stats);
  EXPECT_EQ(stats["chains"], 32);
  EXPECT_EQ(stats["mutations"].get<uint64_t>(), 8u * 24 * 16);
  EXPECT_EQ(img.progress.samples_done, 8u);
  EXPECT_GT(stats["b"].get<double>(), 0.0);
  EXPECT_GT(stats["b_standard_error"].get<double>(), 0.0);
  EXPECT_LT(stats["b_standard_error"].get<double>(), stats["b"].get<double>());
  EXPECT_GT(stats["small_step_acceptance"].get<double>(), 0.0);
  EXPECT_GT(stats["large_step_acceptance"].get<double>(), 0.0);
}

// Detailed balance of multiplexed MLT: the share of mutations that end in each (depth,
// s) state matches the target distribution, each strategy's share of b as the
// bootstrap's independent samples measure it through BDPT's connection and MIS code.
// Cornell box, max_bounces 3 (13 states, 10 of them carry light); 10 runs with independent
// seeds give each share's spread (chains are autocorrelated, runs are not); every state
// with at least 0.1% of the target is compared by Welch's t-test, false-alarm rate 1e-3
// for the whole test (Sidak over the states).
TEST(MmltDetailedBalance, StrategyHistogramMatchesTheTarget) {
  constexpr int kBalanceRuns = 10;
  json scene = load_scene("cornell_box.json");
  json s = {{"width", 24}, {"height", 24}, {"max_bounces", 3}, {"integrator", "mmlt"}, {"samples", 128},
            {"mlt_bootstrap", 16}, {"mlt_chains", 32}};
  std::vector<std::vector<double>> chain_share, target_share;
  for (int k = 0; k < kBalanceRuns; ++k) {
    s["seed"] = 300 + k;
    Image img = render_json(scene.dump(), s.dump());
    json stats = json::parse(img.stats);
    auto counts = stats["strategy_counts"].get<std::vector<double>>();
    auto target = stats["strategy_b"].get<std::vector<double>>();
    ASSERT_EQ(counts.size(), 13u);
    ASSERT_EQ(target.size(), 13u);
    double n = 0, b = 0;
    for (size_t i = 0; i < counts.size(); ++i) { n += counts[i]; b += target[i]; }
    ASSERT_GT(n, 0);
    ASSERT_GT(b, 0);
    for (double &c : counts) c /= n;
    for (double &t : target) t /= b;
    chain_share.push_back(counts);
    target_share.push_back(target);
  }
  const double alpha = 1.0 - std::pow(1.0 - 1e-3, 1.0 / 13);
  std::string table;
  for (size_t i = 0; i < 13; ++i) {
    std::vector<double> c, t;
    for (int k = 0; k < kBalanceRuns; ++k) { c.push_back(chain_share[k][i]); t.push_back(target_share[k][i]); }
    double mc, ec, mt, et;
    mean_and_error(c, mc, ec);
    mean_and_error(t, mt, et);
    double se2 = ec * ec + et * et;
    char line[128];
    std::snprintf(line, sizeof line, "state %2zu: chains %.6f +- %.6f, target %.6f +- %.6f\n", i, mc, ec, mt, et);
    table += line;
    // States with under 0.1% of the target (here the s = 0 strategies past depth 0, whose
    // power-heuristic weight next to the lamp's own sampling is ~1e-3) see a few dozen
    // mutations in all the runs: too few visits for a spread from 10 runs; their share is
    // still bounded.
    if (mt < 1e-3) {
      EXPECT_LT(mc, 1e-3) << line;
      continue;
    }
    double t_stat = (mc - mt) / std::sqrt(se2);
    double dof = se2 * se2 / (std::pow(ec, 4) / (kBalanceRuns - 1) + std::pow(et, 4) / (kBalanceRuns - 1));
    EXPECT_GT(student_t_two_sided(std::fabs(t_stat), dof), alpha) << line;
  }
  std::printf("%s", table.c_str());
}

// Cancel stops a Metropolis render that would take very long, in its bootstrap or its
// chains; the film stays readable and finite. (How fast is a benchmark figure.)
TEST(MltRobustness, CancelStopsCleanly) {
  for (const char *integrator : {"pssmlt", "mmlt"}) {
    for (int wait_ms : {0, 300}) {
      rdv_scene *scene = nullptr;
      ASSERT_EQ(RDV_OK, rdv_scene_create(&scene));
      rdv_tools::load_scene_file(source_path("scenes/cornell_box.json"), scene);
      json s = {{"width", 64}, {"height", 64}, {"samples", 1000000}, {"integrator", integrator}};
      rdv_session *session = nullptr;
      ASSERT_EQ(RDV_OK, rdv_session_create(scene, s.dump().c_str(), &session));
      ASSERT_EQ(RDV_OK, rdv_session_start(session));
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
      ASSERT_EQ(RDV_OK, rdv_session_cancel(session));
      ASSERT_EQ(RDV_OK, rdv_session_wait(session));
      rdv_progress p{};
      ASSERT_EQ(RDV_OK, rdv_session_progress(session, &p));
      EXPECT_EQ(p.finished, 1);
      EXPECT_EQ(p.cancelled, 1);
      std::vector<float> px(64 * 64 * 4);
      ASSERT_EQ(RDV_OK, rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 64, 64, 1, px.data()));
      for (float v : px) ASSERT_TRUE(std::isfinite(v)) << integrator;
      rdv_session_destroy(session);
      rdv_scene_destroy(scene);
    }
  }
}

}  // namespace test_mlt
