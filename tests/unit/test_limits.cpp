// Hostile input (nesting 1e5 deep, 1e9-segment spheres, terabyte films and meshes)
// gets an RDV_ERROR_LIMIT naming the object, the figure and the limit: never a stack
// overflow, a hang or the OOM killer (docs/scene-format.md, Limits).
#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include "core/limits.h"
#include "core/params.h"
#include "render_helpers.h"
#include "rendezvous.h"
#include "scene_file.h"

namespace test_limits {

using rdv::test::SceneHandle;

namespace {

std::string error() { return rdv_last_error(); }
bool has(const std::string &text, const std::string &part) { return text.find(part) != std::string::npos; }

// A memory budget the tests can exceed on any machine, restored afterwards.
struct MemoryCap {
  explicit MemoryCap(const char *mb) { setenv("RDV_MEMORY_LIMIT_MB", mb, 1); }
  ~MemoryCap() { unsetenv("RDV_MEMORY_LIMIT_MB"); }
};

// n Mix shaders, each holding the next in shader1 (text: a JSON library would recurse).
std::string nested_mix(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) text += R"({"type":"mix","fac":0.5,"shader2":{"type":"diffuse"},"shader1":)";
  text += R"({"type":"diffuse","color":[0.8,0.8,0.8]})";
  text.append(size_t(n), '}');
  return text;
}

// A colour input n Math nodes deep.
std::string nested_math(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) text += R"({"node":"math","operation":"ADD","value1":)";
  text += "0.25";
  for (int i = 0; i < n; ++i) text += R"(,"value2":0.0})";
  return text;
}

const char *kSceneStart = R"({"settings": {"width": 8, "height": 8, "samples": 1},
  "camera": {"type": "perspective", "transform": {"look_at": {"from": [0, -4, 0], "to": [0, 0, 0]}}},)";

}  // namespace

TEST(Limits, JsonDepthIsMeasuredWithoutRecursion) {
  std::string arrays = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_EQ(rdv::json_text_depth(arrays), rdv::kMaxJsonDepth + 1);  // stops counting past the limit
  EXPECT_EQ(rdv::json_text_depth(arrays, 1 << 30), 100000);
  EXPECT_EQ(rdv::json_text_depth(R"({"a": "[[[{{", "b": [1, [2]]})"), 3);  // brackets in strings do not count
  EXPECT_EQ(rdv::json_text_depth(R"({"a": "\"[[", "b": 1})"), 1);          // nor after an escaped quote
  // The parser itself is iterative (nlohmann 3.11): a parsed 1e5-deep value is measured
  // and destroyed without recursion.
  nlohmann::json deep = nlohmann::json::parse(arrays);
  EXPECT_EQ(rdv::json_depth(deep), rdv::kMaxJsonDepth + 1);
  EXPECT_EQ(rdv::json_depth(nlohmann::json::parse(R"({"a": [1, {"b": []}], "c": 2})")), 4);
  try {
    rdv::Params p(arrays, "world");
    FAIL() << "1e5 nested arrays must be refused";
  } catch (const rdv::Error &e) {
    EXPECT_EQ(e.status, RDV_ERROR_LIMIT);
    EXPECT_TRUE(has(e.what(), "world")) << e.what();
    EXPECT_TRUE(has(e.what(), "1000")) << e.what();
  }
}

TEST(Limits, HundredThousandNestedMixShadersAreAnError) {
  SceneHandle sc;
  uint32_t id;
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_material(sc.s, "Deep", nested_mix(100000).c_str(), &id));
  EXPECT_TRUE(has(error(), "material 'Deep'")) << error();
  EXPECT_TRUE(has(error(), "1000 levels")) << error();
  // Within the JSON limit but past the shader one: named, with the limit.
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_material(sc.s, "Layers", nested_mix(rdv::kMaxShaderNesting + 1).c_str(), &id));
  EXPECT_TRUE(has(error(), "material 'Layers'")) << error();
  EXPECT_TRUE(has(error(), "Mix / Add shaders nest more than 256")) << error();
  EXPECT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "Fine", nested_mix(rdv::kMaxShaderNesting).c_str(), &id)) << error();
  // rdv_scene_set_material takes the same path.
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_set_material(sc.s, id, nested_mix(100000).c_str()));
}

