// Bad input gets a clear message naming the object and the field, never a crash,
// and never NaN or Inf in a pixel.
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>
#include "render_helpers.h"
#include "rendezvous.h"

namespace test_bad_input {

using namespace rdv::test;

namespace {

std::string error() { return rdv_last_error(); }

const float kIdentity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

}  // namespace

TEST(BadInput, MalformedParameterJson) {
  SceneHandle sc;
  uint32_t id;
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_material(sc.s, "Red", "{\"type\": \"diffuse\", ", &id));
  EXPECT_NE(error().find("material 'Red'"), std::string::npos) << error();
  EXPECT_NE(error().find("malformed"), std::string::npos) << error();
}

TEST(BadInput, UnknownParameterKeyIsReported) {
  SceneHandle sc;
  uint32_t id;
  EXPECT_EQ(RDV_ERROR_UNKNOWN_PARAMETER,
            rdv_scene_add_material(sc.s, "Shiny", R"({"type":"glossy","roughnes":0.2})", &id));
  EXPECT_NE(error().find("material 'Shiny'"), std::string::npos) << error();
  EXPECT_NE(error().find("'roughnes'"), std::string::npos) << error();
  EXPECT_EQ(RDV_ERROR_UNKNOWN_PARAMETER, rdv_scene_add_light(sc.s, "Key", R"({"type":"point","wattage":5})", &id));
  EXPECT_NE(error().find("light 'Key'"), std::string::npos) << error();
  EXPECT_EQ(RDV_ERROR_UNKNOWN_PARAMETER, rdv_scene_set_camera(sc.s, R"({"fov":40})"));
  EXPECT_NE(error().find("camera"), std::string::npos) << error();
}

TEST(BadInput, WrongTypesAndRanges) {
  SceneHandle sc;
  uint32_t id;
  EXPECT_NE(RDV_OK, rdv_scene_add_material(sc.s, "M", R"({"type":"diffuse","color":"red"})", &id));
  EXPECT_NE(error().find("'color'"), std::string::npos) << error();
  EXPECT_NE(RDV_OK, rdv_scene_add_material(sc.s, "M", R"({"type":"velvet"})", &id));
  EXPECT_NE(error().find("velvet"), std::string::npos) << error();
  EXPECT_NE(RDV_OK, rdv_scene_add_light(sc.s, "L", R"({"type":"point","power":-5})", &id));
  EXPECT_NE(error().find("'power'"), std::string::npos) << error();
  EXPECT_NE(RDV_OK, rdv_scene_add_light(sc.s, "A", R"({"type":"area","size":0})", &id));
  EXPECT_NE(error().find("light 'A'"), std::string::npos) << error();
  EXPECT_NE(RDV_OK, rdv_scene_set_camera(sc.s, R"({"transform":[1,2,3]})"));
  EXPECT_NE(error().find("16"), std::string::npos) << error();
}

