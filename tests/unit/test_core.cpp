// Camera framing (Blender's sensor fit and shift), parameter parsing, the sampler.
#include <gtest/gtest.h>
#include <cmath>
#include "bsdfs/ggx_albedo.h"
#include "core/params.h"
#include "film/film.h"
#include "samplers/sampler.h"
#include "scene/camera.h"

namespace test_core {

using namespace rdv;

static Camera camera(const std::string &json, int w, int h) {
  Params p(json, "camera");
  Camera c = Camera::from_params(p);
  c.set_resolution(w, h);
  return c;
}

TEST(Camera, SensorFitAutoUsesTheWiderDimension) {
  Camera c = camera(R"({"focal_length":50,"sensor_width":36})", 1920, 1080);
  EXPECT_NEAR(c.right, 0.36f, 1e-6f);  // tan(half fov) = 18 / 50
  EXPECT_NEAR(c.top, 0.36f * 1080 / 1920, 1e-6f);
  Camera portrait = camera(R"({"focal_length":50,"sensor_width":36})", 1080, 1920);
  EXPECT_NEAR(portrait.top, 0.36f, 1e-6f);
}

TEST(Camera, SensorFitVerticalAndShift) {
  Camera c = camera(R"({"focal_length":50,"sensor_height":24,"sensor_fit":"VERTICAL","shift_x":0.1})", 1920, 1080);
  EXPECT_NEAR(c.top, 0.24f, 1e-6f);
  float half_w = 0.24f * 1920 / 1080;
  // Shift is in units of the fitted dimension (here the height, 2 * 0.24).
  EXPECT_NEAR(c.left, -half_w + 0.1f * 0.48f, 1e-5f);
}

TEST(Camera, OrthographicScaleAndRays) {
  Camera c = camera(R"({"type":"orthographic","ortho_scale":4})", 200, 100);
  EXPECT_NEAR(c.right, 2.0f, 1e-6f);
  EXPECT_NEAR(c.top, 1.0f, 1e-6f);
  Ray r = c.generate_ray({0, 0}, {0.5f, 0.5f});  // top-left corner
  EXPECT_NEAR(r.o.x, -2.0f, 1e-5f);
  EXPECT_NEAR(r.o.y, 1.0f, 1e-5f);
  EXPECT_NEAR(r.d.z, -1.0f, 1e-6f);
}

TEST(Camera, ThinLensRaysMeetOnTheFocalPlane) {
  Camera c = camera(R"({"fstop":1.4,"focal_length":50,"focus_distance":3})", 64, 64);
  EXPECT_NEAR(c.aperture_radius, 0.05f / 2.8f, 1e-6f);
  Vec3 p0, p1;
  for (int i = 0; i < 2; ++i) {
    Ray r = c.generate_ray({20.0f, 40.0f}, {i ? 0.9f : 0.1f, i ? 0.2f : 0.7f});
    float t = (-3.0f - r.o.z) / r.d.z;  // plane z = -3 (camera looks down -Z)
    (i ? p1 : p0) = r.o + r.d * t;
  }
  EXPECT_NEAR(p0.x, p1.x, 1e-4f);
  EXPECT_NEAR(p0.y, p1.y, 1e-4f);
}

TEST(Params, TransformFromTranslateRotateScale) {
  Params p(R"({"transform":{"translate":[1,2,3],"rotate":[0,0,90],"scale":2}})", "thing");
  Transform t = p.get_transform("transform", Transform());
  Vec3 x = t.point(Vec3(1, 0, 0));
  EXPECT_NEAR(x.x, 1.0f, 1e-5f);
  EXPECT_NEAR(x.y, 4.0f, 1e-5f);
  EXPECT_NEAR(x.z, 3.0f, 1e-5f);
  p.check_all_used();
}

TEST(Params, LookAtPointsMinusZAtTarget) {
  Params p(R"({"transform":{"look_at":{"from":[0,-5,0],"to":[0,0,0]}}})", "camera");
  Transform t = p.get_transform("transform", Transform());
  Vec3 forward = -t.column(2);
  EXPECT_NEAR(forward.y, 1.0f, 1e-6f);
  EXPECT_NEAR(t.column(1).z, 1.0f, 1e-6f) << "up stays +Z";
}

// Owen-scrambled Sobol: values in [0,1), and the first 2^k samples of a 2D
// dimension are stratified: every cell of a 2^k-cell elementary grid gets exactly one.
TEST(Sampler, SobolIsStratifiedAndInRange) {
  SobolSampler s(7);
  const int n = 256;
  std::vector<int> cells(16 * 16, 0);
  for (int i = 0; i < n; ++i) {
    s.start_sample(3, 5, i);
    s.get_2d();  // dimension 0 (pixel filter)
    Vec2 u = s.get_2d();
    ASSERT_GE(u.x, 0.0f);
    ASSERT_LT(u.x, 1.0f);
    ASSERT_GE(u.y, 0.0f);
    ASSERT_LT(u.y, 1.0f);
    cells[int(u.y * 16) * 16 + int(u.x * 16)]++;
  }
  for (int c : cells) EXPECT_EQ(c, 1);
}

TEST(Sampler, DependsOnPixelSeedAndIndexOnly) {
  SobolSampler a(1), b(1), c(2);
  a.start_sample(10, 20, 5);
  b.start_sample(10, 20, 5);
  c.start_sample(10, 20, 5);
  float va = a.get_1d(), vb = b.get_1d(), vc = c.get_1d();
  EXPECT_EQ(va, vb);
  EXPECT_NE(va, vc);
  a.start_sample(11, 20, 5);
  EXPECT_NE(a.get_1d(), vb);
}

// The splat buffer sums in double: MLT adds millions of splats to a pixel, and a
// float sum stops growing once a splat is below half its rounding step (2^-24 of the
// sum). One splat of 1 and then 10^6 splats of 10^-8 each: a float sum stays at 1.
TEST(Film, SplatsSumInDoublePrecision) {
  rdv::Film film(4, 4, rdv::Rect{0, 0, 4, 4});
  rdv::PixelFilter filter(1.5f);
  const rdv::Vec2 centre{2.0f, 2.0f};
  auto pixel = [&] {
    float rgba[4];
    film.read(RDV_PASS_COMBINED, 1, 1, 1, 1, true, rgba);
    return double(rgba[0]);
  };
  {
    rdv::Film::PassPublisher pass(film);
    pass.add_splat(centre, rdv::Color(1.0f), filter);
    pass.publish(1, {1.0, 1.0});
  }
  double one = pixel();
  ASSERT_GT(one, 0.0);
  {
    rdv::Film::PassPublisher pass(film);
    for (int i = 0; i < 1000000; ++i) pass.add_splat(centre, rdv::Color(1e-8f), filter);
    pass.publish(2, {1.0, 1.0});
  }
  EXPECT_NEAR(pixel() / one, 1.01, 1e-5);
}

// A render that estimates no noise keeps no half images: its film costs 128 bytes a
// pixel, not 184 (a 4K frame: 0.46 GB less), and copies none in its tiles. The halves'
// estimate itself is tested in tests/render/test_noise_target.cpp.
TEST(Film, HalvesOnlyWhenTheNoiseIsEstimated) {
  EXPECT_EQ(rdv::Film::bytes_per_pixel(true) - rdv::Film::bytes_per_pixel(false),
            sizeof(rdv::HalfSum) + sizeof(rdv::SplatSums));
  EXPECT_EQ(rdv::Film::bytes_per_pixel(false), 128u);
  rdv::Film plain(4, 4, rdv::Rect{0, 0, 4, 4}), halves(4, 4, rdv::Rect{0, 0, 4, 4}, true);
  EXPECT_FALSE(plain.has_halves());
  EXPECT_TRUE(halves.has_halves());
  rdv::PixelFilter filter(1.5f);
  for (rdv::Film *film : {&plain, &halves}) {
    rdv::FilmTile tile;
    film->take_tile(rdv::Rect{0, 0, 4, 4}, tile);
    tile.add_sample(1, 1, rdv::Color(1.0f), film->has_halves());
    tile.add_sample(1, 1, rdv::Color(3.0f), false);
    film->put_tile(tile);
    rdv::Film::PassPublisher pass(*film);
    pass.add_splat({2.0f, 2.0f}, rdv::Color(1.0f), filter, true);  // ignored without halves
    pass.publish(2, {1.0, 2.0}, film->has_halves() ? rdv::HalfSplit::CameraSamples : rdv::HalfSplit::None,
                 {1.0, 1.0});
  }
  float a[4], b[4];
  plain.read(RDV_PASS_COMBINED, 1, 1, 1, 1, true, a);
  halves.read(RDV_PASS_COMBINED, 1, 1, 1, 1, true, b);
  EXPECT_EQ(a[0], b[0]);  // the same image either way
  EXPECT_LT(plain.relative_mse_estimate(), 0);  // no estimate without halves
  EXPECT_GE(halves.relative_mse_estimate(), 0);
}

// A Metropolis camera sample's catcher-pass splat (CatcherSplat::SplitPass) counts its
// split in every pixel it reaches, as the samples of a tile integrator's pixel whose
// filter reaches a catcher split given enough of them: those pixels read the catcher's
// ratio (C - M) / S, not 1, though no first-hit ray of theirs split (the Blender shadow
// catcher scene read BDPT's 4-spp pass at the ball's edge over its shadow at any mutation
// count: block means 6% above BDPT's 2048 spp and Cycles' 4096). A copy's light-tracing
// splat (CatcherSplat::Pass) counts none. Deterministic.
TEST(Film, MetropolisCatcherSplatsCountTheirSplits) {
  for (rdv::CatcherSplat tag : {rdv::CatcherSplat::SplitPass, rdv::CatcherSplat::Pass}) {
    rdv::Film film(4, 4, rdv::Rect{0, 0, 4, 4});
    film.keep_shadow_catcher({true, true});
    rdv::PixelFilter filter(1.5f);
    rdv::FilmTile tile;  // the first-hit pass: an opaque sample a pixel, no split
    film.take_tile(rdv::Rect{0, 0, 4, 4}, tile);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        tile.add_sample(x, y, rdv::Color(0.0f), false, 0.0f);
        tile.add_shadow_catcher(x, y, rdv::CatcherSample{});
      }
    film.put_tile(tile);
    {
      rdv::Film::PassPublisher pass(film);
      pass.add_splat({2.0f, 2.0f}, rdv::Color(0.25f), filter, false, 0xff, {}, nullptr, rdv::CatcherSplat::Combined);
      pass.add_splat({2.0f, 2.0f}, rdv::Color(1.0f), filter, false, 0xff, {}, nullptr, tag);
      pass.publish(1, {1.0, 1.0});
    }
    float f[4 * 4 * 3];
    film.read(RDV_PASS_SHADOW_CATCHER, 0, 0, 4, 4, true, f);
    const bool counted = tag == rdv::CatcherSplat::SplitPass;
    for (int i = 0; i < 16; ++i)
      EXPECT_NEAR(f[3 * i], counted ? 0.25f : 1.0f, 1e-6f) << "pixel " << i << " tag " << int(tag);
  }
}

