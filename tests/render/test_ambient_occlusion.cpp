// The Ambient Occlusion node (textures/ambient_occlusion.h) where its value is known exactly:
// an emission of AO's colour on a floor with nothing above it is 1 in every pixel (no ray of
// the point's own surface occludes it: the origins are offset by the point's rounding error),
// the inside of a closed box is 0 (every ray meets a wall), whatever the scene's scale and
// however far from the origin the floor lies; Only
// Local ignores another object; Inside looks the other way. Deterministic (the images are
// exact; the directions are a fixed set per point). Its agreement with Cycles is
// blender.brightness.ambient_occlusion.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_ambient_occlusion {

using namespace rdv::test;
using nlohmann::json;

namespace {

json ao(bool only_local = false, bool inside = false, double distance = 1e9) {
  return {{"node", "ambient_occlusion"}, {"distance", distance}, {"samples", 16}, {"only_local", only_local},
          {"inside", inside}};
}

// Seen from above at `scale` (the view 10 units wide on the floor), `far` units from the
// origin: a floor and, unless left out, a 2-unit box floating 0.2 above it (or around the camera).
json scene(double scale, const json &floor_ao, const json &box_ao, bool box, bool camera_in_box = false,
           double far = 0) {
  const double c = far * scale;
  json meshes = {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 40 * scale}}}, {"materials", {"floor"}},
                  {"transform", {{"translate", {c, c, 0}}}}}};
  if (box)
    meshes.push_back({{"name", "box"}, {"shape", {{"type", "box"}, {"size", {2 * scale, 2 * scale, 2 * scale}}}},
                      {"materials", {"box"}}, {"transform", {{"translate", {c, c, camera_in_box ? 0.0 : 1.2 * scale}}}}});
  const json from = camera_in_box ? json{c, c - 0.5 * scale, 0.2 * scale} : json{c, c, 10 * scale};
  const json to = camera_in_box ? json{c, c + 1 * scale, 0} : json{c, c, 0};
  return {{"settings", {{"width", 16}, {"height", 16}, {"samples", 2}}},
          {"camera", {{"focal_length", 35}, {"clip_start", 0.01 * scale}, {"clip_end", 100 * scale},
                      {"transform", {{"look_at", {{"from", from}, {"to", to}, {"up", {0, 1, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "floor"}, {"type", "emission"}, {"color", floor_ao}, {"strength", 1}},
                         {{"name", "box"}, {"type", "emission"}, {"color", box_ao}, {"strength", 1}}}},
          {"meshes", meshes}};
}

}  // namespace

TEST(AmbientOcclusion, ExactWhereTheAnswerIsKnown) {
  for (double scale : {1e-3, 1.0, 1e3}) {
    SCOPED_TRACE("scale " + std::to_string(scale));
    // A floor alone: nothing occludes it; and 10,000 units from the origin (its rounding
    // error there is 2^-10 of a unit: the rays must still leave the floor).
    for (double far : {0.0, 1e4}) {
      Image open = render_json(scene(scale, ao(), ao(), false, false, far).dump());
      ASSERT_TRUE(open.all_finite());
      for (size_t i = 0; i < open.rgba.size(); i += 4) ASSERT_FLOAT_EQ(open.rgba[i], 1.0f) << "pixel " << i / 4 << " far " << far;
    }
    // Inside a closed box (the camera in it): every ray from a wall meets another.
    Image closed = render_json(scene(scale, ao(), ao(), true, true).dump());
    for (size_t i = 0; i < closed.rgba.size(); i += 4) ASSERT_EQ(closed.rgba[i], 0.0f) << "pixel " << i / 4;
    // Inside: a box's outside seen from above, its rays into the box meet its far walls.
    Image inward = render_json(scene(scale, json::array({0.5, 0.5, 0.5}), ao(false, true), true).dump());
    Image outward = render_json(scene(scale, json::array({0.5, 0.5, 0.5}), ao(), true).dump());
    const size_t centre = (8 * 16 + 8) * 4;
    EXPECT_EQ(inward.rgba[centre], 0.0f);
    EXPECT_FLOAT_EQ(outward.rgba[centre], 1.0f);  // the box's top: nothing above it
    // Only Local: the floor beside the box (2 units from its centre, one from its side) is
    // darkened by it, not with Only Local.
    Image shaded = render_json(scene(scale, ao(false, false, 10 * scale), ao(), true).dump());
    Image local = render_json(scene(scale, ao(true, false, 10 * scale), ao(), true).dump());
    const size_t corner = (8 * 16 + 11) * 4;
    EXPECT_LT(shaded.rgba[corner], 0.95f);
    EXPECT_FLOAT_EQ(local.rgba[corner], 1.0f);
  }
  // Bad settings name the node.
  json bad = scene(1, ao(), ao(), false);
  bad["materials"][0]["color"]["samples"] = 0;
  Image img = render_json(bad.dump());
  EXPECT_NE(img.warnings.find("'samples' must be 1 to 128"), std::string::npos) << img.warnings;
}

}  // namespace test_ambient_occlusion
