// Regression tests for what the fuzz targets found (tests/fuzz, docs/reliability.md):
// each input that crashed, tripped ASan / UBSan or failed with an internal error, cut
// down to its cause. Under the ASan + UBSan build (docs/reliability.md) these also show
// that the undefined behaviour is gone.
#include <gtest/gtest.h>
#include <stdexcept>
#include <string>
#include "render_helpers.h"
#include "rendezvous.h"
#include "scene_file.h"

namespace test_fuzz_findings {

using rdv::test::Image;
using rdv::test::render_json;
using rdv::test::SceneHandle;

namespace {

std::string error() { return rdv_last_error(); }
bool has(const std::string &text, const std::string &part) { return text.find(part) != std::string::npos; }

// The loader's message for a scene file, or "" when it loads.
std::string load_error(const std::string &text) {
  SceneHandle sc;
  try {
    rdv_tools::LoadedScene loaded = rdv_tools::load_scene_json(text, ".", sc.s);
    std::string problems;
    for (const std::string &p : loaded.problems) problems += p + "\n";
    return problems;
  } catch (const std::runtime_error &e) {
    return e.what();
  }
}

const char *kCamera = R"("camera": {"type": "perspective"})";

}  // namespace

// fuzz_scene_json: a value of the wrong type in the file was a JSON library exception
// ("[json.exception.type_error.306] cannot use value() with string"), not a message naming
// the object; a list that is not a list of objects was walked as if it were.
TEST(FuzzFindings, SceneFileValuesOfTheWrongTypeNameTheObject) {
  struct Case { std::string body, expected; };
  const std::string side_file = RDV_SOURCE_DIR "/scenes/cornell_box.json";  // any file that exists
  const Case cases[] = {
      {R"("materials": ["diffuse"])", "materials[0] must be a JSON object"},
      {R"("materials": 5)", "'materials' must be a list of objects"},
      {R"("materials": [{"name": 7, "type": "diffuse"}])", "materials[0]: 'name' must be a string"},
      {R"("meshes": [{"name": "Ball", "shape": {"type": "sphere", "radius": "big"}}])", "mesh 'Ball' shape: 'radius'"},
      {R"("meshes": [{"name": "Q", "shape": "quad"}])", "mesh 'Q' shape must be a JSON object"},
      {R"("meshes": [{"name": "Q", "shape": {"type": "quad", "smooth": 1}}])", "'smooth' must be true or false"},
      {R"("meshes": [{"name": "T", "positions": [0,0,0, 1,0,0, 0,1,0], "indices": [0, 1, 1e30]}])",
       "mesh 'T' 'indices' must be whole numbers"},
      {R"("meshes": [{"name": "T", "positions": [0,0,0, 1,0,0, 0,1,0], "indices": [0, 1, -2]}])",
       "mesh 'T' 'indices' must be whole numbers"},
      {R"("meshes": [{"name": "B", "binary": {"file": ")" + side_file + R"(", "num_vertices": -3}}])",
       "'num_vertices' must be a whole number"},
      {R"("meshes": [{"name": "B", "binary": {"file": ")" + side_file + R"(", "num_vertices": 1e20}}])",
       "'num_vertices' must be a whole number"},
      {R"("meshes": [{"name": "A", "shape": {"type": "quad"}, "attributes": [{"name": "Col", "components": "3"}]}])",
       "mesh 'A' attribute 'Col': 'components'"},
      {R"("meshes": [{"name": "M", "shape": {"type": "quad"}, "materials": "red"}])", "mesh 'M': 'materials' must be a list"},
      {R"("instances": [{"mesh": 3}])", "instance: 'mesh' must be a string"},
      {R"("lights": [{"name": ["Key"], "type": "point"}])", "light 0: 'name' must be a string"},
      {R"("lights": [[]])", "lights[0] must be a JSON object"},
  };
  for (const Case &c : cases) {
    std::string message = load_error("{" + std::string(kCamera) + ", " + c.body + "}");
    EXPECT_TRUE(has(message, c.expected)) << c.body << "\n  gave: " << message;
    EXPECT_FALSE(has(message, "json.exception")) << c.body << "\n  gave: " << message;
  }
}

// fuzz_abi_calls: a session's 'border' (and 'strategy') of 1e30 was converted to int
// (undefined behaviour: UBSan's float-cast-overflow); now clamped to the image first.
TEST(FuzzFindings, HugeBorderAndStrategyValuesAreClampedNotConverted) {
  SceneHandle sc;
  ASSERT_EQ(RDV_OK, rdv_scene_set_camera(sc.s, R"({"type":"perspective"})")) << error();
  rdv_session *session = nullptr;
  // The whole image: a border past its edges is cut to them.
  EXPECT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":4,"height":4,"samples":1,"border":[-1e30,-1e30,1e30,1e30]})",
                                       &session)) << error();
  rdv_session_destroy(session);
  session = nullptr;
  // Wholly outside: empty, refused naming the setting.
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT,
            rdv_session_create(sc.s, R"({"width":4,"height":4,"samples":1,"border":[1e30,0,1e30,4]})", &session));
  EXPECT_TRUE(has(error(), "'border' is empty")) << error();
  EXPECT_EQ(RDV_OK, rdv_session_create(sc.s, R"({"width":4,"height":4,"samples":1,"integrator":"bdpt",
                                                 "strategy":[1e30,1e30]})", &session)) << error();
  rdv_session_destroy(session);
}

