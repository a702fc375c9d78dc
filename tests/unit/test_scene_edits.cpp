// In-place scene edits for the interactive viewport (rdv_scene_set_material / _set_mesh /
// _set_light) and the live-object counters: an edit changes the image like a rebuilt
// scene would, ids stay valid, edits are refused while a session exists.
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>
#include "rendezvous.h"

namespace test_scene_edits {

namespace {

const float kIdentity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
// A floor quad 4x4 at z=0 and a camera 3 units above looking down.
const float kQuad[] = {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0};
const uint32_t kQuadIdx[] = {0, 1, 2, 0, 2, 3};
const char *kCamera = R"({"type":"perspective","focal_length":50,"transform":[1,0,0,0, 0,1,0,0, 0,0,1,3, 0,0,0,1]})";
const char *kSettings = R"({"width":16,"height":16,"samples":4,"threads":1,"seed":1})";

struct Fixture {
  rdv_scene *s = nullptr;
  uint32_t mat = 0, mesh = 0, inst = 0, light = 0;
  Fixture() {
    EXPECT_EQ(RDV_OK, rdv_scene_create(&s));
    EXPECT_EQ(RDV_OK, rdv_scene_add_material(s, "Floor", R"({"type":"diffuse","color":[0.8,0.8,0.8]})", &mat));
    EXPECT_EQ(RDV_OK, rdv_scene_add_mesh(s, "Quad", kQuad, 4, nullptr, nullptr, kQuadIdx, 2, nullptr, mat, &mesh));
    EXPECT_EQ(RDV_OK, rdv_scene_add_instance(s, mesh, kIdentity, &inst));
    EXPECT_EQ(RDV_OK, rdv_scene_add_light(
                          s, "Sun", R"({"type":"sun","strength":3,"angle":0.1,"transform":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]})",
                          &light));
    EXPECT_EQ(RDV_OK, rdv_scene_set_world(s, R"({"color":[0,0,0],"strength":0})"));
    EXPECT_EQ(RDV_OK, rdv_scene_set_camera(s, kCamera));
  }
  ~Fixture() { rdv_scene_destroy(s); }
  // Mean RGB of a small render.
  std::vector<double> render(const char *settings = kSettings) {
    rdv_session *sess = nullptr;
    EXPECT_EQ(RDV_OK, rdv_session_create(s, settings, &sess)) << rdv_last_error();
    if (!sess) return {0, 0, 0};
    EXPECT_EQ(RDV_OK, rdv_session_start(sess));
    EXPECT_EQ(RDV_OK, rdv_session_wait(sess));
    nlohmann::json js = nlohmann::json::parse(settings);
    const uint32_t w = js["width"], h = js["height"];
    std::vector<float> px(size_t(w) * h * 4);
    EXPECT_EQ(RDV_OK, rdv_session_read_film(sess, RDV_PASS_COMBINED, 0, 0, w, h, 1, px.data()));
    rdv_session_destroy(sess);
    std::vector<double> mean(3, 0.0);
    for (size_t i = 0; i < px.size(); i += 4)
      for (int c = 0; c < 3; ++c) mean[c] += px[i + c] / (double(w) * h);
    return mean;
  }
  // How many media the scene holds (rdv_scene_summary), 0 when it has none.
  int media_count() {
    const char *text = nullptr;
    EXPECT_EQ(RDV_OK, rdv_scene_summary(s, &text));
    nlohmann::json j = nlohmann::json::parse(text ? text : "{}");
    if (!j.contains("media") || j["media"] == "none") return 0;
    return j["media"]["homogeneous"].get<int>() + j["media"]["grid"].get<int>();
  }
  // Seconds of the fastest of three renders with `settings`.
  double render_seconds(const char *settings) {
    double best = 1e30;
    for (int i = 0; i < 3; ++i) {
      auto t0 = std::chrono::steady_clock::now();
      render(settings);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  }
};

// A closed box from (-3,-3,0.5) to (3,3,1.5) between the camera and the floor, faces outward.
const float kBox[] = {-3, -3, 0.5f, 3, -3, 0.5f, 3, 3, 0.5f, -3, 3, 0.5f,
                      -3, -3, 1.5f, 3, -3, 1.5f, 3, 3, 1.5f, -3, 3, 1.5f};
const uint32_t kBoxIdx[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                            1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
const char *kFoggyWorld = R"({"color":[0,0,0],"strength":0,"volume":{"density":0.5}})";
const char *kClearWorld = R"({"color":[0,0,0],"strength":0})";
const char *kFoggyDiffuse = R"({"type":"diffuse","color":[0.5,0.5,0.5],"volume":{"density":2}})";
const char *kDiffuse = R"({"type":"diffuse","color":[0.5,0.5,0.5]})";

}  // namespace

TEST(SceneEdits, SetMaterialChangesColourInPlace) {
  Fixture f;
  std::vector<double> grey = f.render();
  EXPECT_GT(grey[0], 0.1);
  EXPECT_NEAR(grey[0], grey[2], 1e-3 + 0.01 * grey[0]);
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, f.mat, R"({"type":"diffuse","color":[0.8,0.0,0.0]})"))
      << rdv_last_error();
  std::vector<double> red = f.render();
  EXPECT_NEAR(red[0], grey[0], 0.02 * grey[0]);  // same sun, same red reflectance
  EXPECT_LT(red[2], 1e-6);
  // An emissive material added in place becomes a light (the light tables are rebuilt).
  ASSERT_EQ(RDV_OK, rdv_scene_set_light(f.s, f.light, R"({"type":"sun","strength":0,"transform":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]})"));
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, f.mat, R"({"type":"emission","color":[0,1,0],"strength":2})"));
  std::vector<double> green = f.render();
  EXPECT_GT(green[1], 1.0);
  EXPECT_LT(green[0], 1e-6);
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_set_material(f.s, 99, R"({"type":"diffuse"})"));
  EXPECT_NE(std::string(rdv_last_error()).find("no such material"), std::string::npos) << rdv_last_error();
}