TEST(Limits, DeepTextureGraphsAreAnError) {
  SceneHandle sc;
  uint32_t id;
  std::string params = R"({"type":"diffuse","color":)" + nested_math(rdv::kMaxTextureDepth + 1) + "}";
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_material(sc.s, "Procedural", params.c_str(), &id));
  EXPECT_TRUE(has(error(), "material 'Procedural' 'color'")) << error();
  EXPECT_TRUE(has(error(), "texture nodes nest more than 256")) << error();
  EXPECT_LT(error().size(), 300u) << "the message names the input, not every node on the way";
  params = R"({"type":"diffuse","color":)" + nested_math(rdv::kMaxTextureDepth) + "}";
  EXPECT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "Procedural", params.c_str(), &id)) << error();
}

TEST(Limits, TextureEvaluationsPerHitAreBounded) {
  // Bump nodes whose height is the next bump: 3^n height evaluations per shading point.
  auto bumps = [](int n) {
    std::string text;
    for (int i = 0; i < n; ++i) text += R"({"node":"bump","height":)";
    text += "0.5";
    text.append(size_t(n), '}');
    return R"({"type":"diffuse","normal":)" + text + "}";
  };
  SceneHandle sc;
  uint32_t id;
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_material(sc.s, "Bumpy", bumps(30).c_str(), &id));  // 3^30 = 2e14
  EXPECT_TRUE(has(error(), "material 'Bumpy' 'normal': its texture nodes would be evaluated")) << error();
  EXPECT_TRUE(has(error(), "at most 1000000")) << error();
  EXPECT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "Bumpy", bumps(11).c_str(), &id)) << error();  // 442,866 evaluations
}

TEST(Limits, NestedBumpsOverAnImageAreBounded) {
  // The hostile file's form: 30 bump nodes over a 4x4 image, whose vector (UV) is looked up
  // three times too: refused at parse time, naming the material, instead of a render without end.
  SceneHandle sc;
  std::vector<float> pixels(4 * 4 * 3, 0.5f);
  uint32_t image, id;
  ASSERT_EQ(RDV_OK, rdv_scene_add_image(sc.s, "Tiny", pixels.data(), 4, 4, 3, "Non-Color", &image)) << error();
  std::string height = R"({"node":"image","buffer":"Tiny"})";
  for (int i = 0; i < 30; ++i) height = R"({"node":"bump","height":)" + height + "}";
  std::string params = R"({"type":"diffuse","normal":)" + height + "}";
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_material(sc.s, "BumpyImage", params.c_str(), &id));
  EXPECT_TRUE(has(error(), "material 'BumpyImage' 'normal': its texture nodes would be evaluated")) << error();
}

TEST(Limits, SceneFileStopsAtALimitNamingTheObject) {
  SceneHandle sc;
  std::string doc = std::string(kSceneStart) + R"("materials": [)" + nested_mix(100000).substr(0, std::string::npos);
  doc.pop_back();  // the outermost mix gets its name
  doc += R"(, "name": "Deep"}], "meshes": [{"name": "Ball", "shape": {"type": "sphere"}, "materials": ["Deep"]}]})";
  try {
    rdv_tools::load_scene_json(doc, ".", sc.s);
    FAIL() << "a 1e5-deep material must stop the load";
  } catch (const std::runtime_error &e) {
    EXPECT_TRUE(has(e.what(), "material 'Deep' (materials[0])")) << e.what();
  }
  // Past the shader limit but within the JSON one: the engine's error stops the load
  // too (a limit is not a typo to render magenta).
  SceneHandle sc2;
  doc = std::string(kSceneStart) + R"("materials": [)" + nested_mix(300);
  doc.pop_back();
  doc += R"(, "name": "Layers"}]})";
  try {
    rdv_tools::load_scene_json(doc, ".", sc2.s);
    FAIL() << "300 nested Mix shaders must stop the load";
  } catch (const std::runtime_error &e) {
    EXPECT_TRUE(has(e.what(), "material 'Layers'")) << e.what();
  }
}