// fuzz_abi_calls: an orthographic camera with ortho_scale 3e38 sent rays from infinite
// origins to Embree, which asserts on them (RayK::valid) and so aborted the process:
// in Blender, the artist's session. Rays Embree cannot take now meet nothing; the image
// is the world's colour, finite, with every integrator. And an instance sheared by 4.7e30
// made rays in its object space too large for Embree (the same abort, from a valid world
// ray): such instances are not rendered, with a warning naming the mesh.
TEST(FuzzFindings, RaysBeyondEmbreesRangeMissInsteadOfAborting) {
  const std::string scene = R"({
    "settings": {"width": 4, "height": 4, "samples": 2, "max_bounces": 4, "mlt_bootstrap": 4, "mlt_chains": 2},
    "camera": {"type": "orthographic", "ortho_scale": 3e38, "shift_x": -1,
               "transform": {"look_at": {"from": [0, -3.9, 1], "to": [0, 0, 1]}}},
    "world": {"color": [0.25, 0.5, 0.75]},
    "materials": [{"name": "white", "type": "diffuse"}],
    "meshes": [{"name": "floor", "shape": {"type": "quad", "size": 2}, "materials": ["white"]},
               {"name": "far", "shape": {"type": "quad", "size": 2}, "materials": ["white"],
                "transform": {"translate": [1e30, 0, 0]}},
               {"name": "sheared", "shape": {"type": "quad", "size": 2}, "materials": ["white"],
                "transform": [1000, 0, 4.74e30, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]}],
    "lights": [{"name": "lamp", "type": "point", "position": [0, 0, 1], "power": 100}]
  })";
  for (const char *integrator : {"path", "bdpt", "pssmlt"}) {
    Image img = render_json(scene, std::string(R"({"integrator":")") + integrator + "\"}");
    EXPECT_TRUE(img.all_finite()) << integrator;
    EXPECT_TRUE(has(img.warnings, "instance of mesh 'sheared': transform places it beyond the range rays reach"))
        << img.warnings;
  }
}

// fuzz_abi_calls (2026-11-30, CI): a Noise texture of scale 5e29 (in a material's shader AOV,
// a case the fuzzer had just been given) converted its lattice cell floor(x) to int (UBSan:
// undefined behaviour). Cells beyond int's range are 0 now; the image stays finite, and so do
// the AOV pass's values. Under the ASan + UBSan build this shows the conversion gone.
TEST(FuzzFindings, HugeNoiseCoordinatesAreNotConvertedToInt) {
  const std::string scene = R"({
    "settings": {"width": 4, "height": 4, "samples": 2, "max_bounces": 2, "aovs": [{"name": "n"}]},
    "camera": {"transform": {"look_at": {"from": [0, -3, 1], "to": [0, 0, 0]}}},
    "world": {"color": [0.5, 0.5, 0.5]},
    "materials": [{"name": "noisy", "type": "diffuse", "color": {"node": "noise", "scale": 5e29},
                   "aovs": {"n": {"color": {"node": "noise", "scale": -5e29, "detail": 3}}}}],
    "meshes": [{"name": "floor", "shape": {"type": "quad", "size": 2}, "materials": ["noisy"]}]
  })";
  Image img = render_json(scene, R"({"integrator": "path"})");
  EXPECT_TRUE(img.all_finite());
  ASSERT_EQ(img.shader_aovs.size(), 1u);
  for (float v : img.shader_aovs[0]) EXPECT_TRUE(std::isfinite(v));
}

// fuzz_abi_calls (2026-11-25, CI): a Checker texture at a coordinate of 9e37 converted
// floor(x) to int (UBSan: undefined behaviour). Its parity is now taken in float; UDIM tiles
// and image texels are found without converting huge or NaN coordinates either. Under the
// ASan + UBSan build (.ci/setup sanitize) this shows the conversion gone; in any build the
// image is finite and the checker shows one of its two colours.
TEST(FuzzFindings, HugeTextureCoordinatesAreNotConvertedToInt) {
  const std::string scene = R"({
    "settings": {"width": 4, "height": 4, "samples": 2, "max_bounces": 2},
    "camera": {"transform": {"look_at": {"from": [0, -3, 1], "to": [0, 0, 0]}}},
    "world": {"color": [0.5, 0.5, 0.5]},
    "materials": [{"name": "checker", "type": "diffuse",
                   "color": {"node": "checker", "scale": 9e37, "color1": [1, 0, 0], "color2": [0, 0, 1]}},
                  {"name": "tiles", "type": "diffuse",
                   "color": {"node": "image", "file": ")" + rdv::test::source_path("scenes/textures/tiles.png") + R"(",
                             "vector": {"node": "mapping", "vector": {"node": "uv"}, "scale": [3e38, 3e38, 1]}}}],
    "meshes": [{"name": "floor", "shape": {"type": "quad", "size": 2}, "materials": ["checker"]},
               {"name": "card", "shape": {"type": "quad", "size": 1}, "materials": ["tiles"],
                "transform": {"translate": [0, 0, 0.5], "rotate": [90, 0, 0]}}]
  })";
  Image img = render_json(scene, R"({"integrator": "path"})");
  EXPECT_TRUE(img.all_finite());
  EXPECT_FALSE(has(img.warnings, "tiles.png")) << img.warnings;  // the image was read
}

}  // namespace test_fuzz_findings
