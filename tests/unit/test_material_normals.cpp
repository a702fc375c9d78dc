// Shading normals from normal maps and bump, and the normal bending that keeps
// grazing views from going black (Cycles' ensure_valid_reflection). Deterministic.
#include <gtest/gtest.h>
#include "bsdfs/material.h"
#include "bsdfs/shading_normal.h"
#include "textures/texture_graph.h"

namespace test_material_normals {

using namespace rdv;
using nlohmann::json;

namespace {

ShadingPoint plane_point() {
  ShadingPoint sp;
  sp.ng = sp.ns = Vec3(0, 0, 1);
  sp.dpdu = sp.dpdu_object = Vec3(1, 0, 0);
  sp.dpdv = sp.dpdv_object = Vec3(0, 1, 0);
  sp.has_uv_frame = true;
  sp.uv = {0.3f, 0.4f};
  return sp;
}

Vec3 normal_of(const std::string &node, const ShadingPoint &sp) {
  TextureGraph g;
  std::vector<std::string> w;
  int n = g.parse(json::parse(node), "test", w);
  return g.eval_normal(n, sp);
}

void expect_vec(Vec3 a, Vec3 b, float tol = 1e-4f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(ShadingNormals, TangentSpaceNormalMap) {
  ShadingPoint sp = plane_point();
  expect_vec(normal_of(R"({"node":"normal_map","color":[0.5,0.5,1]})", sp), Vec3(0, 0, 1));
  expect_vec(normal_of(R"({"node":"normal_map","color":[1,0.5,0.5]})", sp), Vec3(1, 0, 0));  // along +u
  expect_vec(normal_of(R"({"node":"normal_map","color":[0.5,1,0.5]})", sp), Vec3(0, 1, 0));  // along +v
  Vec3 half = normal_of(R"({"node":"normal_map","color":[1,0.5,0.5],"strength":0.5})", sp);
  expect_vec(half, normalize(Vec3(0.5f, 0, 0.5f)));
  // Mirrored UVs (dpdv flipped) flip the bitangent.
  sp.dpdv = Vec3(0, -1, 0);
  expect_vec(normal_of(R"({"node":"normal_map","color":[0.5,1,0.5]})", sp), Vec3(0, -1, 0));
  // World space: the colour is the normal.
  expect_vec(normal_of(R"({"node":"normal_map","space":"WORLD","color":[0.5,1,0.5]})", sp), Vec3(0, 1, 0));
}

TEST(ShadingNormals, BumpFromAHeightRamp) {
  ShadingPoint sp = plane_point();
  // h = 0.5 u: the normal tilts against the slope: normalize(-0.5, 0, 1).
  Vec3 n = normal_of(R"({"node":"bump","height":{"node":"math","operation":"MULTIPLY","value1":{"node":"separate_rgb","color":{"node":"uv"},"output":"r"},"value2":0.5}})", sp);
  expect_vec(n, normalize(Vec3(-0.5f, 0, 1)), 2e-3f);
  Vec3 inv = normal_of(R"({"node":"bump","invert":true,"height":{"node":"math","operation":"MULTIPLY","value1":{"node":"separate_rgb","color":{"node":"uv"},"output":"r"},"value2":0.5}})", sp);
  expect_vec(inv, normalize(Vec3(0.5f, 0, 1)), 2e-3f);
  Vec3 none = normal_of(R"({"node":"bump","strength":0,"height":{"node":"uv"}})", sp);
  expect_vec(none, Vec3(0, 0, 1));
  // Chained: bump on top of a normal map.
  Vec3 chained = normal_of(R"({"node":"bump","height":0.3,"normal":{"node":"normal_map","color":[1,0.5,0.5]}})", sp);
  expect_vec(chained, Vec3(1, 0, 0));
}

Vec3 vector_of(const std::string &node, const ShadingPoint &sp) {
  TextureGraph g;
  std::vector<std::string> w;
  int n = g.parse(json::parse(node), "test", w);
  return g.eval(n, sp);
}

// Blender's Displacement node as Cycles' svm_node_displacement: (height - midlevel) x scale
// along the normal in the world, or in object space carried back (the object's scale applies).
TEST(ShadingNormals, DisplacementIsAnOffsetAlongTheNormal) {
  ShadingPoint sp = plane_point();
  const char *world = R"({"node":"displacement","space":"WORLD","height":0.8,"midlevel":0.5,"scale":2})";
  const char *object = R"({"node":"displacement","height":0.8,"midlevel":0.5,"scale":2})";
  expect_vec(vector_of(world, sp), Vec3(0, 0, 0.6f));
  expect_vec(vector_of(object, sp), Vec3(0, 0, 0.6f));  // no transform: object space is the world
  // Object scaled (1, 1, 3) with a normal tilted in x-z: n_o = normalize(M^T n), offset M n_o k.
  const float M[12] = {1, 0, 0, 5, 0, 1, 0, -2, 0, 0, 3, 7};
  std::copy(M, M + 12, sp.object_to_world);
  sp.has_object_to_world = true;
  sp.ns = normalize(Vec3(1, 0, 1));
  const Vec3 n_o = normalize(Vec3(sp.ns.x, sp.ns.y, 3 * sp.ns.z));
  expect_vec(vector_of(object, sp), Vec3(n_o.x, n_o.y, 3 * n_o.z) * 0.6f);
  expect_vec(vector_of(world, sp), sp.ns * 0.6f);
  // Vector Displacement: tangent space reads x along the tangent, y the normal, z the
  // bitangent (Blender's maps; here no tangent attribute: dp/du's direction, object space).
  ShadingPoint flat = plane_point();
  const char *vec = R"({"node":"vector_displacement","vector":[0.8,1.0,0.7],"midlevel":0.5,"scale":2,"space":")";
  expect_vec(vector_of(std::string(vec) + R"(TANGENT"})", flat), Vec3(0.6f, 0.4f, 1.0f));
  expect_vec(vector_of(std::string(vec) + R"(WORLD"})", flat), Vec3(0.6f, 1.0f, 0.4f));
  std::copy(M, M + 12, flat.object_to_world);
  flat.has_object_to_world = true;
  expect_vec(vector_of(std::string(vec) + R"(OBJECT"})", flat), Vec3(0.6f, 1.0f, 1.2f));
  // A linked normal replaces the shading normal.
  expect_vec(vector_of(R"({"node":"displacement","space":"WORLD","height":1,"midlevel":0,"normal":[0,1,0]})", sp),
             Vec3(0, 1, 0));
}

// The Material Output's Displacement as the add-on lowers it (Cycles' Bump Only): a bump of
// height offset . normal. A height of 0.5 u in world space tilts the normal as BumpFromAHeightRamp;
// in object space under a uniform scale of 2 the offset doubles, and so does the slope.
TEST(ShadingNormals, BumpFromADisplacement) {
  ShadingPoint sp = plane_point();
  auto bump = [](const char *space) {
    return std::string(R"({"node":"bump","height":{"node":"vector_math","operation":"DOT_PRODUCT","output":"value",)"
                       R"("vector2":{"node":"texture_coordinate","output":"normal"},"vector1":{"node":"displacement",)"
                       R"("midlevel":0,"space":")") + space +
           R"(","height":{"node":"math","operation":"MULTIPLY","value1":{"node":"separate_rgb","color":{"node":"uv"},"output":"r"},"value2":0.5}}}})";
  };
  expect_vec(normal_of(bump("WORLD"), sp), normalize(Vec3(-0.5f, 0, 1)), 2e-3f);
  const float M[12] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0};
  std::copy(M, M + 12, sp.object_to_world);
  sp.has_object_to_world = true;
  expect_vec(normal_of(bump("OBJECT"), sp), normalize(Vec3(-1, 0, 1)), 2e-3f);
  expect_vec(normal_of(bump("WORLD"), sp), normalize(Vec3(-0.5f, 0, 1)), 2e-3f);
  // Displacement and Bump: Cycles takes the bump's differences in object space, the heights
  // still world units, so under a scale of 2 the same heights tilt the normal twice as much.
  sp.dpdu_object = Vec3(0.5f, 0, 0);
  sp.dpdv_object = Vec3(0, 0.5f, 0);
  const char *world_ramp = R"({"node":"bump","space":"OBJECT","height":{"node":"math","operation":"MULTIPLY",)"
                           R"("value1":{"node":"separate_rgb","color":{"node":"uv"},"output":"r"},"value2":0.5}})";
  expect_vec(normal_of(world_ramp, sp), normalize(Vec3(-1, 0, 1)), 2e-3f);
}