TEST(SceneEdits, SetLightChangesBrightness) {
  Fixture f;
  std::vector<double> a = f.render();
  ASSERT_EQ(RDV_OK, rdv_scene_set_light(
                        f.s, f.light, R"({"type":"sun","strength":6,"angle":0.1,"transform":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]})"))
      << rdv_last_error();
  std::vector<double> b = f.render();
  EXPECT_NEAR(b[0], 2.0 * a[0], 0.02 * b[0]);
  ASSERT_EQ(RDV_OK, rdv_scene_set_light(f.s, f.light, R"({"type":"sun","strength":0,"transform":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]})"));
  EXPECT_LT(f.render()[0], 1e-6);
  EXPECT_NE(RDV_OK, rdv_scene_set_light(f.s, 7, R"({"type":"sun","strength":1})"));
}

// The viewport sets the world again on every world edit: a world without "volume" removes
// the fog an earlier one had (it used to stay).
TEST(SceneEdits, SetWorldAddsAndRemovesTheWorldVolume) {
  Fixture f;
  std::vector<double> clear = f.render();
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, R"({"color":[0,0,0],"strength":0,"volume":{"density":0.5}})"))
      << rdv_last_error();
  std::vector<double> foggy = f.render();
  EXPECT_LT(foggy[0], 0.5 * clear[0]);  // the sun is extinguished by fog without end
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, R"({"color":[0,0,0],"strength":0})")) << rdv_last_error();
  std::vector<double> again = f.render();
  EXPECT_NEAR(again[0], clear[0], 1e-4 + 1e-3 * clear[0]);  // same seed, same paths
}

