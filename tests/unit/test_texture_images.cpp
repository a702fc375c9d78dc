// Image textures and texture graphs: known images written at run time (PNG 8-bit,
// TIFF 16-bit, EXR half and float, HDR, JPEG) sampled at known UVs give known values
// in each colour space of Blender's config; Blender's interpolation and extension
// modes; v = 0 at the bottom row; a missing or unreadable file gives a warning naming
// the image and renders magenta, never a crash; procedural and utility nodes; named
// mesh attributes. Deterministic (no false alarms).
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <filesystem>
#include <fstream>
#include "bsdfs/material.h"
#include "rendezvous.h"
#include "scene/mesh.h"
#include "textures/image_texture.h"
#include "render_helpers.h"
#include "textures/math_nodes.h"
#include "textures/texture_graph.h"

namespace test_texture_images {

using namespace rdv;
using rdv::test::temp_path;
using nlohmann::json;

namespace {

// A 4 x 2 image; texel (x, y) from the top row: value = (x + 1) / 8 + y * 0.5 in R,
// 1 - that in G, 0.25 in B; alpha 0.5 when asked.
std::string write_image(const std::string &name, OIIO::TypeDesc format, int channels = 3) {
  std::string path = temp_path(name);
  const int w = 4, h = 2;
  std::vector<float> px(size_t(w) * h * channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = (x + 1) / 8.0f + y * 0.5f;
      float *p = &px[(size_t(y) * w + x) * channels];
      p[0] = v;
      if (channels > 1) p[1] = 1 - v;
      if (channels > 2) p[2] = 0.25f;
      if (channels > 3) p[3] = 0.5f;
    }
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out) << path;
  OIIO::ImageSpec spec(w, h, channels, format);
  EXPECT_TRUE(out->open(path, spec)) << out->geterror();
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
  return path;
}

// Texel (x, y) (y from the top) centre in Blender's UV convention.
float tu(int x) { return (x + 0.5f) / 4.0f; }
float tv(int y) { return 1.0f - (y + 0.5f) / 2.0f; }

float texel_value(int x, int y) { return (x + 1) / 8.0f + y * 0.5f; }

Color lookup(const std::string &path, const std::string &cs, float u, float v, TexInterp interp = TexInterp::Closest,
             TexExtension ext = TexExtension::Repeat, float *alpha = nullptr) {
  std::string problem;
  int id = ImageTextures::instance().load(path, cs, problem);
  EXPECT_GE(id, 0) << problem;
  if (id < 0) return Color(-1.0f);
  return ImageTextures::instance().lookup(id, u, v, interp, ext, alpha);
}

TextureGraph graph_of(const std::string &node_json, int &node, std::vector<std::string> &warnings) {
  TextureGraph g;
  node = g.parse(json::parse(node_json), "test", warnings);
  return g;
}

// A node graph's value at a default shading point (warnings appended to w).
Color eval_at_default_point(const std::string &node_json, std::vector<std::string> &w) {
  int n;
  TextureGraph g = graph_of(node_json, n, w);
  return g.eval(n, ShadingPoint{});
}

}  // namespace

TEST(TextureImages, KnownValuesInEachFormatLinearAndNonColor) {
  struct F { const char *name; OIIO::TypeDesc fmt; float tol; };
  for (F f : {F{"a.exr", OIIO::TypeDesc::FLOAT, 1e-6f}, F{"h.exr", OIIO::TypeDesc::HALF, 1e-3f},
              F{"b.png", OIIO::TypeDesc::UINT8, 1.0f / 255}, F{"c.tif", OIIO::TypeDesc::UINT16, 1.0f / 65535},
              F{"d.hdr", OIIO::TypeDesc::FLOAT, 0.01f}}) {
    std::string path = write_image(f.name, f.fmt);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) {
        Color c = lookup(path, "Non-Color", tu(x), tv(y));
        EXPECT_NEAR(c.x, texel_value(x, y), f.tol + 1e-6f) << f.name << " texel " << x << "," << y;
        EXPECT_NEAR(c.z, 0.25f, f.tol + 1e-6f) << f.name;
      }
  }
  // JPEG is lossy: only roughly, and its default space is sRGB.
  std::string jpg = write_image("e.jpg", OIIO::TypeDesc::UINT8);
  EXPECT_NEAR(lookup(jpg, "Non-Color", tu(1), tv(0)).z, 0.25f, 0.06f);
}

