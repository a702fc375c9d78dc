// Replaying primary samples (what Metropolis light transport needs of the integrators):
// a RecordingSampler logs every (stream, position, value) a sample draws, a
// ReplayingSampler hands the logged values back, and the same numbers must give the
// same path and contribution bit for bit, for the path tracer and BDPT (splats
// included), on a scene with a delta-tracked grid cloud, a ray-marched grid, an
// emissive grid (a volume light), homogeneous fog and an image-textured floor.
// Also: BDPT's streams are separate (a changed light-stream number leaves the camera
// subpath alone and the other way round), and a medium on the way does not move the
// dimensions of later decisions (samplers/dimension_layout.h).
// Deterministic (fixed seeds, exact comparisons): nothing here fails by chance.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/path/path_tracer.h"
#include "media_grids.h"
#include "render_helpers.h"
#include "samplers/dimension_layout.h"

namespace test_replay {

using namespace rdv;
using nlohmann::json;

namespace {

struct Draw {
  SampleStream stream;
  uint32_t position;
  bool two_d;
  Vec2 value;
};
using DrawKey = std::tuple<uint32_t, uint32_t, bool>;
DrawKey key(const Draw &d) { return {uint32_t(d.stream), d.position, d.two_d}; }

// Follows the stream position as samplers do (start_sample: Camera, 0; each draw
// takes one position) and logs each draw of the wrapped sampler.
class RecordingSampler final : public Sampler {
 public:
  explicit RecordingSampler(Sampler &inner) : inner_(inner) {}
  void start_sample(uint32_t px, uint32_t py, uint32_t index) override {
    inner_.start_sample(px, py, index);
    stream_ = SampleStream::Camera;
    position_ = 0;
    log.clear();
  }
  void start_stream(SampleStream stream, uint32_t position) override {
    inner_.start_stream(stream, position);
    stream_ = stream;
    position_ = position;
  }
  float get_1d() override {
    float v = inner_.get_1d();
    log.push_back({stream_, position_++, false, Vec2(v, 0.0f)});
    return v;
  }
  Vec2 get_2d() override {
    Vec2 v = inner_.get_2d();
    log.push_back({stream_, position_++, true, v});
    return v;
  }
  std::vector<Draw> log;

 private:
  Sampler &inner_;
  SampleStream stream_ = SampleStream::Camera;
  uint32_t position_ = 0;
};

// Returns the recorded values; a draw that was never recorded is counted in `misses`.
class ReplayingSampler final : public Sampler {
 public:
  explicit ReplayingSampler(const std::vector<Draw> &log) {
    for (const Draw &d : log) values_.emplace(key(d), d.value);
  }
  void set(const Draw &d, Vec2 value) { values_[key(d)] = value; }
  void start_sample(uint32_t, uint32_t, uint32_t) override { start_stream(SampleStream::Camera, 0); }
  void start_stream(SampleStream stream, uint32_t position) override {
    stream_ = stream;
    position_ = position;
  }
  float get_1d() override { return lookup(false).x; }
  Vec2 get_2d() override { return lookup(true); }
  int misses = 0;
  std::vector<SampleStream> streams_read;

 private:
  Vec2 lookup(bool two_d) {
    streams_read.push_back(stream_);
    auto it = values_.find({uint32_t(stream_), position_++, two_d});
    if (it == values_.end()) {
      ++misses;
      return Vec2(0.5f, 0.5f);
    }
    return it->second;
  }
  std::map<DrawKey, Vec2> values_;
  SampleStream stream_ = SampleStream::Camera;
  uint32_t position_ = 0;
};

struct LoadedScene {
  rdv_scene *handle = nullptr;
  ~LoadedScene() { rdv_scene_destroy(handle); }
  const Scene &scene() const { return *handle->scene; }
};

void load(LoadedScene &s, const json &doc, int width, int height) {
  rdv_scene_create(&s.handle);
  auto loaded = rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), s.handle);
  ASSERT_TRUE(loaded.problems.empty());
  ASSERT_EQ(rdv_scene_commit(s.handle), RDV_OK);
  s.handle->scene->camera().set_resolution(width, height);
}

json fog_spot() {
  std::ifstream f(test::source_path("scenes/fog_spot.json"));
  std::stringstream ss;
  ss << f.rdbuf();
  return json::parse(ss.str());
}