TEST(SceneEdits, SetMeshReplacesGeometryAndKeepsInstances) {
  Fixture f;
  std::vector<double> full = f.render();
  // A quad covering only x > 0: about half of the view goes black.
  const float half[] = {0, -2, 0, 2, -2, 0, 2, 2, 0, 0, 2, 0};
  ASSERT_EQ(RDV_OK, rdv_scene_set_mesh(f.s, f.mesh, half, 4, nullptr, nullptr, kQuadIdx, 2, nullptr, f.mat))
      << rdv_last_error();
  std::vector<double> h = f.render();
  EXPECT_NEAR(h[0], 0.5 * full[0], 0.1 * full[0]);
  // The instance transform applies to the replaced geometry: stretched back over the view.
  const float moved[16] = {2, 0, 0, -2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // x in [0,2] -> [-2,2]
  ASSERT_EQ(RDV_OK, rdv_scene_set_instance_transform(f.s, f.inst, moved));
  std::vector<double> m = f.render();
  EXPECT_NEAR(m[0], full[0], 0.1 * full[0]);
  const uint32_t bad_idx[] = {0, 1, 9};
  EXPECT_EQ(RDV_ERROR_INVALID_ARGUMENT, rdv_scene_set_mesh(f.s, f.mesh, half, 4, nullptr, nullptr, bad_idx, 1, nullptr, f.mat));
  EXPECT_NE(RDV_OK, rdv_scene_set_mesh(f.s, 5, half, 4, nullptr, nullptr, kQuadIdx, 2, nullptr, f.mat));
}

TEST(SceneEdits, EditsRefusedWhileASessionExistsAndCountsTrackObjects) {
  uint32_t scenes0 = 0, sessions0 = 0;
  ASSERT_EQ(RDV_OK, rdv_live_objects(&scenes0, &sessions0));
  {
    Fixture f;
    rdv_session *sess = nullptr;
    ASSERT_EQ(RDV_OK, rdv_session_create(f.s, kSettings, &sess));
    uint32_t scenes = 0, sessions = 0;
    rdv_live_objects(&scenes, &sessions);
    EXPECT_EQ(scenes0 + 1, scenes);
    EXPECT_EQ(sessions0 + 1, sessions);
    EXPECT_EQ(RDV_ERROR_STATE, rdv_scene_set_material(f.s, f.mat, R"({"type":"diffuse"})"));
    EXPECT_EQ(RDV_ERROR_STATE, rdv_scene_set_light(f.s, f.light, R"({"type":"sun","strength":1})"));
    EXPECT_EQ(RDV_ERROR_STATE, rdv_scene_set_mesh(f.s, f.mesh, kQuad, 4, nullptr, nullptr, kQuadIdx, 2, nullptr, f.mat));
    rdv_session_destroy(sess);
    EXPECT_EQ(RDV_OK, rdv_scene_set_material(f.s, f.mat, R"({"type":"diffuse"})"));
  }
  uint32_t scenes = 0, sessions = 0;
  rdv_live_objects(&scenes, &sessions);
  EXPECT_EQ(scenes0, scenes);
  EXPECT_EQ(sessions0, sessions);
}

// A World volume and a material volume added and taken away 100 times (as viewport toggles
// do): no medium stays behind, the scene is media-free again (has_media() false: the summary
// says "none") and renders as before.
TEST(SceneEdits, RemovedMediaLeaveTheScene) {
  Fixture f;
  uint32_t toggled = 0;
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(f.s, "Toggled", kDiffuse, &toggled));
  const char *timing = R"({"width":96,"height":96,"samples":16,"threads":1,"seed":1})";
  std::vector<double> clear = f.render(timing);
  double media_free = f.render_seconds(timing);
  EXPECT_EQ(0, f.media_count());
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kFoggyWorld)) << rdv_last_error();
    ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, toggled, kFoggyDiffuse)) << rdv_last_error();
    ASSERT_EQ(RDV_OK, rdv_scene_commit(f.s)) << rdv_last_error();
    if (i == 0) EXPECT_EQ(2, f.media_count());
    ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kClearWorld));
    ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, toggled, kDiffuse));
    ASSERT_EQ(RDV_OK, rdv_scene_commit(f.s));
  }
  int left = f.media_count();
  EXPECT_EQ(0, left) << "media taken away by edits stay in the scene";
  std::vector<double> again = f.render(timing);
  EXPECT_NEAR(again[0], clear[0], 1e-5 + 1e-4 * clear[0]);  // same seed, same paths
  double toggled_time = f.render_seconds(timing);
  std::printf("[ media ] 96x96 16 spp, 1 thread: media-free %.2f ms, after 100 volume toggles %.2f ms (x%.3f), "
              "%d media left\n", 1e3 * media_free, 1e3 * toggled_time, toggled_time / media_free, left);
}