TEST(ShadingNormals, BendingKeepsReflectionAboveTheSurface) {
  Vec3 ng(0, 0, 1);
  for (float tilt : {0.3f, 0.8f, 1.2f, 1.5f})
    for (float view : {0.02f, 0.1f, 0.5f, 1.2f}) {
      Vec3 n(std::sin(tilt), 0, std::cos(tilt));
      Vec3 wo(-std::cos(view), 0.1f, std::sin(view));
      wo = normalize(wo);
      Vec3 b = ensure_valid_reflection(ng, wo, n);
      EXPECT_NEAR(length(b), 1.0f, 1e-4f);
      Vec3 r = b * (2 * dot(b, wo)) - wo;
      EXPECT_GE(dot(r, ng), std::min(0.9f * dot(ng, wo), 0.01f) - 1e-3f) << tilt << " " << view;
    }
  // A normal that is already fine is left alone.
  Vec3 n = normalize(Vec3(0.1f, 0, 1));
  expect_vec(ensure_valid_reflection(Vec3(0, 0, 1), normalize(Vec3(0.3f, 0, 1)), n), n, 0);
}

TEST(ShadingNormals, MaterialUsesTheMappedNormalWithoutLeaking) {
  Params p(R"({"type":"diffuse","color":[1,1,1],"normal":{"node":"normal_map","color":[0.9,0.5,0.6]}})", "material 'n'");
  Material m = Material::from_params(p, "n");
  ShadingPoint sp = plane_point();
  Vec3 wo = normalize(Vec3(0.2f, 0.1f, 1));
  Bsdf bsdf = m.make_bsdf(sp, wo);
  EXPECT_GT(bsdf.shading_normal(wo).x, 0.3f) << "tilted toward +u";
  // Light from below the geometric surface never arrives, whatever the shading normal.
  EXPECT_TRUE(is_black(bsdf.eval(wo, normalize(Vec3(0.9f, 0, -0.1f)), TransportMode::Radiance)));
  EXPECT_TRUE(is_black(bsdf.eval(wo, normalize(Vec3(0.9f, 0, -0.1f)), TransportMode::Importance)));
  // A grazing view across the tilt still reflects (no black terminator).
  Vec3 grazing = normalize(Vec3(-1, 0, 0.05f));
  Bsdf g = m.make_bsdf(sp, grazing);
  EXPECT_GT(dot(g.shading_normal(grazing), grazing), 0.0f);
  EXPECT_FALSE(is_black(g.eval(grazing, normalize(Vec3(0.3f, 0.2f, 1)), TransportMode::Radiance)));
}