// A 64 x 64 two-tone checker image (filtered lookups through the ray cone's MIP level).
std::string checker_image() {
  std::string path = test::temp_path("replay_checker.png");
  std::vector<float> px(64 * 64 * 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) px[(y * 64 + x) * 3 + c] = ((x / 4 + y / 4) % 2) ? 0.9f : (c == 0 ? 0.6f : 0.1f);
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(64, 64, 3, OIIO::TypeDesc::UINT8))) << path;
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
  return path;
}

// fog_spot.json (homogeneous fog in a box, a spot) with an image-textured floor, a
// delta-tracked grid cloud and a ray-marched grid nested in the fog, and an emissive
// grid (a volume light: emission and blackbody from grids) in place of the ball.
json media_scene() {
  json scene = fog_spot();
  scene["materials"][0]["color"] = {{"node", "image"}, {"file", checker_image()},
                                    {"vector", {{"node", "texture_coordinate"}, {"output", "uv"}}}};
  json unit = {{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}};
  auto at = [](json grid, json translate) {
    grid["transform"] = {{"translate", translate}};
    return grid;
  };
  json temperature = test::puff_grid(24, unit);
  for (auto &v : temperature["values"]) v = float(v) * 1500.0f;
  const json fire_at = {0.2, 0.5, 1.4}, cloud_at = {-1.0, 0.0, 1.0}, marched_at = {1.2, -0.5, 0.8};
  scene["materials"].push_back({{"name", "fire"}, {"type", "volume"},
                                {"volume", {{"density", 12.0}, {"color", 0.6}, {"blackbody_intensity", 1.0},
                                            {"temperature", 1.0}, {"temperature_grid", at(temperature, fire_at)},
                                            {"emission_color", {1.0, 0.4, 0.1}}, {"emission_strength", 2000.0},
                                            {"emission_grid", at(test::puff_grid(24, unit), fire_at)},
                                            {"grid", at(test::puff_grid(12, unit), fire_at)}}}});
  scene["materials"].push_back({{"name", "cloud"}, {"type", "volume"},
                                {"volume", {{"density", 20.0}, {"color", {0.9, 0.8, 0.7}}, {"anisotropy", 0.3},
                                            {"grid", at(test::puff_grid(12, unit), cloud_at)}}}});
  scene["materials"].push_back({{"name", "marched"}, {"type", "volume"},
                                {"volume", {{"density", 4.0}, {"color", 0.7}, {"method", "ray_marching"},
                                            {"grid", at(test::puff_grid(12, unit), marched_at)}}}});
  scene["meshes"][2]["shape"] = {{"type", "box"}, {"size", {1, 1, 1}}};
  scene["meshes"][2]["materials"] = {"fire"};
  scene["meshes"][2]["transform"] = {{"translate", fire_at}};
  scene["meshes"].push_back({{"name", "cloud_box"}, {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}},
                             {"materials", {"cloud"}}, {"transform", {{"translate", cloud_at}}}});
  scene["meshes"].push_back({{"name", "marched_box"}, {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}},
                             {"materials", {"marched"}}, {"transform", {{"translate", marched_at}}}});
  scene["lights"][0]["radius"] = 0.1;
  return scene;
}

constexpr int kWidth = 16, kHeight = 12, kSamples = 8;

// The camera ray of a sample, drawn as the session draws it (Camera positions 0 and 1).
CameraRay camera_ray(const Scene &scene, Sampler &sampler, int px, int py) {
  CameraRay cr;
  Vec2 u_pixel = sampler.get_2d();
  cr.ray = scene.camera().generate_ray(Vec2(px + u_pixel.x, py + u_pixel.y), sampler.get_2d(), &cr.lens_point,
                                       &cr.cone);
  return cr;
}

bool same_bits(Color a, Color b) { return std::memcmp(&a, &b, sizeof(Color)) == 0; }

