// Images from memory (rdv_scene_add_image, {"node": "image", "buffer": name}): the same
// texels as a file filter identically (Closest, Linear, footprint MIP levels, every
// extension mode; Cubic as OIIO filters the file), in the colour space given; bad
// buffers are rejected naming the image, NaN texels become 0 with a warning, a re-added
// name replaces the texels, an unknown name warns and renders magenta. Deterministic.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "rendezvous.h"
#include "textures/image_texture.h"

namespace test_image_buffers {

using namespace rdv;
using nlohmann::json;

namespace {

constexpr int kW = 8, kH = 4, kC = 4;

// Texel (x, y), y from the TOP row: smooth ramps plus a bright spot, alpha 0.25..1.
float texel(int x, int y, int c) {
  if (c == 3) return 0.25f + 0.75f * float(x) / (kW - 1);
  float v = (x + 1) / float(kW) * (c == 0 ? 1.0f : 0.5f) + y * 0.2f + (c == 2 ? 0.1f : 0.0f);
  return (x == 5 && y == 1) ? v + 0.9f : v;
}

// The texels as Blender's image.pixels: bottom row first.
std::vector<float> bottom_up() {
  std::vector<float> px(size_t(kW) * kH * kC);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < kC; ++c) px[(size_t(kH - 1 - y) * kW + x) * kC + c] = texel(x, y, c);
  return px;
}

std::string write_exr() {
  std::string path = rdv::test::temp_path("buffer_ref.exr");
  std::vector<float> px(size_t(kW) * kH * kC);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < kC; ++c) px[(size_t(y) * kW + x) * kC + c] = texel(x, y, c);
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out);
  OIIO::ImageSpec spec(kW, kH, kC, OIIO::TypeDesc::FLOAT);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  EXPECT_TRUE(out->open(path, spec)) << out->geterror();
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
  return path;
}

// An emissive quad beyond an orthographic view (each pixel filter sees only the quad):
// the image shows as it is.
json emissive_quad_scene(const json &image_node) {
  return {{"settings", {{"width", 8}, {"height", 8}, {"samples", 4}, {"threads", 1}, {"seed", 3}}},
          {"camera", {{"type", "orthographic"}, {"ortho_scale", 1.0}, {"clip_start", 0.01},
                      {"transform", {{"look_at", {{"from", {0, 0, 3}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "screen"}, {"type", "emission"}, {"color", image_node}, {"strength", 1.0}}}},
          {"meshes", {{{"name", "quad"}, {"shape", {{"type", "quad"}, {"size", 2}}}, {"materials", {"screen"}}}}}};
}

std::vector<float> solid(float r, float g, float b, int w = 2, int h = 2) {
  std::vector<float> px;
  for (int i = 0; i < w * h; ++i) px.insert(px.end(), {r, g, b, 1.0f});
  return px;
}

}  // namespace

TEST(ImageBuffers, MemoryImageFiltersExactlyLikeTheSameFile) {
  std::string path = write_exr();
  std::vector<float> px = bottom_up();
  ImageTextures &t = ImageTextures::instance();
  for (const char *cs : {"Linear", "sRGB", "Non-Color"}) {
    std::string problem;
    int file = t.load(path, cs, problem);
    ASSERT_GE(file, 0) << problem;
    int mem = t.add_pixels(px.data(), kW, kH, kC, cs, problem);
    ASSERT_TRUE(problem.empty()) << problem;
    for (TexExtension ext : {TexExtension::Repeat, TexExtension::Extend, TexExtension::Clip, TexExtension::Mirror})
      for (TexInterp interp : {TexInterp::Closest, TexInterp::Linear, TexInterp::Cubic})
        for (float fw : {0.0f, 0.3f, 0.9f})  // footprint: none, ~2.4 and ~7 texels wide
          for (float u = -0.7f; u < 1.8f; u += 0.137f)
            for (float v = -0.6f; v < 1.7f; v += 0.151f) {
              float af = 0, am = 0;
              Vec2 dx(fw, 0.0f), dy(0.0f, fw * 0.5f);
              Color cf = t.lookup(file, u, v, interp, ext, &af, dx, dy);
              Color cm = t.lookup(mem, u, v, interp, ext, &am, dx, dy);
              // Cubic: the file goes through OIIO's B-spline (and its own MIP filter
              // over a footprint), the memory image through ours.
              bool cubic = interp == TexInterp::Cubic;
              if (cubic && fw > 0) continue;
              float tol = cubic ? 2e-3f : 0.0f;
              for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(cm[c], cf[c], tol * (1 + std::fabs(cf[c])))
                    << cs << " interp " << int(interp) << " ext " << int(ext) << " fw " << fw << " at " << u << ","
                    << v << " channel " << c;
              ASSERT_NEAR(am, af, tol) << cs << " alpha";
            }
    t.release(mem);
  }
}

TEST(ImageBuffers, RendersThroughTheCAbiAndReplacesByName) {
  json scene = emissive_quad_scene({{"node", "image"}, {"buffer", "paint"}, {"interpolation", "Closest"}});
  // Added once; then added first in another colour and replaced (a paint stroke).
  for (bool replaced : {false, true}) {
    rdv::test::Image img = rdv::test::render_json_prepared(
        [&](rdv_scene *s) {
          uint32_t id = 7;
          if (replaced) {
            auto first = solid(0.9f, 0.1f, 0.1f);
            ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "paint", first.data(), 2, 2, 4, "Linear", &id));
            EXPECT_EQ(id, 0u);
          }
          auto px = solid(0.2f, 0.4f, 0.6f);
          ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "paint", px.data(), 2, 2, 4, "Linear", &id)) << rdv_last_error();
          EXPECT_EQ(id, 0u);  // re-adding a name keeps its id
        },
        scene.dump());
    ASSERT_TRUE(img.all_finite());
    EXPECT_EQ(img.warnings, "");
    EXPECT_NEAR(img.channel_mean(0), 0.2f, 1e-4) << (replaced ? "replaced" : "added once");
    EXPECT_NEAR(img.channel_mean(1), 0.4f, 1e-4);
    EXPECT_NEAR(img.channel_mean(2), 0.6f, 1e-4);
  }
  // sRGB byte-like values are converted to scene-linear as a file's are.
  rdv::test::Image srgb = rdv::test::render_json_prepared(
      [&](rdv_scene *s) {
        auto px = solid(0.5f, 0.5f, 0.5f);
        ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "paint", px.data(), 2, 2, 4, "sRGB", nullptr));
      },
      scene.dump());
  EXPECT_NEAR(srgb.channel_mean(0), 0.2140f, 2e-3);
}