// A Bsdf evaluates a pair of directions the same whichever direction it was built toward
// (Bsdf::frame_toward): f by the frame its camera-side direction sees (Radiance: wo,
// Importance: wi), each density by the frame of the direction sampled from. BDPT builds a
// light vertex's BSDF toward the light and a camera vertex's toward the camera; before,
// the shading normal's fallback to the geometric one (a direction facing away from a tilted
// shading normal, at smooth-shaded silhouettes) followed the direction built toward, so
// light tracing there saw another surface than path tracing (0.8% dark on a sphere lit
// from below). Diffuse (the Lambert fast path), a glossy lobe and Principled's mixture;
// directions on both sides of the tilted normal's horizon. Normal-mapped materials (a
// strong tilt, which ensure_valid_reflection bends for most of these directions): before
// the bend was made per direction (Bsdf::bend_for_each_viewer), each Bsdf bent it toward
// the direction it was built toward: 1,046 failures here.
TEST(ShadingNormals, EvaluationDoesNotDependOnTheDirectionBuiltToward) {
  const Vec3 ng(0, 0, 1), ns = normalize(Vec3(0.3f, 0, 1));
  const std::vector<Vec3> dirs = {normalize(Vec3(-1, 0, 0.1f)),  normalize(Vec3(-1, 0.3f, 0.25f)),
                                  normalize(Vec3(0.2f, 0.1f, 1)), normalize(Vec3(0.9f, -0.2f, 0.3f)),
                                  normalize(Vec3(-0.4f, 0.8f, 0.2f)), normalize(Vec3(-0.95f, -0.1f, 0.05f))};
  int band = 0;
  for (Vec3 w : dirs) band += dot(w, ns) <= 1e-4f ? 1 : 0;
  ASSERT_GE(band, 2);  // past the shading normal's horizon, above the geometric one
  const ShadingPoint mapped_point = plane_point();
  for (const char *material :
       {R"({"type":"diffuse","color":[0.8,0.8,0.8]})", R"({"type":"glossy","color":[0.8,0.8,0.8],"roughness":0.4})",
        R"({"type":"principled","base_color":[0.8,0.8,0.8],"roughness":0.3})",
        R"({"type":"diffuse","color":[0.8,0.8,0.8],"normal":{"node":"normal_map","color":[0.95,0.55,0.6]}})",
        R"({"type":"glossy","color":[0.8,0.8,0.8],"roughness":0.4,"normal":{"node":"normal_map","color":[0.95,0.55,0.6]}})",
        R"({"type":"principled","base_color":[0.8,0.8,0.8],"roughness":0.3,"anisotropic":0.6,)"
        R"("normal":{"node":"normal_map","color":[0.95,0.55,0.6]}})"}) {
    Params p(material, "material 'm'");
    Material m = Material::from_params(p, "m");
    const bool mapped = std::string(material).find("normal_map") != std::string::npos;
    auto build = [&](Vec3 w) { return mapped ? m.make_bsdf(mapped_point, w) : m.make_bsdf(ng, ns, w); };
    int nonzero = 0, bent = 0;
    for (Vec3 a : dirs)
      for (Vec3 b : dirs) {
        const Bsdf from_a = build(a), from_b = build(b);
        const Vec3 na = from_a.shading_normal(a), nb = from_a.shading_normal(b);
        bent += na.x == nb.x && na.y == nb.y && na.z == nb.z ? 0 : 1;
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
          const Color fa = from_a.f(a, b, mode), fb = from_b.f(a, b, mode);
          EXPECT_EQ(fa.x, fb.x) << material << " f, a " << a.x << " b " << b.x;
          const Color ea = from_a.eval(b, a, mode), eb = from_b.eval(b, a, mode);
          EXPECT_EQ(ea.x, eb.x) << material << " eval";
          float fwd_a, rev_a, fwd_b, rev_b;
          const Color ca = from_a.f_and_pdfs(a, b, mode, fwd_a, rev_a), cb = from_b.f_and_pdfs(a, b, mode, fwd_b, rev_b);
          EXPECT_EQ(ca.x, cb.x) << material;
          EXPECT_EQ(fwd_a, fwd_b) << material;
          EXPECT_EQ(rev_a, rev_b) << material;
          nonzero += !is_black(fa) ? 1 : 0;
        }
        EXPECT_EQ(from_a.pdf(a, b), from_b.pdf(a, b)) << material;
        EXPECT_EQ(from_a.pdf(b, a), from_b.pdf(b, a)) << material;
      }
    EXPECT_GT(nonzero, 30) << material;
    EXPECT_GT(bent, 10) << material << ": the directions see different frames";
  }
}

