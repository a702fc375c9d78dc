// True displacement (scene/displacement.cpp): a grid's vertices moved by its material's
// Displacement graph, as Cycles moves them. The offset here is linear in the grid's u, so the
// moved surface is a plane whose height and slope are known exactly wherever a ray meets it:
// - object space under an instance scaled 2: the offset doubles in the world;
// - "true" rebuilds the smooth normals from the moved faces (the plane's tilt), "both" keeps
//   the mesh's (its bump is the material's surface normal);
// - a second instance of the mesh carries the same object-space displacement;
// - replacing the material with one without displacement restores the grid, and a material
//   whose offset is not finite leaves those vertices where they were, with a warning;
// - the displacement costs shading nothing: a displaced plain diffuse stays a constant material.
// At 1 m, 1 mm and 1 km scales (that one 1 km from the origin). Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "render_helpers.h"
#include "scene_file.h"

namespace test_displacement {

using namespace rdv;
using nlohmann::json;

namespace {

// An n x n grid of quads over [-1, 1]^2 at z = 0, normals +z, uv = (x + 1) / 2, (y + 1) / 2.
json grid(int n) {
  json positions = json::array(), normals = json::array(), uvs = json::array(), indices = json::array();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = double(i) / n, v = double(j) / n;
      for (double c : {2 * u - 1, 2 * v - 1, 0.0}) positions.push_back(c);
      for (double c : {0.0, 0.0, 1.0}) normals.push_back(c);
      uvs.push_back(u);
      uvs.push_back(v);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      for (int k : {a, b, c, a, c, d}) indices.push_back(k);
    }
  return {{"positions", positions}, {"normals", normals}, {"uvs", uvs}, {"indices", indices}};
}

// The material: diffuse, displaced by scale x u along the normal in `space` ("" : none).
json material(const std::string &space, const std::string &method, double scale = 0.4) {
  json m = {{"type", "diffuse"}, {"color", {0.5, 0.5, 0.5}}};
  if (space.empty()) return m;
  m["displacement"] = {{"node", "displacement"}, {"space", space}, {"midlevel", 0}, {"scale", scale},
                       {"height", {{"node", "separate_rgb"}, {"color", {{"node", "uv"}}}, {"output", "r"}}}};
  m["displacement_method"] = method;
  return m;
}

struct DisplacedGrid {
  rdv_scene *handle = nullptr;
  ~DisplacedGrid() { rdv_scene_destroy(handle); }
  const Scene &scene() const { return *handle->scene; }
  double s = 1, far = 0;  // the grid's scale / 2 and its distance from the origin in x and y
  void load(json mat, double scale = 1, double distance = 0) {
    s = scale;
    far = distance;
    mat["name"] = "ground";
    json g = grid(16);
    g["name"] = "grid";
    g["materials"] = {"ground"};
    g["transform"] = {{"translate", {far, far, 0}}, {"scale", {2 * s, 2 * s, 2 * s}}};
    json copy = g;
    copy["name"] = "grid_copy";
    copy["transform"] = {{"translate", {far + 10 * s, far, 0}}, {"scale", {2 * s, 2 * s, 2 * s}}};
    json doc = {{"camera", {{"transform", {{"look_at", {{"from", {far, far - 8 * s, 6 * s}}, {"to", {far, far, 0}},
                                                         {"up", {0, 0, 1}}}}}}}},
                {"world", {{"color", {1, 1, 1}}}},
                {"materials", {mat}},
                {"meshes", {g, copy}}};
    rdv_scene_create(&handle);
    rdv_tools::load_scene_json(doc.dump(), test::source_path("scenes"), handle);
    ASSERT_EQ(rdv_scene_commit(handle), RDV_OK);
  }
  // Where a ray straight down at (x, y) in the grid's units (scale 1 at the origin) meets the
  // surface; its height back in those units.
  SurfaceHit down_at(float x, float y) const {
    SurfaceHit hit;
    const Vec3 o(float(far + s * x), float(far + s * y), float(10 * s));
    EXPECT_TRUE(scene().intersect(Ray{o, {0, 0, -1}}, hit)) << x << " " << y;
    return hit;
  }
  float height_at(float x, float y) const { return float(down_at(x, y).p.z / s); }
};

void expect_vec(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(Displacement, TrueDisplacementMovesTheVerticesAndRebuildsTheNormals) {
  // 2 units wide at the origin, 2 mm wide, and 2 km wide 1 km from the origin.
  for (auto [scale, far] : {std::pair{1.0, 0.0}, std::pair{1e-3, 0.0}, std::pair{1e3, 1e3}}) {
    DisplacedGrid g;
    g.load(material("OBJECT", "true"), scale, far);
    // x = 2 (2u - 1) in the grid's units: u = (x / 2 + 1) / 2; height 0.4 u in object space, 0.8 u there.
    for (float x : {-1.9f, -0.77f, 0.0f, 0.31f, 1.6f})
      for (float y : {-1.3f, 0.2f, 1.85f}) {
        const float u = (x / 2 + 1) / 2;
        const SurfaceHit hit = g.down_at(x, y);
        EXPECT_NEAR(hit.p.z / scale, 0.8f * u, 2e-5f) << x << " " << y << " at scale " << scale;
        expect_vec(hit.ns, normalize(Vec3(-0.2f, 0, 1)), 1e-5f);  // dz/dx = 0.8 / 4
        // The copy 10 units along x carries the same object-space displacement.
        EXPECT_NEAR(g.height_at(x + 10, y), 0.8f * u, 2e-5f) << "at scale " << scale;
      }
  }
  DisplacedGrid g;
  g.load(material("OBJECT", "true"));
  // Only the vertices read the displacement: a plain diffuse is still resolved once.
  EXPECT_TRUE(g.scene().material(0).is_constant());
  // In world space the offset is the scale itself: half the object-space one here.
  DisplacedGrid w;
  w.load(material("WORLD", "true"));
  EXPECT_NEAR(w.down_at(0.31f, 0.2f).p.z, 0.4f * ((0.31f / 2 + 1) / 2), 2e-5f);
}

TEST(Displacement, BothKeepsTheGivenNormals) {
  DisplacedGrid g;
  g.load(material("OBJECT", "both"));
  const SurfaceHit hit = g.down_at(0.31f, 0.2f);
  EXPECT_NEAR(hit.p.z, 0.8f * ((0.31f / 2 + 1) / 2), 2e-5f);
  expect_vec(hit.ns, Vec3(0, 0, 1), 1e-6f);
}

TEST(Displacement, EditsStartFromTheGivenMesh) {
  DisplacedGrid g;
  g.load(material("OBJECT", "true"));
  const float x = 0.31f, u = (x / 2 + 1) / 2;
  // A bigger scale moves the grid from where it was given, not from where it was moved.
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(g.handle, 0, material("OBJECT", "true", 0.8).dump().c_str()));
  ASSERT_EQ(RDV_OK, rdv_scene_commit(g.handle));
  EXPECT_NEAR(g.down_at(x, 0.2f).p.z, 1.6f * u, 2e-5f);
  // Without displacement: flat again, the given normals back.
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(g.handle, 0, material("", "").dump().c_str()));
  ASSERT_EQ(RDV_OK, rdv_scene_commit(g.handle));
  const SurfaceHit flat = g.down_at(x, 0.2f);
  EXPECT_NEAR(flat.p.z, 0.0f, 1e-6f);
  expect_vec(flat.ns, Vec3(0, 0, 1), 1e-6f);
}

TEST(Displacement, OffsetsThatAreNotFiniteLeaveTheirVertices) {
  DisplacedGrid g;
  json m = material("WORLD", "true");
  // u x 1e30 x 1e30: infinite where u > 0, 0 on the first column.
  m["displacement"]["height"] = {{"node", "math"}, {"operation", "MULTIPLY"}, {"value1", m["displacement"]["height"]},
                                 {"value2", 1e30}};
  m["displacement"]["scale"] = 1e30;
  g.load(m);
  const char *messages = nullptr;
  ASSERT_EQ(RDV_OK, rdv_scene_messages(g.handle, &messages));
  EXPECT_NE(std::string(messages).find("mesh 'grid': the displacement of"), std::string::npos) << messages;
  EXPECT_NEAR(g.down_at(0.31f, 0.2f).p.z, 0.0f, 1e-6f);
}

}  // namespace test_displacement