struct Coverage {  // how much of the machinery the recorded samples went through
  int crossing = 0, long_run = 0, volume_point = 0, connection = 0, lens = 0, next_event_media = 0;
  void count(const std::vector<Draw> &log) {
    for (const Draw &d : log) {
      uint32_t in_bounce = (d.position - dims::kWalkStart) % dims::kBounceDims;
      bool walk = d.stream == SampleStream::Camera || d.stream == SampleStream::Light;
      crossing += d.stream == SampleStream::CameraCrossing || d.stream == SampleStream::LightCrossing;
      // Runs that reach their last fixed dimension (and may go on with the generator).
      long_run += walk && d.position >= dims::kWalkStart &&
                  (in_bounce == dims::kMedium + dims::kMediumRun - 1 || in_bounce == dims::kGather + dims::kGatherRun - 1);
      volume_point += (d.stream == SampleStream::LightPoint && d.position % dims::kNeeDims == dims::kNeeVolumePoint) ||
                      (d.stream == SampleStream::Light && d.position == dims::kLightVolumePoint);
      connection += d.stream == SampleStream::Connection;
      lens += d.stream == SampleStream::Lens;
      next_event_media += d.stream == SampleStream::LightPoint && d.position % dims::kNeeDims >= dims::kNeeMedia;
    }
  }
};

// Renders every sample twice, recorded from Sobol and replayed from the record: the
// radiance and the splats must be the same bits, and the replay must read only
// recorded numbers.
void expect_replay_is_exact(const TileIntegrator &integrator, const Scene &scene, bool bdpt) {
  SobolSampler sobol(11);
  RecordingSampler recorder(sobol);
  Coverage coverage;
  int nonzero = 0;
  for (int py = 0; py < kHeight; ++py)
    for (int px = 0; px < kWidth; ++px)
      for (uint32_t s = 0; s < kSamples; ++s) {
        RayStats stats;
        std::vector<Splat> splats, replayed_splats;
        recorder.start_sample(px, py, s);
        Color L = integrator.Li(camera_ray(scene, recorder, px, py), recorder, stats, nullptr, splats);
        coverage.count(recorder.log);
        ReplayingSampler replay(recorder.log);
        replay.start_sample(px, py, s);
        Color L2 = integrator.Li(camera_ray(scene, replay, px, py), replay, stats, nullptr, replayed_splats);
        ASSERT_EQ(replay.misses, 0) << "pixel " << px << "," << py << " sample " << s;
        ASSERT_TRUE(same_bits(L, L2)) << "pixel " << px << "," << py << " sample " << s << ": " << L.x << " vs " << L2.x;
        ASSERT_EQ(splats.size(), replayed_splats.size());
        for (size_t i = 0; i < splats.size(); ++i) {
          ASSERT_TRUE(same_bits(splats[i].L, replayed_splats[i].L)) << "splat " << i;
          ASSERT_EQ(0, std::memcmp(&splats[i].raster, &replayed_splats[i].raster, sizeof(Vec2))) << "splat " << i;
        }
        nonzero += !is_black(L);
      }
  // The samples went through what this test is about.
  EXPECT_GT(nonzero, kWidth * kHeight * kSamples / 5);
  EXPECT_GT(coverage.crossing, 0);
  EXPECT_GT(coverage.long_run, 0);  // tracking runs that reach the seeded generator
  EXPECT_GT(coverage.volume_point, 0);
  EXPECT_GT(coverage.next_event_media, 0);
  if (bdpt) {
    EXPECT_GT(coverage.connection, 0);
    EXPECT_GT(coverage.lens, 0);
  }
}

}  // namespace

TEST(Replay, PathTracerSameSamplesSameContribution) {
  LoadedScene loaded;
  load(loaded, media_scene(), kWidth, kHeight);
  PathTracer pt(loaded.scene(), 8);
  expect_replay_is_exact(pt, loaded.scene(), false);
}

TEST(Replay, BdptSameSamplesSameContributionAndSplats) {
  LoadedScene loaded;
  load(loaded, media_scene(), kWidth, kHeight);
  bdpt::BdptSettings settings;
  settings.max_bounces = 8;
  bdpt::Bdpt bdpt(loaded.scene(), settings);
  expect_replay_is_exact(bdpt, loaded.scene(), true);
}

namespace {

bool same_vertices(const std::vector<bdpt::PathVertex> &a, int na, const std::vector<bdpt::PathVertex> &b, int nb) {
  if (na != nb) return false;
  for (int i = 0; i < na; ++i) {
    const bdpt::PathVertex &u = a[i], &v = b[i];
    if (std::memcmp(&u.p, &v.p, sizeof(Vec3)) || !same_bits(u.beta, v.beta) || u.pdf_fwd != v.pdf_fwd ||
        u.pdf_rev != v.pdf_rev || u.type != v.type)
      return false;
  }
  return true;
}

}  // namespace