// Dropping a medium moves the ids of the media after it: a fog box whose medium came after
// the dropped ones renders exactly as before, and a World volume added later works too.
TEST(SceneEdits, DroppedMediaKeepTheOthersRendering) {
  Fixture f;
  uint32_t toggled = 0, fog = 0, box = 0, inst = 0;
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kFoggyWorld));
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(f.s, "Toggled", kFoggyDiffuse, &toggled));
  ASSERT_EQ(RDV_OK, rdv_scene_add_material(f.s, "FogBox", R"({"type":"volume","volume":{"density":1}})", &fog));
  ASSERT_EQ(RDV_OK, rdv_scene_add_mesh(f.s, "Box", kBox, 8, nullptr, nullptr, kBoxIdx, 12, nullptr, fog, &box));
  ASSERT_EQ(RDV_OK, rdv_scene_add_instance(f.s, box, kIdentity, &inst));
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kClearWorld));  // media before the box's: world, Toggled
  ASSERT_EQ(RDV_OK, rdv_scene_commit(f.s));
  EXPECT_EQ(2, f.media_count());
  std::vector<double> fogged = f.render();
  // A lamp inside the box: BDPT's light subpaths start in the box's medium (found per commit).
  uint32_t lamp = 0;
  ASSERT_EQ(RDV_OK, rdv_scene_add_light(f.s, "Lamp", R"({"type":"point","position":[0,0,1],"radius":0,"power":50})",
                                        &lamp));
  const char *bdpt = R"({"width":16,"height":16,"samples":4,"threads":1,"seed":1,"integrator":"bdpt"})";
  std::vector<double> lamp_fogged = f.render(bdpt);
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, toggled, kDiffuse));
  EXPECT_EQ(1, f.media_count());
  std::vector<double> lamp_same = f.render(bdpt);
  EXPECT_NEAR(lamp_same[0], lamp_fogged[0], 1e-6 + 1e-5 * lamp_fogged[0]);
  ASSERT_EQ(RDV_OK, rdv_scene_set_light(f.s, lamp, R"({"type":"point","position":[0,0,1],"radius":0,"power":0})"));
  std::vector<double> same = f.render();
  EXPECT_NEAR(same[0], fogged[0], 1e-6 + 1e-5 * fogged[0]);
  // The box's fog dims the sunlit floor: sun 3 through density 1 over 1 unit, down and up.
  std::vector<double> clear;
  {
    Fixture plain;
    clear = plain.render();
  }
  EXPECT_LT(fogged[0], 0.5 * clear[0]);
  EXPECT_GT(fogged[0], 0.02 * clear[0]);
  // A World volume added after the drops gets a valid id of its own.
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kFoggyWorld));
  EXPECT_EQ(2, f.media_count());
  std::vector<double> both = f.render();
  EXPECT_LT(both[0], 0.5 * fogged[0]);
  ASSERT_EQ(RDV_OK, rdv_scene_set_world(f.s, kClearWorld));
  std::vector<double> back = f.render();
  EXPECT_NEAR(back[0], fogged[0], 1e-6 + 1e-5 * fogged[0]);
  // The box's material without its volume: the scene is media-free.
  ASSERT_EQ(RDV_OK, rdv_scene_set_material(f.s, fog, kDiffuse));
  EXPECT_EQ(0, f.media_count());
}

}  // namespace test_scene_edits