TEST(TextureImages, SrgbAndOtherSpacesThroughBlendersConfig) {
  std::string png = write_image("srgb.png", OIIO::TypeDesc::UINT8);
  auto srgb = [](float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); };
  for (int x = 0; x < 4; ++x) {
    float raw = std::round(texel_value(x, 0) * 255) / 255;
    Color def = lookup(png, "", tu(x), tv(0));      // 8-bit default: sRGB
    Color exp = lookup(png, "sRGB", tu(x), tv(0));
    EXPECT_NEAR(exp.x, srgb(raw), 2e-3f) << x;   // Blender's sRGB is the standard curve
    EXPECT_NEAR(def.x, exp.x, 1e-6f);
    EXPECT_NEAR(lookup(png, "Non-Color", tu(x), tv(0)).x, raw, 1e-6f);
  }
  // Float files default to Linear (no conversion).
  std::string exr = write_image("lin.exr", OIIO::TypeDesc::FLOAT);
  EXPECT_NEAR(lookup(exr, "", tu(2), tv(1)).x, texel_value(2, 1), 1e-6f);
  // Filmic Log: whatever OCIO says, the image lookup agrees with a direct conversion
  // and is not the raw value.
  Color raw(texel_value(1, 0), 1 - texel_value(1, 0), 0.25f), conv = raw;
  ASSERT_TRUE(to_scene_linear("Filmic Log", conv));
  Color looked = lookup(exr, "Filmic Log", tu(1), tv(0));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(looked[k], conv[k], 1e-5f);
  EXPECT_GT(std::fabs(conv.x - raw.x), 1e-3f);
  Color bogus(0.5f);
  EXPECT_FALSE(to_scene_linear("No Such Space", bogus));
}

TEST(TextureImages, InterpolationExtensionAndOrientation) {
  std::string exr = write_image("modes.exr", OIIO::TypeDesc::FLOAT, 4);
  // v = 0 is the bottom row (the file's last row).
  EXPECT_NEAR(lookup(exr, "Linear", tu(0), 0.01f).x, texel_value(0, 1), 1e-6f);
  EXPECT_NEAR(lookup(exr, "Linear", tu(0), 0.99f).x, texel_value(0, 0), 1e-6f);
  // Linear: halfway between texel centres 1 and 2 of the top row.
  float mid = 0.5f * (texel_value(1, 0) + texel_value(2, 0));
  EXPECT_NEAR(lookup(exr, "Linear", 0.5f, tv(0), TexInterp::Linear).x, mid, 1e-5f);
  EXPECT_NEAR(lookup(exr, "Linear", 0.51f, tv(0), TexInterp::Closest).x, texel_value(2, 0), 1e-6f);
  // Cubic is the uniform cubic B-spline (as Cycles' Cubic): symmetric in x, and at a
  // texel centre in y it blends 1/6 of each neighbouring row (the row above clamps).
  EXPECT_NEAR(lookup(exr, "Linear", 0.5f, tv(0), TexInterp::Cubic, TexExtension::Extend).x, mid + 0.5f / 6, 1e-4f);
  // Repeat / Extend / Clip / Mirror outside [0, 1].
  EXPECT_NEAR(lookup(exr, "Linear", 1.0f + tu(1), tv(0)).x, texel_value(1, 0), 1e-6f);
  EXPECT_NEAR(lookup(exr, "Linear", 1.6f, tv(0), TexInterp::Closest, TexExtension::Extend).x, texel_value(3, 0), 1e-6f);
  float a = -1;
  Color clip = lookup(exr, "Linear", 1.6f, tv(0), TexInterp::Closest, TexExtension::Clip, &a);
  EXPECT_EQ(clip.x, 0.0f);
  EXPECT_EQ(a, 0.0f);
  lookup(exr, "Linear", tu(1), tv(0), TexInterp::Closest, TexExtension::Clip, &a);
  EXPECT_NEAR(a, 0.5f, 1e-6f) << "straight alpha from the file";
  EXPECT_NEAR(lookup(exr, "Linear", 1.0f + tu(0), tv(0), TexInterp::Closest, TexExtension::Mirror).x, texel_value(3, 0), 1e-6f);
}

