// The Camera Data node (Cycles' svm_node_camera): a point in the space of the camera at its
// frame, z along the view. Without a scene the camera sits at the origin looking down -z; in a
// scene the depth is the point's distance along the camera's view direction and the distance
// its distance from the camera, for a point a camera ray met and for one it did not (the node
// reads the point, not the ray). Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "render_helpers.h"
#include "scene_file.h"
#include "textures/texture_graph.h"

namespace test_camera_data {

using namespace rdv;
using nlohmann::json;

namespace {

Color camera_data(const char *output, const ShadingPoint &sp) {
  TextureGraph g;
  std::vector<std::string> w;
  const int n = g.parse(json{{"node", "camera_data"}, {"output", output}}, "test", w);
  return g.eval(n, sp);
}

}  // namespace

TEST(CameraData, WithoutASceneTheCameraLooksDownMinusZ) {
  ShadingPoint sp;
  sp.p = Vec3(1, 2, -4);
  const float d = std::sqrt(21.0f);
  EXPECT_NEAR(camera_data("view_z_depth", sp).x, 4.0f, 1e-6f);
  EXPECT_NEAR(camera_data("view_distance", sp).x, d, 1e-6f);
  const Color v = camera_data("view_vector", sp);
  EXPECT_NEAR(v.x, 1 / d, 1e-6f);
  EXPECT_NEAR(v.y, 2 / d, 1e-6f);
  EXPECT_NEAR(v.z, 4 / d, 1e-6f);
}

TEST(CameraData, DepthAndDistanceFromTheScenesCamera) {
  const Vec3 from(3, -5, 2), to(0, 0, 0.5f);
  json doc = {{"camera", {{"transform", {{"look_at", {{"from", {from.x, from.y, from.z}}, {"to", {to.x, to.y, to.z}},
                                                       {"up", {0, 0, 1}}}}}}}},
              {"world", {{"color", {1, 1, 1}}}},
              {"materials", {{{"name", "grey"}, {"type", "diffuse"}}}},
              {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 20}}}, {"materials", {"grey"}}}}}};
  rdv_scene *handle = nullptr;
  rdv_scene_create(&handle);
  rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), handle);
  ASSERT_EQ(rdv_scene_commit(handle), RDV_OK);
  const Scene &scene = *handle->scene;
  const Vec3 view = normalize(to - from);
  for (Vec3 target : {Vec3(0, 0, 0), Vec3(-2, 1, 0), Vec3(4, 6, 0)}) {
    // Met from above (not along a camera ray): the node reads the point alone.
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(Ray{target + Vec3(0, 0, 3), {0, 0, -1}}, hit));
    const ShadingPoint sp = scene.shading_point(hit, Vec3(0, 0, -1));
    EXPECT_NEAR(camera_data("view_z_depth", sp).x, dot(hit.p - from, view), 1e-4f);
    EXPECT_NEAR(camera_data("view_distance", sp).x, length(hit.p - from), 1e-4f);
    EXPECT_NEAR(camera_data("view_vector", sp).z, dot(normalize(hit.p - from), view), 1e-5f);
  }
  rdv_scene_destroy(handle);
}

}  // namespace test_camera_data