// Bad values inside texture nodes: an invalid-argument error naming the material, the
// node and the field (not a JSON library "internal error"); numbers that are not finite
// as the engine's float32 (1e39) are rejected the same way.
TEST(BadInput, BadTextureNodeValuesNameTheNodeAndField) {
  SceneHandle sc;
  uint32_t id;
  struct Case { const char *json, *node, *field; };
  const Case cases[] = {
      {R"({"type":"diffuse","color":{"node":"checker","vector":{"node":"mapping","location":["a",0,0]}}})", "mapping node", "'location'"},
      {R"({"type":"diffuse","color":{"node":"checker","vector":{"node":"mapping","scale":[1,2]}}})", "mapping node", "'scale'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","elements":[{"position":"x","color":[1,1,1]}]}})", "color_ramp node", "'position'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","elements":[{"position":0.5,"color":[1,"g",1]}]}})", "color_ramp node", "'color'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","elements":{"position":0.5}}})", "color_ramp node", "'elements'"},
      {R"({"type":"diffuse","normal":{"node":"normal_map","uv_map":5}})", "normal_map node", "'uv_map'"},
      {R"({"type":"diffuse","color":{"node":"noise","detail":"lots"}})", "noise node", "'detail'"},
      // Not finite as float32.
      {R"({"type":"diffuse","color":{"node":"checker","scale":1e39}})", "checker node", "'scale'"},
      {R"({"type":"diffuse","color":{"node":"math","value1":-1e39}})", "math node", "'value1'"},
      {R"({"type":"diffuse","color":{"node":"checker","color1":[1e39,0,0]}})", "checker node", "'color1'"},
      {R"({"type":"diffuse","color":{"node":"checker","vector":{"node":"mapping","rotation":[0,1e39,0]}}})", "mapping node", "'rotation'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","elements":[{"position":1e39,"color":[1,1,1]}]}})", "color_ramp node", "'position'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","elements":[{"position":0.5,"color":[1,1,1,1e39]}]}})", "color_ramp node", "'color'"},
      {R"({"type":"diffuse","color":{"node":"noise","roughness":-1e39}})", "noise node", "'roughness'"},
      {R"({"type":"diffuse","color":[1e39,0,0]})", "material 'M'", "'color'"},
      {R"({"type":"diffuse","roughness":1e39})", "material 'M'", "'roughness'"},
      {R"({"type":"glossy","eta":[1e39,1,1]})", "material 'M'", "'eta'"},
      // The Cycles 3.4 switch and the noise's dimensions take only their names.
      {R"({"type":"glossy","microfacets":"cycles"})", "material 'M'", "'microfacets'"},
      {R"({"type":"diffuse","color":{"node":"noise","dimensions":"5D"}})", "noise node", "'dimensions'"},
      // Blender's procedural textures: their enums, Magic's depth and Brick's frequencies.
      {R"({"type":"diffuse","color":{"node":"voronoi","feature":"F3"}})", "voronoi node", "'feature'"},
      {R"({"type":"diffuse","color":{"node":"voronoi","distance":"EUCLID"}})", "voronoi node", "'distance'"},
      {R"({"type":"diffuse","color":{"node":"musgrave","musgrave_type":"PERLIN"}})", "musgrave node", "'musgrave_type'"},
      {R"({"type":"diffuse","color":{"node":"wave","direction":"SPHERICAL"}})", "wave node", "'direction'"},
      {R"({"type":"diffuse","color":{"node":"magic","depth":11}})", "magic node", "'depth'"},
      {R"({"type":"diffuse","color":{"node":"magic","depth":1.5}})", "magic node", "'depth'"},
      {R"({"type":"diffuse","color":{"node":"brick","offset_frequency":0}})", "brick node", "'offset_frequency'"},
      {R"({"type":"diffuse","color":{"node":"brick","squash":"x"}})", "brick node", "'squash'"},
      {R"({"type":"diffuse","color":{"node":"white_noise","dimensions":"5D"}})", "white_noise node", "'dimensions'"},
      {R"({"type":"diffuse","color":{"node":"voronoi","randomness":1e39}})", "voronoi node", "'randomness'"},
      // Baked curves and ramps: a table of the right shape, an x range that is one.
      {R"({"type":"diffuse","color":{"node":"rgb_curves"}})", "rgb_curves node", "'table'"},
      {R"({"type":"diffuse","color":{"node":"rgb_curves","table":[[0,0,0]]}})", "rgb_curves node", "'table'"},
      {R"({"type":"diffuse","color":{"node":"rgb_curves","table":[[0,0,0],[1,1]]}})", "rgb_curves node", "'table'"},
      {R"({"type":"diffuse","color":{"node":"float_curve","table":[0,1],"min_x":1,"max_x":1}})", "float_curve node", "'max_x'"},
      {R"({"type":"diffuse","color":{"node":"float_curve","table":[0,1e39]}})", "float_curve node", "'table'"},
      {R"({"type":"diffuse","color":{"node":"color_ramp","table":[[0,0,0,1],[1,1,1,1]],"interpolation":"EASE"}})", "color_ramp node", "'table'"},
      {R"({"type":"diffuse","color":{"node":"vector_math","operation":"CURL"}})", "vector_math node", "'operation'"},
      {R"({"type":"diffuse","color":{"node":"map_range","interpolation_type":"CUBIC"}})", "map_range node", "'interpolation_type'"},
      {R"({"type":"diffuse","color":{"node":"map_range","data_type":"INT"}})", "map_range node", "'data_type'"},
  };
  for (const Case &c : cases) {
    EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_material(sc.s, "M", c.json, &id)) << c.json << "\n" << error();
    EXPECT_EQ(error().find("internal error"), std::string::npos) << c.json << "\n" << error();
    EXPECT_NE(error().find("material 'M'"), std::string::npos) << c.json << "\n" << error();
    EXPECT_NE(error().find(c.node), std::string::npos) << c.json << "\n" << error();
    EXPECT_NE(error().find(c.field), std::string::npos) << c.json << "\n" << error();
  }
  // Past double's range the JSON itself does not parse: malformed, naming the material.
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT,
            rdv_scene_add_material(sc.s, "M", R"({"type":"diffuse","color":{"node":"math","value1":1e999}})", &id));
  EXPECT_NE(error().find("material 'M'"), std::string::npos) << error();
  EXPECT_NE(error().find("malformed"), std::string::npos) << error();
  // Large but finite values stay accepted.
  EXPECT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "Big", R"({"type":"diffuse","color":{"node":"checker","scale":1e30}})", &id)) << error();
}