TEST(ImageBuffers, MaterialsKeepTheirTexelsUntilSetAgain) {
  rdv_scene *s = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_create(&s));
  auto red = solid(1, 0, 0), blue = solid(0, 0, 1);
  ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "img", red.data(), 2, 2, 4, nullptr, nullptr));
  json params = {{"type", "emission"}, {"color", {{"node", "image"}, {"buffer", "img"}}}};
  uint32_t m = 0;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(s, "m", params.dump().c_str(), &m));
  // The replaced texels are released only when no material uses them any more.
  for (int i = 0; i < 50; ++i) {
    auto &px = i % 2 ? red : blue;
    ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "img", px.data(), 2, 2, 4, nullptr, nullptr));
    ASSERT_EQ(RDV_OK, rdv_scene_set_material(s, m, params.dump().c_str()));
  }
  int images = ImageTextures::instance().num_images();
  for (int i = 0; i < 50; ++i) {
    ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "img", blue.data(), 2, 2, 4, nullptr, nullptr));
    ASSERT_EQ(RDV_OK, rdv_scene_set_material(s, m, params.dump().c_str()));
  }
  EXPECT_LE(ImageTextures::instance().num_images(), images + 2) << "replaced images are not freed";
  rdv_scene_destroy(s);
}

TEST(ImageBuffers, BadBuffersAreRejectedNamingTheImage) {
  rdv_scene *s = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_create(&s));
  auto px = solid(0.5f, 0.5f, 0.5f);
  auto named = [&](const char *what) {
    EXPECT_NE(std::string(rdv_last_error()).find("image 'grid'"), std::string::npos) << what << ": " << rdv_last_error();
  };
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_image(s, "grid", nullptr, 2, 2, 4, nullptr, nullptr));
  named("no pixels");
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_image(s, "grid", px.data(), 0, 2, 4, nullptr, nullptr));
  named("zero width");
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_image(s, "grid", px.data(), 2, 2, 5, nullptr, nullptr));
  named("5 channels");
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_image(s, nullptr, px.data(), 2, 2, 4, nullptr, nullptr));
  rdv_scene_destroy(s);
}

TEST(ImageBuffers, NanTexelsBecomeZeroWithAWarning) {
  json scene = emissive_quad_scene({{"node", "image"}, {"buffer", "script"}, {"interpolation", "Linear"}});
  rdv::test::Image img = rdv::test::render_json_prepared(
      [&](rdv_scene *s) {
        auto px = solid(0.5f, 0.5f, 0.5f);
        px[0] = std::numeric_limits<float>::quiet_NaN();
        px[5] = std::numeric_limits<float>::infinity();
        ASSERT_EQ(RDV_OK, rdv_scene_add_image(s, "script", px.data(), 2, 2, 4, "Linear", nullptr));
      },
      scene.dump());
  ASSERT_TRUE(img.all_finite());
  EXPECT_NE(img.warnings.find("image 'script': 2 pixel values are NaN or infinite; set to 0"), std::string::npos)
      << img.warnings;
}

TEST(ImageBuffers, UnknownBufferWarnsAndRendersMagenta) {
  json scene = emissive_quad_scene({{"node", "image"}, {"buffer", "never_added"}});
  rdv::test::Image img = rdv::test::render_json(scene.dump());
  EXPECT_NE(img.warnings.find("material 'screen'"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("no image buffer 'never_added'"), std::string::npos) << img.warnings;
  EXPECT_NEAR(img.channel_mean(0), 1.0f, 1e-4);
  EXPECT_NEAR(img.channel_mean(1), 0.0f, 1e-4);
  // A file and a buffer at once is malformed.
  json both = emissive_quad_scene({{"node", "image"}, {"buffer", "x"}, {"file", "x.png"}});
  rdv::test::Image bad = rdv::test::render_json(both.dump());
  EXPECT_NE(bad.warnings.find("not both"), std::string::npos) << bad.warnings;
}

}  // namespace test_image_buffers
