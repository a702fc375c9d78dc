// Attribute nodes of type Object / Instancer (textures/shading_point.h ObjectAttribute): each
// instance's own value, as Cycles reads it (Fac the average, Alpha the fourth component, 0
// where the object has none), kept apart from a mesh attribute and from the Instancer lookup of
// the same name; bad values refused naming the object. Deterministic.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "render_helpers.h"
#include "scene_file.h"
#include "textures/texture_graph.h"

namespace test_object_attributes {

using namespace rdv;
using nlohmann::json;

namespace {

json quad(const std::string &name, float x, const json &params) {
  json m = {{"name", name}, {"shape", {{"type", "quad"}, {"size", 1}}}, {"materials", {"tinted"}},
            {"transform", {{"translate", {x, 0, 0}}}}};
  m.update(params);
  return m;
}

Color attribute(const Scene &scene, float x, const json &node) {
  SurfaceHit hit;
  EXPECT_TRUE(scene.intersect(Ray{Vec3(x, 0, 3), {0, 0, -1}}, hit));
  const ShadingPoint sp = scene.shading_point(hit, Vec3(0, 0, -1));
  TextureGraph g;
  std::vector<std::string> w;
  return g.eval(g.parse(node, "test", w), sp);
}

}  // namespace

TEST(ObjectAttributes, EachInstanceReadsItsOwn) {
  const json doc = {
      {"camera", {{"transform", {{"look_at", {{"from", {0, -5, 3}}, {"to", {0, 0, 0}}}}}}}},
      {"materials", {{{"name", "tinted"}, {"type", "diffuse"},
                      {"color", {{"node", "attribute"}, {"name", "tint"}, {"attribute_type", "OBJECT"}}}}}},
      {"meshes",
       {quad("A", -2, {{"object_attributes", {{"tint", {0.2, 0.4, 0.9}}, {"level", 3}}},
                       {"instancer_attributes", {{"tint", {1, 0, 0, 0.5}}}}}),
        quad("B", 0, {{"object_attributes", {{"tint", {0.6, 0.3, 0.0, 0.25}}}}}),
        quad("C", 2, json::object())}}};
  rdv_scene *handle = nullptr;
  rdv_scene_create(&handle);
  rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), handle);
  ASSERT_EQ(rdv_scene_commit(handle), RDV_OK);
  const Scene &scene = *handle->scene;
  auto node = [](const char *name, const char *type, const char *output) {
    return json{{"node", "attribute"}, {"name", name}, {"attribute_type", type}, {"output", output}};
  };
  const Color a = attribute(scene, -2, node("tint", "OBJECT", "color"));
  EXPECT_FLOAT_EQ(a.x, 0.2f);
  EXPECT_FLOAT_EQ(a.z, 0.9f);
  EXPECT_FLOAT_EQ(attribute(scene, -2, node("tint", "OBJECT", "fac")).x, (0.2f + 0.4f + 0.9f) / 3.0f);
  EXPECT_FLOAT_EQ(attribute(scene, -2, node("tint", "OBJECT", "alpha")).x, 1.0f) << "three numbers: alpha 1";
  EXPECT_FLOAT_EQ(attribute(scene, -2, node("level", "OBJECT", "color")).y, 3.0f) << "a number n is (n, n, n)";
  EXPECT_FLOAT_EQ(attribute(scene, -2, node("tint", "INSTANCER", "color")).x, 1.0f) << "the instancer's own";
  EXPECT_FLOAT_EQ(attribute(scene, -2, node("tint", "INSTANCER", "alpha")).x, 0.5f);
  EXPECT_FLOAT_EQ(attribute(scene, 0, node("tint", "OBJECT", "alpha")).x, 0.25f);
  EXPECT_FLOAT_EQ(attribute(scene, 0, node("tint", "INSTANCER", "color")).x, 0.0f) << "none: 0, as Cycles";
  EXPECT_FLOAT_EQ(attribute(scene, 2, node("tint", "OBJECT", "color")).y, 0.0f);
  // A mesh attribute of that name is another thing: the mesh has none.
  EXPECT_FLOAT_EQ(attribute(scene, -2, json{{"node", "attribute"}, {"name", "tint"}}).x, 0.0f);
  // The material itself: each quad shaded with its own tint.
  SurfaceHit hit;
  ASSERT_TRUE(scene.intersect(Ray{Vec3(0, 0, 3), {0, 0, -1}}, hit));
  const Bsdf bsdf = scene.bsdf(hit, Vec3(0, 0, 1), 0);
  const Color albedo = bsdf.albedo(Vec3(0, 0, 1));
  EXPECT_NEAR(albedo.x / albedo.y, 2.0f, 1e-4f);
  rdv_scene_destroy(handle);
}

TEST(ObjectAttributes, BadValuesNameTheObject) {
  rdv_scene *handle = nullptr;
  rdv_scene_create(&handle);
  const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t tri[] = {0, 1, 2};
  uint32_t material = 0, mesh = 0, inst = 0;
  ASSERT_EQ(rdv_scene_add_material(handle, "grey", R"({"type": "diffuse"})", &material), RDV_OK);
  ASSERT_EQ(rdv_scene_add_mesh(handle, "Plate", p, 3, nullptr, nullptr, tri, 1, nullptr, 0, &mesh), RDV_OK);
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(rdv_scene_add_instance(handle, mesh, identity, &inst), RDV_OK);
  for (const char *bad : {R"({"object_attributes": {"tint": [1, 2, 3, 4, 5]}})", R"({"object_attributes": {"tint": "red"}})",
                          R"({"instancer_attributes": {"tint": []}})", R"({"object_attributes": [1]})"}) {
    EXPECT_NE(rdv_scene_set_instance_params(handle, inst, bad), RDV_OK) << bad;
    EXPECT_NE(std::string(rdv_last_error()).find("object 'Plate'"), std::string::npos) << rdv_last_error();
  }
  EXPECT_EQ(rdv_scene_set_instance_params(handle, inst, R"({"object_attributes": {"tint": 0.5}})"), RDV_OK);
  rdv_scene_destroy(handle);
}

}  // namespace test_object_attributes
