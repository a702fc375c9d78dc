// Scene::intersect_media where an index-matched medium boundary lies in a real surface: one
// mesh holding both a floor and a box of fog whose bottom face is in the floor's plane
// (boundaries and surfaces go to separate BVHs, keeping the mesh's triangle ids), rays
// that meet the two at the same distance from either side, and a material edit that
// turns a surface into a boundary and back.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "committed_scene.h"
#include "core/ray_offset.h"
#include "media/medium_stack.h"
#include "render_helpers.h"

namespace test_boundary_hits {

using namespace rdv;
using nlohmann::json;

namespace {

// Triangles 0-1: a 4 m floor quad at z = 0 ("floor"); 2-13: a unit box standing on it
// ("fog"), its bottom face (triangles 2-3) in the floor's plane, normals outward.
json mixed_mesh_scene() {
  json positions = {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0};
  json indices = {0, 1, 2, 0, 2, 3};
  json slots = {0, 0};
  const float c[8][3] = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0},
                         {-0.5f, -0.5f, 1}, {0.5f, -0.5f, 1}, {0.5f, 0.5f, 1}, {-0.5f, 0.5f, 1}};
  for (auto &v : c) positions.insert(positions.end(), {v[0], v[1], v[2]});
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (auto &f : faces) {
    for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) indices.push_back(4 + k);
    slots.insert(slots.end(), {1, 1});
  }
  return {{"camera", {{"transform", {{"look_at", {{"from", {0, -5, 2}}, {"to", {0, 0, 0.5}}}}}}}},
          {"materials", {{{"name", "floor"}, {"type", "diffuse"}},
                         {{"name", "fog"}, {"type", "volume"}, {"volume", {{"density", 1.0}}}}}},
          {"meshes", {{{"name", "floor and fog"}, {"positions", positions}, {"indices", indices},
                       {"materials", {"floor", "fog"}}, {"material_indices", slots}}}}};
}

}  // namespace

TEST(BoundaryHits, MixedMeshKeepsTriangleIds) {
  test::CommittedScene l(mixed_mesh_scene());
  const Scene &scene = l.scene();
  SurfaceHit hit;
  CoincidentBoundary hit_boundary;
  // Down onto the floor beside the box: the floor, no boundary.
  ASSERT_TRUE(scene.intersect_media(Ray{Vec3(1.5f, 0.3f, 2), Vec3(0, 0, -1), kInf}, hit, hit_boundary));
  EXPECT_LE(hit.prim, 1u);
  EXPECT_EQ(scene.is_boundary_only(hit.material), false);
  EXPECT_EQ(hit_boundary.material, -1);
  // Sideways into the box: its +x face (triangles 8-9), a boundary.
  ASSERT_TRUE(scene.intersect_media(Ray{Vec3(2, 0.1f, 0.5f), Vec3(-1, 0, 0), kInf}, hit, hit_boundary));
  EXPECT_TRUE(hit.prim == 8 || hit.prim == 9) << hit.prim;
  EXPECT_TRUE(scene.is_boundary_only(hit.material));
  EXPECT_NEAR(hit.t, 1.5f, 1e-5f);
}

// Inside the box, straight and slanted rays down: the floor is the hit, the bottom face
// its coincident boundary; a path reflected there stays in the fog, one that went on
// through the floor would leave it. From below the floor likewise.
TEST(BoundaryHits, CoplanarBoundaryRidesOnTheFloor) {
  test::CommittedScene l(mixed_mesh_scene());
  const Scene &scene = l.scene();
  const int fog = scene.interior_medium(1);
  int checked = 0;
  for (Vec3 d : {Vec3(0, 0, -1), normalize(Vec3(0.3f, -0.2f, -1)), normalize(Vec3(-0.45f, 0.1f, -0.02f))}) {
    for (Vec3 o : {Vec3(0.1f, 0.2f, 0.5f), Vec3(-0.3f, 0.05f, 0.01f), Vec3(0.2f, -0.25f, 0.9f)}) {
      SurfaceHit hit;
      CoincidentBoundary hit_boundary;
      Ray ray{o, d, kInf};
      ASSERT_TRUE(scene.intersect_media(ray, hit, hit_boundary));
      if (hit.prim > 1) continue;  // the slanted ray left through a side face first
      ++checked;
      EXPECT_FALSE(scene.is_boundary_only(hit.material));
      EXPECT_EQ(hit_boundary.material, 1) << "ray from " << o.x << "," << o.y << "," << o.z;
      MediumStack inside = MediumStack::from({fog});
      MediumStack through = inside;
      through.cross(scene, hit, hit_boundary, d);
      EXPECT_EQ(through.current(scene), -1);
      // Reflected: the next ray starts above the floor and never meets the bottom face.
      Vec3 up = Vec3(d.x, d.y, -d.z);
      SurfaceHit next;
      CoincidentBoundary next_boundary;
      ASSERT_TRUE(scene.intersect_media(Ray{spawn_origin(hit.p, hit.ng, hit.error, up), up, kInf}, next, next_boundary));
      EXPECT_TRUE(scene.is_boundary_only(next.material));
      EXPECT_GT(next.prim, 3u);  // a side or the top, not the bottom face
    }
  }
  EXPECT_GE(checked, 6);
  SurfaceHit below;
  CoincidentBoundary below_boundary;
  ASSERT_TRUE(scene.intersect_media(Ray{Vec3(0.1f, 0.1f, -1), Vec3(0, 0, 1), kInf}, below, below_boundary));
  EXPECT_FALSE(scene.is_boundary_only(below.material));
  EXPECT_EQ(below_boundary.material, 1);
}

// A material edit that makes the floor's material a boundary (and back) moves its
// triangles between the BVHs: two coplanar boundaries are then two boundary hits, not a
// surface with a boundary on it.
TEST(BoundaryHits, MaterialEditMovesTrianglesBetweenBvhs) {
  test::CommittedScene l(mixed_mesh_scene());
  Ray down{Vec3(0.1f, 0.2f, 0.5f), Vec3(0, 0, -1), kInf};
  SurfaceHit hit;
  CoincidentBoundary hit_boundary;
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(l.handle, 0, R"({"type": "volume", "volume": {"density": 0.5}})"));
  ASSERT_EQ(RDV_OK, rdv_scene_commit(l.handle));
  ASSERT_TRUE(l.scene().intersect_media(down, hit, hit_boundary));
  EXPECT_TRUE(l.scene().is_boundary_only(hit.material));
  EXPECT_EQ(hit_boundary.material, -1);
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(l.handle, 0, R"({"type": "diffuse"})"));
  ASSERT_EQ(RDV_OK, rdv_scene_commit(l.handle));
  ASSERT_TRUE(l.scene().intersect_media(down, hit, hit_boundary));
  EXPECT_EQ(hit.material, 0u);
  EXPECT_EQ(hit_boundary.material, 1);
}

}  // namespace test_boundary_hits