// One number of the light stream changed: the camera subpath is the same (it never
// reads that stream), the light subpath is not. And the other way round.
TEST(Replay, BdptStreamsAreSeparate) {
  LoadedScene loaded;
  load(loaded, media_scene(), kWidth, kHeight);
  const Scene &scene = loaded.scene();
  bdpt::BdptSettings settings;
  settings.max_bounces = 8;
  bdpt::Bdpt bdpt(scene, settings);
  const size_t n = settings.max_bounces + 2;
  std::vector<bdpt::PathVertex> cam(n), light(n), cam2(n), light2(n);
  SobolSampler sobol(5);
  RecordingSampler recorder(sobol);
  int light_changed = 0, camera_changed = 0, samples = 0;
  for (int py = 0; py < kHeight; ++py)
    for (int px = 0; px < kWidth; ++px) {
      RayStats stats;
      std::vector<Color> emitted(n, Color(0.0f));  // per segment (Bdpt::camera_subpath)
      recorder.start_sample(px, py, 0);
      int nc = bdpt.camera_subpath<true>(camera_ray(scene, recorder, px, py), recorder, stats, cam.data(), emitted.data());
      for (const Draw &d : recorder.log)
        ASSERT_TRUE(d.stream == SampleStream::Camera || d.stream == SampleStream::CameraCrossing)
            << "the camera subpath read stream " << uint32_t(d.stream);
      int nl = bdpt.light_subpath<true>(recorder, stats, light.data());
      // Perturb the light's position (Light stream), then the first bounce's direction
      // (Camera stream), each in turn.
      for (bool perturb_light : {true, false}) {
        ReplayingSampler replay(recorder.log);
        Draw target{perturb_light ? SampleStream::Light : SampleStream::Camera,
                    perturb_light ? dims::kLightPosition : dims::bounce(1, dims::kScatterDirection), true, Vec2(0.0f, 0.0f)};
        auto it = std::find_if(recorder.log.begin(), recorder.log.end(),
                               [&](const Draw &d) { return key(d) == key(target); });
        if (it == recorder.log.end()) continue;  // the camera path ended before that bounce
        replay.set(*it, Vec2(std::fmod(it->value.x + 0.37f, 1.0f), std::fmod(it->value.y + 0.61f, 1.0f)));
        replay.start_sample(px, py, 0);
        int nc2 = bdpt.camera_subpath<true>(camera_ray(scene, replay, px, py), replay, stats, cam2.data(), emitted.data());
        int nl2 = bdpt.light_subpath<true>(replay, stats, light2.data());
        bool cam_same = same_vertices(cam, nc, cam2, nc2), light_same = same_vertices(light, nl, light2, nl2);
        if (perturb_light) {
          EXPECT_TRUE(cam_same) << "pixel " << px << "," << py << ": a light-stream number moved the camera subpath";
          light_changed += !light_same;
          ++samples;
        } else {
          EXPECT_TRUE(light_same) << "pixel " << px << "," << py << ": a camera-stream number moved the light subpath";
          camera_changed += !cam_same;
        }
      }
    }
  EXPECT_GT(light_changed, samples / 2);  // the perturbation did reach the light subpath
  EXPECT_GT(camera_changed, 0);
}

namespace {

// The positions (and values) of the decisions at the path's vertices: scattering
// (BSDF lobe and direction), Russian roulette and next-event estimation.
std::vector<Draw> vertex_decisions(const std::vector<Draw> &log) {
  std::vector<Draw> out;
  for (const Draw &d : log) {
    bool walk = d.stream == SampleStream::Camera && d.position >= dims::kWalkStart &&
                (d.position - dims::kWalkStart) % dims::kBounceDims < dims::kMedium;
    bool nee = d.stream == SampleStream::LightPoint && d.position % dims::kNeeDims < dims::kNeeMedia;
    if (walk || nee) out.push_back(d);
  }
  return out;
}

}  // namespace