// The GGX albedo tables (bsdfs/ggx_albedo.h) are read at a coordinate from a direction; a
// degenerate direction upstream (NaN) read far outside them before clamp_unit (mlt on
// materials.json crashed, docs/reliability.md). Now NaN reads the table's first entry.
TEST(GgxAlbedo, NanCoordinatesStayInsideTheTable) {
  const float nan = std::nanf("");
  for (float e : {rdv::ggx_albedo(nan, 0.3f, false), rdv::ggx_albedo(0.5f, nan, false), rdv::ggx_albedo(nan, nan, true),
                  rdv::ggx_average_albedo(nan, false), rdv::ggx_schlick_albedo(nan, 0.3f, true)}) {
    EXPECT_TRUE(std::isfinite(e) && e >= 0 && e <= 1) << e;
  }
  float e_mu = -1, e1_mu = -1;
  rdv::ggx_albedo_rows(nan, false).at(nan, e_mu, e1_mu);
  EXPECT_TRUE(std::isfinite(e_mu) && std::isfinite(e1_mu)) << e_mu << " " << e1_mu;
  EXPECT_EQ(rdv::clamp_unit(nan), 0.0f);
  EXPECT_EQ(rdv::clamp_unit(-2.0f), 0.0f);
  EXPECT_EQ(rdv::clamp_unit(2.0f), 1.0f);
  EXPECT_EQ(rdv::clamp_unit(0.25f), 0.25f);
}

}  // namespace test_core