// Cycles darkens diffuse closures whose normal a map moved (kernel/closure/bsdf.h,
// bump_shadowing_term): f x s(g), g = cos(N0, I) / (cos(N, I) cos(N0, N)), s(g) = g + g^2 (1 - g)
// on [0, 1], N0 the mesh's normal, N the map's, I the light side (wi on camera paths, wo on
// light paths, so both evaluate one f). Written out here against a Diffuse BSDF under a world
// normal map, both modes (Importance with the shading normal's adjoint correction). Without it
// a noise-bumped diffuse floor (sun at 30 degrees) had 1.26x the contrast of Cycles' image,
// now 1.00x (README). Deterministic.
TEST(ShadingNormals, DiffuseUnderAMapIsShadowedAsCycles) {
  const Vec3 n = normalize(Vec3(0.35f, -0.2f, 0.9f)), n0(0, 0, 1);
  const std::string map = R"({"node":"normal_map","space":"WORLD","color":[)" + std::to_string(0.5f + 0.5f * n.x) + "," +
                          std::to_string(0.5f + 0.5f * n.y) + "," + std::to_string(0.5f + 0.5f * n.z) + "]}";
  Params p(R"({"type":"diffuse","color":[1,1,1],"normal":)" + map + "}", "material 'm'");
  const Material m = Material::from_params(p, "m");
  auto shadowing = [&](Vec3 light) {
    const double g = double(dot(n0, light)) / (double(dot(n, light)) * dot(n0, n));
    return g >= 1 ? 1.0 : g <= 0 ? 0.0 : g + g * g * (1 - g);
  };
  const Vec3 wo = normalize(Vec3(-0.2f, 0.3f, 1.0f));
  const Bsdf camera_side = m.make_bsdf(plane_point(), wo);
  int shadowed = 0;
  for (Vec3 wi : {normalize(Vec3(0.6f, -0.3f, 0.5f)), normalize(Vec3(-0.7f, 0.4f, 0.3f)), normalize(Vec3(0.1f, 0.9f, 0.4f)),
                  normalize(Vec3(-0.9f, -0.1f, 0.15f))}) {
    const double s = shadowing(wi);
    if (s < 0.999) ++shadowed;
    const double radiance = std::max(0.0, double(dot(n, wi))) / kPi * s;
    EXPECT_NEAR(camera_side.eval(wo, wi, TransportMode::Radiance).x, radiance, 1e-5 * std::max(1.0, radiance))
        << "wi.z " << wi.z;
    // A light path arriving from wi: f times the shading normal's correction, times cos(wo).
    const Bsdf light_side = m.make_bsdf(plane_point(), wi);
    const double importance = std::max(0.0, double(dot(n, wi))) / kPi * s * dot(wo, n0) / dot(wi, n0);
    EXPECT_NEAR(light_side.eval(wi, wo, TransportMode::Importance).x, importance, 1e-5 * std::max(1.0, importance))
        << "light path, wi.z " << wi.z;
  }
  EXPECT_GE(shadowed, 2);
}