TEST(BadInput, NullPointersAreErrorsNotCrashes) {
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_create(nullptr));
  EXPECT_NE(RDV_OK, rdv_scene_add_material(nullptr, "x", "{}", nullptr));
  EXPECT_NE(RDV_OK, rdv_session_start(nullptr));
  EXPECT_NE(RDV_OK, rdv_session_progress(nullptr, nullptr));
  SceneHandle sc;
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh(sc.s, "m", nullptr, 3, nullptr, nullptr, nullptr, 1, nullptr, 0, nullptr));
}

TEST(BadInput, OutOfRangeIndicesRejectTheMesh) {
  SceneHandle sc;
  uint32_t mat, mesh;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "grey", R"({"type":"diffuse"})", &mat));
  float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t idx[6] = {0, 1, 2, 0, 2, 7};
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_add_mesh(sc.s, "Broken", p, 3, nullptr, nullptr, idx, 2, nullptr, mat, &mesh));
  EXPECT_NE(error().find("mesh 'Broken'"), std::string::npos) << error();
  EXPECT_NE(error().find("triangle 1"), std::string::npos) << error();
  uint32_t bad_mat[1] = {5};
  EXPECT_NE(RDV_OK, rdv_scene_add_mesh(sc.s, "BadSlot", p, 3, nullptr, nullptr, idx, 1, bad_mat, 0, &mesh));
  EXPECT_NE(error().find("material 5"), std::string::npos) << error();
}

// Object Info's instance values: a random_id outside 0 .. 2^32 - 1, a colour without its
// four numbers: an invalid-argument error naming the object and the key.
TEST(BadInput, InstanceObjectInfoValuesNameTheKey) {
  SceneHandle sc;
  uint32_t mat, mesh, inst;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "grey", R"({"type":"diffuse"})", &mat));
  float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t idx[3] = {0, 1, 2};
  ASSERT_EQ(RDV_OK, rdv_scene_add_mesh(sc.s, "Tile", p, 3, nullptr, nullptr, idx, 1, nullptr, mat, &mesh));
  const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(RDV_OK, rdv_scene_add_instance(sc.s, mesh, m, &inst));
  for (const char *bad : {R"({"random_id":-1})", R"({"random_id":4294967296})", R"({"random_id":0.5})",
                          R"({"color":[1,1,1]})", R"({"color":[1,1,1,1e39]})"}) {
    EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_set_instance_params(sc.s, inst, bad)) << bad;
    EXPECT_NE(error().find("object 'Tile'"), std::string::npos) << bad << ": " << error();
    EXPECT_TRUE(error().find("random_id") != std::string::npos || error().find("color") != std::string::npos) << error();
  }
  EXPECT_EQ(RDV_OK, rdv_scene_set_instance_params(sc.s, inst, R"({"random_id":4294967295,"color":[0.5,0.5,0.5,1]})"))
      << error();
}