TEST(TextureImages, MissingOrUnreadableFileWarnsAndRendersMagenta) {
  std::string garbage = temp_path("garbage.png");
  { std::ofstream(garbage) << "this is not a png"; }
  for (std::string file : {std::string("/nonexistent/dir/brick_wall.png"), garbage}) {
    rdv_scene *scene = nullptr;
    ASSERT_EQ(RDV_OK, rdv_scene_create(&scene));
    json mat = {{"type", "principled"},
                {"base_color", {{"node", "image"}, {"file", file}, {"name", "Bricks"}}}};
    uint32_t id;
    ASSERT_EQ(RDV_OK, rdv_scene_add_material(scene, "Wall", mat.dump().c_str(), &id)) << rdv_last_error();
    const char *messages = nullptr;
    ASSERT_EQ(RDV_OK, rdv_scene_messages(scene, &messages));
    std::string m = messages;
    EXPECT_NE(m.find("image 'Bricks'"), std::string::npos) << m;
    EXPECT_NE(m.find("magenta"), std::string::npos) << m;
    EXPECT_NE(m.find("material 'Wall'"), std::string::npos) << m;
    rdv_scene_destroy(scene);
    // The node itself evaluates to magenta.
    std::vector<std::string> w;
    int n;
    TextureGraph g = graph_of(json{{"node", "image"}, {"file", file}}.dump(), n, w);
    Color c = g.eval(n, ShadingPoint{});
    EXPECT_EQ(c.x, 1.0f);
    EXPECT_EQ(c.y, 0.0f);
    EXPECT_EQ(c.z, 1.0f);
    ASSERT_EQ(w.size(), 1u);
  }
}