// A material's "surface_normal" (the add-on's bump from a displacement) is Cycles' sd->N after
// SetNormal: the shading normal of closures without their own, the base a Bump node without a
// Normal tilts, and the reference of the diffuse bump shadowing, so under it alone a diffuse
// lobe is the plain cosine over pi; a Bump on top is shadowed against it.
TEST(ShadingNormals, SurfaceNormalMovesEverythingAfterIt) {
  const Vec3 n = normalize(Vec3(0.35f, -0.2f, 0.9f));
  const std::string map = R"({"node":"normal_map","space":"WORLD","color":[)" + std::to_string(0.5f + 0.5f * n.x) + "," +
                          std::to_string(0.5f + 0.5f * n.y) + "," + std::to_string(0.5f + 0.5f * n.z) + "]}";
  const std::string ramp = R"({"node":"bump","height":{"node":"math","operation":"MULTIPLY","value1":)"
                           R"({"node":"separate_rgb","color":{"node":"uv"},"output":"r"},"value2":0.5}})";
  Params plain(R"({"type":"diffuse","color":[1,1,1],"surface_normal":)" + map + "}", "material 's'");
  Params bumped(R"({"type":"diffuse","color":[1,1,1],"surface_normal":)" + map + R"(,"normal":)" + ramp + "}",
                "material 'b'");
  const Material m = Material::from_params(plain, "s"), mb = Material::from_params(bumped, "b");
  const Vec3 wo = normalize(Vec3(-0.2f, 0.3f, 1.0f));
  const Bsdf bsdf = m.make_bsdf(plane_point(), wo), bsdf_b = mb.make_bsdf(plane_point(), wo);
  expect_vec(bsdf.shading_normal(wo), n, 1e-4f);
  // The ramp's bump evaluated with n as the shading normal (what the material must do).
  ShadingPoint at_n = plane_point();
  at_n.ns = n;
  const Vec3 nb = normal_of(ramp, at_n);
  expect_vec(bsdf_b.shading_normal(wo), nb, 1e-4f);
  EXPECT_GT(length(nb - normal_of(ramp, plane_point())), 0.1f) << "the bump's base must matter here";
  auto shadowing = [](Vec3 mapped, Vec3 reference, Vec3 light) {
    const double g = double(dot(reference, light)) / (double(dot(mapped, light)) * dot(reference, mapped));
    return g >= 1 ? 1.0 : g <= 0 ? 0.0 : g + g * g * (1 - g);
  };
  int shadowed_against_the_mesh = 0;
  for (Vec3 wi : {normalize(Vec3(0.6f, -0.3f, 0.5f)), normalize(Vec3(-0.7f, 0.4f, 0.3f)), normalize(Vec3(0.1f, 0.9f, 0.4f)),
                  normalize(Vec3(-0.9f, -0.1f, 0.15f))}) {
    if (shadowing(n, Vec3(0, 0, 1), wi) < 0.999) ++shadowed_against_the_mesh;
    const double plain_f = std::max(0.0, double(dot(n, wi))) / kPi;
    EXPECT_NEAR(bsdf.eval(wo, wi, TransportMode::Radiance).x, plain_f, 1e-5 * std::max(1.0, plain_f)) << wi.z;
    const double bumped_f = std::max(0.0, double(dot(nb, wi))) / kPi * shadowing(nb, n, wi);
    EXPECT_NEAR(bsdf_b.eval(wo, wi, TransportMode::Radiance).x, bumped_f, 1e-5 * std::max(1.0, bumped_f)) << wi.z;
  }
  EXPECT_GE(shadowed_against_the_mesh, 2) << "directions where the mesh normal would have shadowed";
}

}  // namespace test_material_normals