// The same scene with and without an absorbing grid medium around the camera and the
// ball (index-matched: no surface of its own): every path visits the same surfaces, and
// each vertex's decisions must draw from the same dimensions, however many tracking
// steps and boundary crossings the medium took before them.
TEST(Replay, AMediumDoesNotShiftLaterDimensions) {
  json plain = fog_spot();
  plain["meshes"].erase(3);     // no fog
  plain["materials"].erase(3);
  plain["lights"][0]["radius"] = 0.1;
  json absorbing = plain;
  absorbing["materials"].push_back(
      {{"name", "smoke"}, {"type", "volume"},
       {"volume", {{"sigma_a", {0.3, 0.5, 0.8}}, {"sigma_s", 0},
                   {"grid", test::puff_grid(12, {{-2, -5, -0.1}, {2, 2, 3.3}})}}}});
  absorbing["meshes"].push_back({{"name", "smoke_box"}, {"shape", {{"type", "box"}, {"size", {4, 7, 3.4}}}},
                                 {"materials", {"smoke"}}, {"transform", {{"translate", {0, -1.5, 1.6}}}}});
  LoadedScene a, b;
  load(a, plain, kWidth, kHeight);
  load(b, absorbing, kWidth, kHeight);
  ASSERT_FALSE(a.scene().has_media());
  ASSERT_TRUE(b.scene().has_media());
  // Short enough that Russian roulette (which depends on the absorbed throughput) never
  // runs: the path tracer's starts at bounce 3, BDPT's at its fourth vertex.
  const int max_bounces = 3;
  PathTracer pt_a(a.scene(), max_bounces), pt_b(b.scene(), max_bounces);
  bdpt::BdptSettings settings;
  settings.max_bounces = max_bounces - 1;
  bdpt::Bdpt bdpt_a(a.scene(), settings), bdpt_b(b.scene(), settings);
  std::vector<bdpt::PathVertex> cam_a(max_bounces + 2), cam_b(max_bounces + 2);
  SobolSampler sobol(3);
  RecordingSampler rec(sobol);
  int medium_draws = 0, compared = 0;
  for (int py = 0; py < kHeight; ++py)
    for (int px = 0; px < kWidth; ++px)
      for (uint32_t s = 0; s < kSamples; ++s) {
        RayStats stats;
        std::vector<Splat> splats;
        rec.start_sample(px, py, s);
        pt_a.Li(camera_ray(a.scene(), rec, px, py), rec, stats, nullptr, splats);
        std::vector<Draw> plain_log = vertex_decisions(rec.log);
        rec.start_sample(px, py, s);
        pt_b.Li(camera_ray(b.scene(), rec, px, py), rec, stats, nullptr, splats);
        std::vector<Draw> medium_log = vertex_decisions(rec.log);
        medium_draws += int(rec.log.size()) - int(medium_log.size()) - 2;
        ASSERT_EQ(plain_log.size(), medium_log.size()) << "path tracer, pixel " << px << "," << py << " sample " << s;
        for (size_t i = 0; i < plain_log.size(); ++i) {
          ASSERT_TRUE(key(plain_log[i]) == key(medium_log[i])) << "path tracer, pixel " << px << "," << py;
          ASSERT_EQ(plain_log[i].value.x, medium_log[i].value.x);
        }
        // BDPT's camera subpath: the same vertex decisions at the same dimensions, and
        // the same first hit (within the rounding of ray origins spawned at the medium's
        // boundaries, which later bounces off the curved ball magnify).
        std::vector<Color> emitted(dims::kMaxVertices, Color(0.0f));  // per segment (Bdpt::camera_subpath)
        rec.start_sample(px, py, s);
        int na = bdpt_a.camera_subpath<false>(camera_ray(a.scene(), rec, px, py), rec, stats, cam_a.data(), emitted.data());
        plain_log = vertex_decisions(rec.log);
        rec.start_sample(px, py, s);
        int nb = bdpt_b.camera_subpath<true>(camera_ray(b.scene(), rec, px, py), rec, stats, cam_b.data(), emitted.data());
        medium_log = vertex_decisions(rec.log);
        ASSERT_EQ(na, nb) << "bdpt, pixel " << px << "," << py << " sample " << s;
        ASSERT_EQ(plain_log.size(), medium_log.size()) << "bdpt, pixel " << px << "," << py << " sample " << s;
        for (size_t i = 0; i < plain_log.size(); ++i)
          ASSERT_TRUE(key(plain_log[i]) == key(medium_log[i])) << "bdpt, pixel " << px << "," << py;
        if (na > 1) {
          ASSERT_LT(length(cam_a[1].p - cam_b[1].p), 1e-3f * (1 + length(cam_a[1].p))) << "bdpt first hit";
          ++compared;
        }
      }
  EXPECT_GT(medium_draws, kWidth * kHeight * kSamples);  // the medium did draw (tracking, shadow rays)
  EXPECT_GT(compared, kWidth * kHeight * kSamples / 2);
}

}  // namespace test_replay
