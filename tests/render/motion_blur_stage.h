// The stages the motion-blur tests share (test_motion_blur.cpp, test_deformation_blur.cpp):
// a floor, a red box and a glossy blue ball over it under an area lamp; and a floor lit
// only by an emitting mesh. The camera's shutter is open over [-0.25, 0.25] frames.
#pragma once
#include <nlohmann/json.hpp>

namespace rdv::test {

// box_motion: the box's transform steps (null: it stands still); ball: the ball's mesh
// (material "blue"), however it moves.
inline nlohmann::json motion_blur_stage(int size, const nlohmann::json &box_motion, const nlohmann::json &ball) {
  using nlohmann::json;
  json box = {{"name", "box"},
              {"shape", {{"type", "box"}, {"size", {0.8, 0.8, 0.8}}}},
              {"materials", {"red"}},
              {"transform", {{"translate", {-1, 0, 0.4}}}}};
  if (!box_motion.is_null()) box["motion"] = box_motion;
  return {{"settings", {{"width", size}, {"height", size}, {"samples", 32}, {"max_bounces", 4}, {"seed", 1}}},
          {"camera",
           {{"focal_length", 35},
            {"transform", {{"look_at", {{"from", {0, -5, 2.2}}, {"to", {0, 0, 0.6}}}}}},
            {"shutter_open", -0.25},
            {"shutter_close", 0.25}}},
          {"world", {{"color", {0.08, 0.09, 0.1}}}},
          {"materials",
           {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.7, 0.7}}},
            {{"name", "red"}, {"type", "diffuse"}, {"color", {0.8, 0.15, 0.1}}},
            {{"name", "blue"}, {"type", "glossy"}, {"color", {0.3, 0.4, 0.8}}, {"roughness", 0.3}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"floor"}}}, box, ball}},
          {"lights",
           {{{"type", "area"}, {"size", 1.0}, {"power", 200}, {"position", {0.5, -1.0, 3.2}}, {"direction", {0, 0, -1}}}}}};
}

// A floor (6 x 6, grey) seen from above, lit only by `lamp`, a mesh of material "lamp"
// (emission 20), over a black world.
inline nlohmann::json emitter_stage(int size, const nlohmann::json &lamp) {
  return {{"settings", {{"width", size}, {"height", size}, {"samples", 64}, {"max_bounces", 3}}},
          {"camera",
           {{"focal_length", 30},
            {"transform", {{"look_at", {{"from", {0, -4, 4}}, {"to", {0, 0, 0}}}}}},
            {"shutter_open", -0.25},
            {"shutter_close", 0.25}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials",
           {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.7, 0.7}}},
            {{"name", "lamp"}, {"type", "emission"}, {"color", {1, 0.9, 0.8}}, {"strength", 20}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"floor"}}}, lamp}}};
}

}  // namespace rdv::test