TEST(Limits, GeneratedShapesAreBounded) {
  for (const char *shape : {R"({"type": "sphere", "segments": 1000000000})", R"({"type": "sphere", "segments": 1e12})",
                            R"({"type": "disk", "segments": 1e9})"}) {
    SceneHandle sc;
    std::string doc = std::string(kSceneStart) + R"("meshes": [{"name": "Huge", "shape": )" + shape + "}]}";
    try {
      rdv_tools::load_scene_json(doc, ".", sc.s);
      FAIL() << shape << " must be refused";
    } catch (const std::runtime_error &e) {
      EXPECT_TRUE(has(e.what(), "mesh 'Huge'")) << e.what();
      EXPECT_TRUE(has(e.what(), "limited to 16777216 triangles")) << e.what();
    }
  }
  SceneHandle sc;
  std::string doc = std::string(kSceneStart) + R"("meshes": [{"name": "Ball", "shape": {"type": "sphere", "segments": "many"}}]})";
  auto loaded = rdv_tools::load_scene_json(doc, ".", sc.s);
  ASSERT_EQ(loaded.problems.size(), 1u);
  EXPECT_TRUE(has(loaded.problems[0], "mesh 'Ball'")) << loaded.problems[0];
}

TEST(Limits, SideFileCountsAreCheckedAgainstTheFile) {
  const std::string file = rdv::test::temp_path("tiny.bin");
  const std::string dir = std::filesystem::path(file).parent_path().string();
  { std::ofstream(file, std::ios::binary) << std::string(48, '\0'); }
  SceneHandle sc;
  std::string doc = std::string(kSceneStart) + R"("meshes": [{"name": "Liar", "binary": {"file": "tiny.bin",
      "num_vertices": 1000000000000, "num_triangles": 1}}]})";
  auto loaded = rdv_tools::load_scene_json(doc, dir, sc.s);
  ASSERT_EQ(loaded.problems.size(), 1u);
  EXPECT_TRUE(has(loaded.problems[0], "mesh 'Liar'")) << loaded.problems[0];
  doc = std::string(kSceneStart) + R"("meshes": [{"name": "Liar", "binary": {"file": "tiny.bin",
      "num_vertices": 1000000, "num_triangles": 1}}]})";
  loaded = rdv_tools::load_scene_json(doc, dir, sc.s);
  ASSERT_EQ(loaded.problems.size(), 1u);
  EXPECT_TRUE(has(loaded.problems[0], "side file is too short (48 bytes")) << loaded.problems[0];
}