// NaN / Inf vertices and zero-area triangles: those triangles are dropped with a
// warning naming the mesh; the render goes on and stays finite.
TEST(BadInput, NanAndDegenerateGeometryRendersFinite) {
  const char *scene = R"({
    "settings": {"width": 24, "height": 24, "samples": 8},
    "camera": {"transform": {"look_at": {"from": [0, -4, 1], "to": [0, 0, 0]}}},
    "world": {"color": [0.5, 0.5, 0.5]},
    "materials": [{"name": "grey", "type": "diffuse"}],
    "meshes": [
      {"name": "Poisoned", "positions": [0,0,0, 1,0,0, 0,1,0, null,0,0, 1e39,1,1],
       "indices": [0,1,2, 0,1,3, 4,1,2, 0,0,1, 0,1,1], "materials": ["grey"]},
      {"name": "Empty", "positions": [], "indices": [], "materials": ["grey"]},
      {"name": "Flat", "shape": {"type": "quad", "size": 1}, "materials": ["grey"], "transform": {"scale": [1, 1, 0]}},
      {"name": "Vanished", "shape": {"type": "quad", "size": 1}, "materials": ["grey"], "transform": {"scale": 0}}
    ],
    "lights": [{"name": "Lamp", "type": "point", "position": [0, 0, 3], "power": 100}]
  })";
  Image img = render_json(scene);
  EXPECT_TRUE(img.all_finite());
  EXPECT_EQ(img.progress.samples_dropped, 0u);
  EXPECT_NE(img.warnings.find("mesh 'Poisoned'"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("NaN or infinite"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("zero-area"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("mesh 'Empty': has no faces"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("mesh 'Vanished'"), std::string::npos) << img.warnings;
  EXPECT_GT(img.channel_mean(0), 0.0f);
}

TEST(BadInput, MalformedSceneFileAndMissingFile) {
  rdv_scene *s = nullptr;
  rdv_scene_create(&s);
  EXPECT_THROW(rdv_tools::load_scene_json("{\"camera\": ", ".", s), std::runtime_error);
  try {
    rdv_tools::load_scene_file("/nonexistent/scene.json", s);
    FAIL() << "a missing file must throw";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos) << e.what();
  }
  // A mesh whose side file is missing is left out with a message naming mesh and file.
  auto loaded = rdv_tools::load_scene_json(R"({"camera": {}, "meshes": [{"name": "Big",
      "binary": {"file": "missing.bin", "num_vertices": 3, "num_triangles": 1}}]})", "/tmp", s);
  ASSERT_EQ(loaded.problems.size(), 1u);
  EXPECT_NE(loaded.problems[0].find("mesh 'Big'"), std::string::npos) << loaded.problems[0];
  EXPECT_NE(loaded.problems[0].find("missing.bin"), std::string::npos) << loaded.problems[0];
  rdv_scene_destroy(s);
}

TEST(BadInput, BadMaterialBecomesMagentaAndRenderGoesOn) {
  const char *scene = R"({
    "settings": {"width": 8, "height": 8, "samples": 4},
    "camera": {"type": "orthographic", "ortho_scale": 0.5, "transform": {"look_at": {"from": [0, 0, 3], "to": [0, 0, 0], "up": [0, 1, 0]}}},
    "world": {"color": [1, 1, 1]},
    "materials": [{"name": "Typo", "type": "difuse"}],
    "meshes": [{"name": "Floor", "shape": {"type": "quad", "size": 4}, "materials": ["Typo"]}]
  })";
  Image img = render_json(scene);
  EXPECT_NE(img.warnings.find("material 'Typo'"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("magenta"), std::string::npos) << img.warnings;
  EXPECT_GT(img.channel_mean(0), 0.5f);
  EXPECT_LT(img.channel_mean(1), 0.05f);
}