TEST(TextureGraphs, ProceduralAndUtilityNodes) {
  std::vector<std::string> w;
  int n;
  ShadingPoint sp;
  // Checker (Blender's formula): scale 2 over generated (0.1, 0.1, 0.1) -> cell (0,0,0): color2.
  TextureGraph g = graph_of(R"({"node":"checker","scale":2,"color1":[1,0,0],"color2":[0,0,1]})", n, w);
  sp.generated = {0.1f, 0.1f, 0.1f};
  EXPECT_EQ(g.eval(n, sp).z, 1.0f);
  sp.generated = {0.6f, 0.1f, 0.1f};
  EXPECT_EQ(g.eval(n, sp).x, 1.0f);
  // Gradient linear along x, clamped.
  g = graph_of(R"({"node":"gradient","output":"fac"})", n, w);
  sp.generated = {0.3f, 0.9f, 0};
  EXPECT_NEAR(g.eval(n, sp).x, 0.3f, 1e-6f);
  // Math, mix, invert, ramp, hue/saturation identities.
  g = graph_of(R"({"node":"math","operation":"POWER","value1":2,"value2":3})", n, w);
  EXPECT_EQ(g.eval(n, sp).x, 8.0f);
  g = graph_of(R"({"node":"mix","blend_type":"MULTIPLY","fac":1,"color1":[0.5,0.5,0.5],"color2":[0.5,1,0]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.25f, 1e-6f);
  EXPECT_NEAR(g.eval(n, sp).z, 0.0f, 1e-6f);
  g = graph_of(R"({"node":"invert","color":[0.2,0.3,0.4]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).y, 0.7f, 1e-6f);
  g = graph_of(R"({"node":"color_ramp","fac":0.25,"elements":[{"position":0,"color":[0,0,0,1]},{"position":0.5,"color":[1,1,1,1]}]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.5f, 1e-6f);
  g = graph_of(R"({"node":"hue_saturation","color":[0.8,0.3,0.1]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.8f, 1e-5f);
  EXPECT_NEAR(g.eval(n, sp).y, 0.3f, 1e-5f);
  g = graph_of(R"({"node":"hue_saturation","color":[0.8,0.3,0.1],"saturation":0})", n, w);
  EXPECT_NEAR(g.eval(n, sp).y, 0.8f, 1e-5f);
  // Noise stays in [0, 1] and varies.
  g = graph_of(R"({"node":"noise","scale":3,"detail":4})", n, w);
  float lo = 1, hi = 0;
  for (int i = 0; i < 200; ++i) {
    sp.generated = {i * 0.0137f, i * 0.0071f, 0.3f};
    float v = g.eval(n, sp).x;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GE(lo, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(hi - lo, 0.2f);
  // A graph: image coordinates through a mapping node (Texture Coordinate -> Mapping).
  g = graph_of(R"({"node":"mapping","vector":{"node":"texture_coordinate","output":"object"},"location":[1,2,3],"scale":[2,2,2]})", n, w);
  sp.p_object = {1, 1, 1};
  Color m = g.eval(n, sp);
  EXPECT_NEAR(m.x, 3.0f, 1e-6f);
  EXPECT_NEAR(m.z, 5.0f, 1e-6f);
  EXPECT_TRUE(w.empty());
  // Malformed input is an error naming the key.
  EXPECT_THROW(graph_of(R"({"node":"checker","colour1":[1,0,0]})", n, w), Error);
  EXPECT_THROW(graph_of(R"({"node":"wood"})", n, w), Error);
}

// Blender's procedural textures (Voronoi, Musgrave, Wave, Magic, Brick, White Noise) in
// every dimension, feature and output: finite everywhere, including coordinates far beyond
// any cell (1e30) and a zero or huge scale; varying over an ordinary patch. Their patterns
// against Blender's own are in blender.brightness.procedural_textures.
TEST(TextureGraphs, ProceduralTexturesAreFiniteAndVary) {
  struct Spec { std::string json; bool varies; };  // varies: an output the node's settings fill
  std::vector<Spec> nodes;
  const json w_varies = {{"node", "texture_coordinate"}, {"output", "generated"}};  // 1D textures follow w alone
  for (const char *dims : {"1D", "2D", "3D", "4D"}) {
    const bool has_w = dims[0] == '1' || dims[0] == '4', has_position = dims[0] != '1';
    for (const std::string feature : {"F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"})
      for (const char *metric : {"EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI"})
        for (const std::string out : {"distance", "color", "position", "w", "radius"}) {
          const bool cells = feature == "F1" || feature == "F2" || feature == "SMOOTH_F1";
          const bool varies = out == "distance" ? feature != "N_SPHERE_RADIUS"
                              : out == "radius" ? feature == "N_SPHERE_RADIUS"
                              : out == "w"      ? cells && has_w
                              : out == "position" ? cells && has_position
                                                  : cells;
          nodes.push_back({json{{"node", "voronoi"}, {"dimensions", dims}, {"feature", feature}, {"distance", metric},
                                {"output", out}, {"w", w_varies}, {"exponent", 1.5}, {"smoothness", 0.7}}.dump(),
                           varies});
        }
    for (const char *type : {"MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "FBM", "HETERO_TERRAIN"})
      nodes.push_back({json{{"node", "musgrave"}, {"dimensions", dims}, {"musgrave_type", type}, {"detail", 3.5},
                            {"offset", 0.7}, {"gain", 1.3}, {"w", w_varies}}.dump(),
                       true});
    for (const char *out : {"value", "color"})
      nodes.push_back({json{{"node", "white_noise"}, {"dimensions", dims}, {"output", out},
                            {"vector", w_varies}, {"w", w_varies}}.dump(),
                       true});
  }
  for (const char *type : {"BANDS", "RINGS"})
    for (const char *direction : {"X", "Y", "Z"})
      for (const char *profile : {"SIN", "SAW", "TRI"})
        nodes.push_back({json{{"node", "wave"}, {"wave_type", type}, {"direction", direction}, {"profile", profile},
                              {"distortion", 3.0}, {"detail", 2.5}}.dump(), true});
  nodes.push_back({R"({"node":"wave","direction":"DIAGONAL"})", true});
  nodes.push_back({R"({"node":"wave","wave_type":"RINGS","direction":"SPHERICAL"})", true});
  for (int depth = 0; depth <= 10; ++depth)
    nodes.push_back({json{{"node", "magic"}, {"depth", depth}, {"distortion", 0.5 + depth * 0.4}}.dump(), true});
  nodes.push_back({R"({"node":"brick","offset":0.3,"squash":0.6,"squash_frequency":3,"mortar_smooth":0.4,"bias":-0.3})", true});
  nodes.push_back({R"({"node":"brick","output":"fac","mortar_smooth":0})", true});
  ShadingPoint sp;
  for (const Spec &spec : nodes) {
    for (float scale : {0.0f, 5.0f, 1e30f}) {
      json j = json::parse(spec.json);
      if (j["node"] != "white_noise") j["scale"] = scale;
      std::vector<std::string> w;
      int n;
      TextureGraph g = graph_of(j.dump(), n, w);
      EXPECT_TRUE(w.empty()) << spec.json;
      float lo = 1e30f, hi = -1e30f;
      for (int i = 0; i < 64; ++i) {
        sp.generated = {0.37f + i * 0.0139f, 0.61f - i * 0.0083f, 0.29f + i * 0.0047f};
        if (i == 61) sp.generated = Vec3(1e30f);
        if (i == 62) sp.generated = Vec3(-3e38f, 1e-38f, 0.0f);
        if (i == 63) sp.generated = Vec3(0.0f);
        const Color c = g.eval(n, sp);
        ASSERT_TRUE(is_finite(c)) << j.dump() << " at point " << i;
        if (i < 61) lo = std::min(lo, c.x), hi = std::max(hi, c.x);
      }
      if (scale == 5.0f) EXPECT_EQ(spec.varies, hi - lo > 1e-3f) << j.dump() << ": " << lo << " .. " << hi;
    }
  }
}

// Baked tables as Cycles looks them up (its rgb_ramp_lookup): a Color Ramp from Blender's
// evaluation, linear or constant; RGB / Vector Curves per channel over [min_x, max_x] with the
// end segments extrapolated (or held); Float Curve; the factor mixing input and curve.
TEST(TextureGraphs, CurveAndRampTablesLookUpAsCycles) {
  std::vector<std::string> w;
  int n;
  ShadingPoint sp;
  // A ramp table of 3 entries: 0 at 0, 1 at 0.5, 4 at 1 (red), alpha 1 - f.
  TextureGraph g = graph_of(R"({"node":"color_ramp","fac":0.75,"table":[[0,0,0,1],[1,0,0,0.5],[4,0,0,0]]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 2.5f, 1e-6f);
  g = graph_of(R"({"node":"color_ramp","fac":0.75,"output":"alpha","table":[[0,0,0,1],[1,0,0,0.5],[4,0,0,0]]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.25f, 1e-6f);
  g = graph_of(R"({"node":"color_ramp","fac":0.75,"interpolation":"CONSTANT","table":[[0,0,0,1],[1,0,0,0.5],[4,0,0,0]]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 1.0f, 1e-6f);
  g = graph_of(R"({"node":"color_ramp","fac":7,"table":[[0,0,0,1],[1,0,0,0.5],[4,0,0,0]]})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 4.0f, 1e-6f);  // a ramp clamps its factor
  // RGB Curves over x in [0, 2]: entries at x = 0, 1, 2; red 0, 1, 3, green 1 - x/2, blue x.
  const std::string table = R"("table":[[0,1,0],[1,0.5,1],[3,0,2]],"min_x":0,"max_x":2)";
  g = graph_of(R"({"node":"rgb_curves","color":[0.5,1,3],)" + table + "}", n, w);
  Color c = g.eval(n, sp);
  EXPECT_NEAR(c.x, 0.5f, 1e-6f);   // between 0 and 1
  EXPECT_NEAR(c.y, 0.5f, 1e-6f);   // at x = 1
  EXPECT_NEAR(c.z, 3.0f, 1e-6f);   // beyond the range: the last segment extended (2 + 1 x 1)
  g = graph_of(R"({"node":"rgb_curves","extrapolate":false,"color":[0.5,1,3],)" + table + "}", n, w);
  EXPECT_NEAR(g.eval(n, sp).z, 2.0f, 1e-6f);  // held at the end
  g = graph_of(R"({"node":"rgb_curves","fac":0.25,"color":[0.5,1,3],)" + table + "}", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.5f, 1e-6f);
  EXPECT_NEAR(g.eval(n, sp).z, 3.0f, 1e-6f);
  EXPECT_NEAR(g.eval(n, sp).y, 0.875f, 1e-6f);  // 0.75 x 1 + 0.25 x 0.5
  g = graph_of(R"({"node":"float_curve","value":-0.5,"table":[1,2,4],"min_x":0,"max_x":1})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.0f, 1e-6f);  // the first segment extended: 1 - 1 x 1
  g = graph_of(R"({"node":"float_curve","value":{"node":"math","value1":0.25,"value2":0,"operation":"ADD"},"table":[1,2,4],"min_x":0,"max_x":1})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 1.5f, 1e-6f);
  // NaN in: finite out.
  g = graph_of(R"({"node":"rgb_curves","color":{"node":"math","value1":-1,"operation":"SQRT"},)" + table + "}", n, w);
  EXPECT_TRUE(is_finite(g.eval(n, sp)));
  EXPECT_TRUE(w.empty());
}

// Vector Math and Map Range as Cycles' svm_vector_math / svm_node_map_range, values worked
// by hand; every operation finite on degenerate input (zero vectors, zero ranges, NaN).
TEST(TextureGraphs, VectorMathAndMapRangeAsCycles) {
  std::vector<std::string> w;
  auto eval = [&](const std::string &j) { return eval_at_default_point(j, w); };
  const std::string ab = R"("vector1":[0.6,-0.8,2.5],"vector2":[0,2,0.5],"vector3":[1,1,-1])";
  auto op = [&](const char *o, const char *out = "vector") {
    return eval(std::string(R"({"node":"vector_math","operation":")") + o + R"(","output":")" + out + "\"," + ab + "}");
  };
  Color c = op("CROSS_PRODUCT");
  EXPECT_NEAR(c.x, -5.4f, 1e-5f); EXPECT_NEAR(c.y, -0.3f, 1e-5f); EXPECT_NEAR(c.z, 1.2f, 1e-5f);
  c = op("REFLECT");
  EXPECT_NEAR(c.y, -0.470588f, 1e-5f); EXPECT_NEAR(c.z, 2.582353f, 1e-5f);
  c = op("WRAP");
  EXPECT_NEAR(c.x, 0.6f, 1e-5f); EXPECT_NEAR(c.y, 1.2f, 1e-5f); EXPECT_NEAR(c.z, -0.5f, 1e-5f);
  c = op("SNAP");
  EXPECT_NEAR(c.x, 0.0f, 1e-6f); EXPECT_NEAR(c.y, -2.0f, 1e-6f); EXPECT_NEAR(c.z, 2.5f, 1e-6f);
  EXPECT_NEAR(op("DISTANCE", "value").x, std::sqrt(12.2f), 1e-5f);
  EXPECT_NEAR(op("DOT_PRODUCT", "value").x, -0.35f, 1e-6f);
  EXPECT_NEAR(op("LENGTH").z, std::sqrt(7.25f), 1e-5f);  // a value on the vector output: (v, v, v)
  EXPECT_EQ(op("ADD", "value").x, 0.0f);                  // a vector operation's value output: 0
  c = op("FACEFORWARD");
  EXPECT_NEAR(c.x, -0.6f, 1e-6f);
  for (const std::string &o : kVectorMathOps) {  // zero vectors: finite (NORMALIZE, REFLECT, PROJECT, ...)
    Color z = eval(R"({"node":"vector_math","operation":")" + o + R"(","scale":0})");
    EXPECT_TRUE(is_finite(z)) << o;
  }
  // Map Range, float: linear with its clamp, stepped, smooth-step on a reversed range, a zero range.
  auto range = [&](const std::string &extra) {
    return eval(R"({"node":"map_range","from_min":0,"from_max":1,"to_min":0,"to_max":10,)" + extra + "}").x;
  };
  EXPECT_NEAR(range(R"("value":0.3)"), 3.0f, 1e-5f);
  EXPECT_NEAR(range(R"("value":1.5)"), 10.0f, 1e-5f);
  EXPECT_NEAR(range(R"("value":1.5,"clamp":false)"), 15.0f, 1e-5f);
  EXPECT_NEAR(range(R"("value":0.3,"interpolation_type":"STEPPED","steps":4)"), 2.5f, 1e-5f);
  EXPECT_NEAR(eval(R"({"node":"map_range","value":0.3,"from_min":1,"from_max":0,"interpolation_type":"SMOOTHSTEP"})").x,
              0.784f, 1e-5f);
  EXPECT_NEAR(range(R"("value":0.3,"interpolation_type":"SMOOTHERSTEP")"), 1.6308f, 1e-4f);
  EXPECT_EQ(eval(R"({"node":"map_range","value":0.3,"from_min":0.5,"from_max":0.5})").x, 0.0f);
  // Vector: per component; a zero-width component maps to to_min.
  c = eval(R"({"node":"map_range","data_type":"FLOAT_VECTOR","value":[0.3,0.5,2],"from_max":[1,0,1],"to_max":[10,10,10]})");
  EXPECT_NEAR(c.x, 3.0f, 1e-5f); EXPECT_EQ(c.y, 0.0f); EXPECT_NEAR(c.z, 10.0f, 1e-5f);
  EXPECT_TRUE(w.empty());
}

// HSV / HSL conversions as Cycles' (values by hand), their round trips, and Blackbody's
// luminance-1 colour (its values against Cycles': blender.brightness.color_nodes).
TEST(TextureGraphs, ColorSpacesAndBlackbody) {
  std::vector<std::string> w;
  auto eval = [&](const std::string &j) { return eval_at_default_point(j, w); };
  Color c = eval(R"({"node":"color_space","convert":"RGB_TO_HSV","color":[1,0.8,0.2]})");
  EXPECT_NEAR(c.x, 0.125f, 1e-6f); EXPECT_NEAR(c.y, 0.8f, 1e-6f); EXPECT_NEAR(c.z, 1.0f, 1e-6f);
  c = eval(R"({"node":"color_space","convert":"RGB_TO_HSL","color":[1,0.8,0.2]})");
  EXPECT_NEAR(c.x, 0.125f, 1e-6f); EXPECT_NEAR(c.y, 1.0f, 1e-6f); EXPECT_NEAR(c.z, 0.6f, 1e-6f);
  for (const char *mode : {"HSV", "HSL"}) {
    c = eval(std::string(R"({"node":"color_space","convert":")") + mode + R"(_TO_RGB","color":{"node":"color_space","convert":"RGB_TO_)" +
             mode + R"(","color":[0.3,0.9,0.5]}})");
    EXPECT_NEAR(c.x, 0.3f, 1e-6f) << mode; EXPECT_NEAR(c.y, 0.9f, 1e-6f) << mode; EXPECT_NEAR(c.z, 0.5f, 1e-6f) << mode;
  }
  for (float kelvin : {500.0f, 1200.0f, 6500.0f, 20000.0f}) {
    c = eval(R"({"node":"blackbody","temperature":)" + std::to_string(kelvin) + "}");
    EXPECT_TRUE(is_finite(c)) << kelvin;
    EXPECT_GE(min_component(c), 0.0f) << kelvin;
    EXPECT_NEAR(luminance(c), 1.0f, kelvin < 1000 ? 0.2f : 0.01f) << kelvin;  // negatives clipped at the red end
  }
  EXPECT_GT(eval(R"({"node":"blackbody","temperature":1200})").x, eval(R"({"node":"blackbody","temperature":1200})").z);
  EXPECT_THROW(eval(R"({"node":"color_space","convert":"RGB_TO_LAB"})"), Error);
  EXPECT_TRUE(w.empty());
}

TEST(TextureGraphs, NamedUvMapsAndVertexColours) {
  Mesh mesh;
  MeshAttribute uv2{attribute_id("UVMap.001"), "UVMap.001", 2, {0, 0, 1, 0, 0, 1}};
  MeshAttribute col{attribute_id("Col"), "Col", 4, {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0}};
  mesh.attributes = {uv2, col};
  ShadingPoint sp;
  sp.mesh = &mesh;
  sp.v[0] = 0; sp.v[1] = 1; sp.v[2] = 2;
  sp.b[0] = 0.5f; sp.b[1] = 0.25f; sp.b[2] = 0.25f;
  std::vector<std::string> w;
  int n;
  TextureGraph g = graph_of(R"({"node":"uv","layer":"UVMap.001"})", n, w);
  Color uv = g.eval(n, sp);
  EXPECT_NEAR(uv.x, 0.25f, 1e-6f);
  EXPECT_NEAR(uv.y, 0.25f, 1e-6f);
  g = graph_of(R"({"node":"vertex_color","layer":"Col"})", n, w);
  Color c = g.eval(n, sp);
  EXPECT_NEAR(c.x, 0.5f, 1e-6f);
  EXPECT_NEAR(c.y, 0.25f, 1e-6f);
  EXPECT_NEAR(c.z, 0.25f, 1e-6f);
  g = graph_of(R"({"node":"vertex_color","layer":"Col","output":"alpha"})", n, w);
  EXPECT_NEAR(g.eval(n, sp).x, 0.75f, 1e-6f);
  // An attribute the mesh lacks reads as black (as in Cycles).
  g = graph_of(R"({"node":"attribute","name":"nope"})", n, w);
  EXPECT_EQ(g.eval(n, sp).x, 0.0f);
}

TEST(TextureGraphs, MeshAttributesThroughTheCAbi) {
  rdv_scene *scene = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_create(&scene));
  uint32_t mat, mesh;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(scene, "m", R"({"type":"diffuse","color":{"node":"vertex_color","layer":"Col"}})", &mat));
  float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t idx[] = {0, 1, 2};
  ASSERT_EQ(RDV_OK, rdv_scene_add_mesh(scene, "tri", pos, 3, nullptr, nullptr, idx, 1, nullptr, mat, &mesh));
  float col[] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_EQ(RDV_OK, rdv_scene_add_mesh_attribute(scene, mesh, "Col", "color", col, 3, 3)) << rdv_last_error();
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh_attribute(scene, mesh, "Col", "color", col, 3, 2));
  EXPECT_NE(std::string(rdv_last_error()).find("vertices"), std::string::npos);
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh_attribute(scene, mesh, "UV", "uv", col, 3, 3));
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh_attribute(scene, mesh, "X", "weights", col, 3, 3));
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh_attribute(scene, 7, "Col", "color", col, 3, 3));
  rdv_scene_destroy(scene);
}

namespace {

// A w x w one-texel checker of 8-bit grey 0 / 255, written as a PNG.
std::string write_checker(const std::string &name, int w) {
  std::vector<uint8_t> px(size_t(w) * w);
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y) * w + x] = (x + y) % 2 ? 255 : 0;
  std::string path = temp_path(name);
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(w, w, 1, OIIO::TypeDesc::UINT8)));
  EXPECT_TRUE(out && out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  if (out) out->close();
  return path;
}

// The mean of unfiltered lookups of image `id` (w texels wide) over one period of the checker
// (2 x 2 texels), 64 x 64 points.
double unfiltered_mean(int id, int w) {
  const Vec2 none(0.0f, 0.0f);
  double mean = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      mean += ImageTextures::instance().lookup(id, (10 + (i + 0.5) / 32.0) / w, (20 + (j + 0.5) / 32.0) / w,
                                               TexInterp::Linear, TexExtension::Repeat, nullptr, none, none).x /
              (64.0 * 64.0);
  return mean;
}

}  // namespace

// Filtered lookups: a footprint of many texels on a one-texel checker (sRGB 0 / 255,
// i.e. linear 0 / 1) gives the mean of what unfiltered lookups see, the values
// interpolated in sRGB and then converted as Cycles converts them (0.5 would be the
// texels' own mean, 0.21 the encoded values' mean converted): a camera path's ray cone and
// a light path's unfiltered lookup see one texture. No footprint keeps the texels;
// Closest is never filtered. Cubic (its finest level through OIIO) uses the same levels: it
// averaged the sRGB values through OIIO's levels before (0.214).
// Deterministic.
TEST(TextureImages, FootprintLookupsReturnTheMipAverage) {
  const int w = 64;
  const std::string path = write_checker("checker1.png", w);
  std::string problem;
  int srgb = ImageTextures::instance().load(path, "sRGB", problem);
  int data = ImageTextures::instance().load(path, "Non-Color", problem);
  ASSERT_GE(srgb, 0) << problem;
  ASSERT_GE(data, 0) << problem;
  auto &ts = ImageTextures::instance();
  const Vec2 none(0.0f, 0.0f);
  const double unfiltered = unfiltered_mean(srgb, w);
  EXPECT_NEAR(unfiltered, 0.246, 0.002);
  for (float footprint : {4.0f, 8.0f, 16.0f, 64.0f}) {  // in texels
    Vec2 dx(footprint / w, 0.0f), dy(0.0f, footprint / w);
    for (float u : {0.13f, 0.5f, 0.77f}) {
      EXPECT_NEAR(ts.lookup(srgb, u, 0.31f, TexInterp::Linear, TexExtension::Repeat, nullptr, dx, dy).x, unfiltered,
                  0.002f)
          << footprint << " texels at u " << u;
      // Grazing: a long and a short axis.
      EXPECT_NEAR(ts.lookup(srgb, u, 0.6f, TexInterp::Linear, TexExtension::Repeat, nullptr, dx, dy * 0.1f).x,
                  unfiltered, 0.002f);
      EXPECT_NEAR(ts.lookup(data, u, 0.31f, TexInterp::Cubic, TexExtension::Repeat, nullptr, dx, dy).x, 0.5f, 0.002f)
          << "Non-Color, cubic, " << footprint << " texels";
      EXPECT_NEAR(ts.lookup(srgb, u, 0.31f, TexInterp::Cubic, TexExtension::Repeat, nullptr, dx, dy).x, unfiltered,
                  0.002f)
          << "sRGB, cubic, " << footprint << " texels";
    }
  }
  for (int x = 0; x < 4; ++x) {
    float u = (x + 0.5f) / w, v = 1.0f - 0.5f / w;  // texels (x, 0) from the top row
    float texel = (x % 2) ? 1.0f : 0.0f;
    EXPECT_NEAR(ts.lookup(srgb, u, v, TexInterp::Linear, TexExtension::Repeat, nullptr, none, none).x, texel, 1e-5f);
    Vec2 big(0.5f, 0.0f);
    EXPECT_NEAR(ts.lookup(srgb, u, v, TexInterp::Closest, TexExtension::Repeat, nullptr, big, big).x, texel, 1e-5f);
  }
}

// The same one-texel checker too large to stay resident (2112 x 2112 texels, read through
// OpenImageIO's tile cache): its footprint lookups come from its own coarse levels (the first
// of at most 1024 x 1024 texels, here 528 x 528, and a blend toward the finest below it), so
// they return the mean of unfiltered lookups, 0.2463, where OIIO's levels average the sRGB
// values (0.5, converted 0.214). Deterministic.
TEST(TextureImages, CachedImagesFootprintLookupsReturnTheMipAverage) {
  const int w = 2112;
  const std::string path = write_checker("checker_cached.png", w);
  auto &ts = ImageTextures::instance();
  const size_t resident = ts.resident_bytes();
  std::string problem;
  const int srgb = ts.load(path, "sRGB", problem);
  ASSERT_GE(srgb, 0) << problem;
  EXPECT_EQ(ts.resident_bytes(), resident) << "the image should be read through the cache";
  const double unfiltered = unfiltered_mean(srgb, w);
  EXPECT_NEAR(unfiltered, 0.246, 0.002);
  for (float footprint : {4.0f, 6.0f, 16.0f, 300.0f, 5000.0f}) {  // in texels
    const Vec2 dx(footprint / w, 0.0f), dy(0.0f, footprint / w);
    for (TexInterp interp : {TexInterp::Linear, TexInterp::Cubic})
      for (float u : {0.13f, 0.5f, 0.77f})
        EXPECT_NEAR(ts.lookup(srgb, u, 0.31f, interp, TexExtension::Repeat, nullptr, dx, dy).x, unfiltered, 0.002f)
            << footprint << " texels at u " << u << (interp == TexInterp::Cubic ? " (cubic)" : "");
  }
}

}  // namespace test_texture_images