TEST(Limits, FilmAndMetropolisMemoryIsCheckedFirst) {
  SceneHandle sc;
  ASSERT_EQ(RDV_OK, rdv_scene_set_camera(sc.s, R"({"type":"perspective"})"));
  rdv_session *session = nullptr;
  {
    MemoryCap cap("1024");
    EXPECT_EQ(RDV_ERROR_LIMIT, rdv_session_create(sc.s, R"({"width":65536,"height":65536,"samples":1})", &session));
    // 128 bytes a pixel: double sums of samples, splats, normals, albedo and mist (render
    // parts merge them); 184 with half image B's samples and splats (the noise estimate).
    EXPECT_TRUE(has(error(), "render settings: 65536x65536 film needs about 512.0 GB")) << error();
    EXPECT_EQ(RDV_ERROR_LIMIT, rdv_session_create(sc.s, R"({"width":65536,"height":65536,"samples":1,
                                                             "noise_pass":true})", &session));
    EXPECT_TRUE(has(error(), "65536x65536 film needs about 736.0 GB")) << error();
    EXPECT_TRUE(has(error(), "1.0 GB")) << error();
    EXPECT_EQ(session, nullptr);
    // Metropolis: 4096 bootstrap samples per pixel of a 4K image, 1025 depths (mmlt).
    EXPECT_EQ(RDV_ERROR_LIMIT,
              rdv_session_create(sc.s, R"({"width":3840,"height":2160,"integrator":"mmlt","mlt_bootstrap":4096,
                                            "max_bounces":1024})", &session));
    EXPECT_TRUE(has(error(), "mmlt's bootstrap (4096 per pixel)")) << error();
    EXPECT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":64,"height":64,"integrator":"mmlt"})", &session)) << error();
    rdv_session_destroy(session);
    session = nullptr;
  }
  // Sample counts: past the film's exact count, and past int.
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_session_create(sc.s, R"({"width":8,"height":8,"samples":16777217})", &session));
  EXPECT_TRUE(has(error(), "'samples' is 16777217; at most 16777216")) << error();
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_session_create(sc.s, R"({"width":8,"height":8,"samples":4294967297})", &session));
  EXPECT_TRUE(has(error(), "'samples' is 4294967297")) << error();
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_session_create(sc.s, R"({"width":-4294967295,"height":8})", &session));
  EXPECT_TRUE(has(error(), "'width'")) << error();
  // Path-space MLT's settings out of their range: refused, naming the setting.
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT,
            rdv_session_create(sc.s, R"({"width":8,"height":8,"integrator":"mlt","mlt_keep_distances":1.5})", &session));
  EXPECT_TRUE(has(error(), "'mlt_keep_distances' must be a probability in [0, 1]")) << error();
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT,
            rdv_session_create(sc.s, R"({"width":8,"height":8,"integrator":"mlt","mlt_direct_samples":-1})", &session));
  EXPECT_TRUE(has(error(), "'mlt_direct_samples' must be in 0..65536")) << error();
}

TEST(Limits, AbiBuffersAreCheckedBeforeTheyAreRead) {
  // Sizes that the caller's (tiny) arrays do not have: the check comes before any read.
  MemoryCap cap("1024");
  SceneHandle sc;
  uint32_t id;
  std::vector<float> small(64, 0.5f);
  std::vector<uint32_t> indices(64, 0);
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "M", "{}", &id));
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_mesh(sc.s, "Scan", small.data(), 4000000000u, nullptr, nullptr,
                                                indices.data(), 4000000000u, nullptr, 0, &id));
  EXPECT_TRUE(has(error(), "mesh 'Scan': 4000000000 vertices and 4000000000 triangles needs about")) << error();
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_image(sc.s, "Poster", small.data(), 65536, 4096, 4, "", &id));
  EXPECT_TRUE(has(error(), "image 'Poster': 65536x4096 texels needs about 5.3 GB")) << error();
  EXPECT_EQ(RDV_ERROR_LIMIT, rdv_scene_add_grid(sc.s, "Smoke", small.data(), 1000, 1000, 1000, &id));
  EXPECT_TRUE(has(error(), "grid 'Smoke': 1000x1000x1000 voxels")) << error();
}

TEST(Limits, ImageFileHeadersAreCheckedBeforeReading) {
  // A 300-byte file whose header claims 100000 x 100000 texels: a problem naming the
  // image (rendered magenta, as a missing file), not a 149 GB read (it crashed the CLI).
  const std::string file = rdv::test::temp_path("huge.ppm");
  { std::ofstream(file, std::ios::binary) << "P6\n100000 100000\n255\n" << std::string(300, '\x7f'); }
  for (const std::string node : {R"({"node":"image","file":")" + file + R"("})",
                                 R"({"node":"image","frame":0,"file":")" + file + R"("})"}) {
    SceneHandle sc;
    uint32_t id;
    std::string params = R"({"type":"diffuse","color":)" + node + "}";
    ASSERT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "Poster", params.c_str(), &id)) << error();
    const char *text = nullptr;
    ASSERT_EQ(RDV_OK, rdv_scene_messages(sc.s, &text));
    EXPECT_TRUE(has(text, "material 'Poster'")) << text;
    EXPECT_TRUE(has(text, "is 100000x100000 texels: reading it needs about 149.0 GB")) << text;
    EXPECT_TRUE(has(text, "magenta")) << text;
  }
}

}  // namespace test_limits