TEST(BadInput, NoCameraIsAClearError) {
  SceneHandle sc;
  EXPECT_EQ(RDV_ERROR_STATE, rdv_scene_commit(sc.s));
  EXPECT_NE(error().find("no camera"), std::string::npos) << error();
  rdv_session *session = nullptr;
  EXPECT_NE(RDV_OK, rdv_session_create(sc.s, "{}", &session));
  EXPECT_EQ(session, nullptr);
}

TEST(BadInput, EditWhileRenderingIsRefused) {
  SceneHandle sc;
  ASSERT_EQ(RDV_OK, rdv_scene_set_camera(sc.s, "{}"));
  rdv_session *session = nullptr;
  ASSERT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":4,"height":4,"samples":1})", &session));
  uint32_t id;
  EXPECT_EQ(RDV_ERROR_STATE, rdv_scene_add_material(sc.s, "late", "{}", &id));
  rdv_session_destroy(session);
  EXPECT_EQ(RDV_OK, rdv_scene_add_material(sc.s, "late", "{}", &id));
}

// Cancel stops a render that would otherwise take very long; the film stays readable.
// (How fast it stops is a benchmark figure, not asserted here.)
TEST(Session, CancelStopsCleanly) {
  SceneHandle sc;
  rdv_tools::load_scene_file(source_path("scenes/cornell_box.json"), sc.s);
  rdv_session *session = nullptr;
  ASSERT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":64,"height":64,"samples":1000000})", &session));
  ASSERT_EQ(RDV_OK, rdv_session_start(session));
  ASSERT_EQ(RDV_OK, rdv_session_cancel(session));
  ASSERT_EQ(RDV_OK, rdv_session_wait(session));
  rdv_progress p{};
  ASSERT_EQ(RDV_OK, rdv_session_progress(session, &p));
  EXPECT_EQ(p.finished, 1);
  EXPECT_EQ(p.cancelled, 1);
  EXPECT_LT(p.samples_done, 1000000u);
  std::vector<float> px(64 * 64 * 4);
  EXPECT_EQ(RDV_OK, rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 64, 64, 1, px.data()));
  EXPECT_NE(RDV_OK, rdv_session_read_film(session, RDV_PASS_COMBINED, 60, 0, 8, 8, 1, px.data()));
  rdv_session_destroy(session);
}

TEST(Session, TimeLimitHalts) {
  SceneHandle sc;
  rdv_tools::load_scene_file(source_path("scenes/cornell_box.json"), sc.s);
  rdv_session *session = nullptr;
  ASSERT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":32,"height":32,"samples":0,"time_limit":0.3})", &session));
  rdv_session_start(session);
  rdv_session_wait(session);
  rdv_progress p{};
  rdv_session_progress(session, &p);
  EXPECT_EQ(p.finished, 1);
  EXPECT_EQ(p.cancelled, 0);
  EXPECT_EQ(p.samples_target, 0u);
  rdv_session_destroy(session);
}

TEST(Api, VersionAndSummary) {
  EXPECT_EQ(rdv_api_version(), RDV_API_VERSION);
  SceneHandle sc;
  rdv_tools::load_scene_file(source_path("scenes/cornell_box.json"), sc.s);
  ASSERT_EQ(RDV_OK, rdv_scene_commit(sc.s));
  const char *summary = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_summary(sc.s, &summary));
  std::string s = summary;
  EXPECT_NE(s.find("\"media\":\"none\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"emissive_triangles\":2"), std::string::npos) << s;
}

}  // namespace test_bad_input
