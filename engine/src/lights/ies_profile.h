// An IES LM-63 photometric profile: a luminaire's intensity (candela) by direction, as
// lighting manufacturers publish it and Blender's IES Texture node reads it. Read and
// interpolated as Cycles 3.4 does (util/ies.cpp, kernel/svm/ies.h), so a lamp with an IES
// Texture lights a scene as it does in Cycles:
//  - photometric types C (vertical angle from the nadir, horizontal around the axis) and B;
//    the quadrants or halves a symmetric file leaves out are mirrored, then the horizontal
//    angles wrap at 360 degrees;
//  - candela are turned into the lamp's units by the candela multiplier, both ballast factors
//    and 4 pi / 177.83 (a D65 white's lumens per watt), as Cycles;
//  - Catmull-Rom interpolation over the vertical angles, then over the horizontal ones,
//    negative results clamped to 0; nothing beyond the last vertical angle.
// One deliberate difference: a type C file whose vertical angles run from 90 to 180 degrees
// (a luminaire that lights only upward) emits upward here; Cycles 3.4 reverses those angles
// into a descending table and renders the lamp black.
#pragma once
#include <string>
#include <vector>
#include "core/math.h"

namespace rdv {

class IesProfile {
 public:
  // Reads the text of an .ies file. False, with `error` saying what is wrong, for a file
  // that is not an LM-63 profile of type B or C (Cycles then uses a constant 100).
  bool parse(const std::string &text, std::string &error);
  // Reads and parses the file at `path` (false, with `error`, if it cannot be read).
  bool load(const std::string &path, std::string &error);
  // The intensity along a unit direction in the lamp's own space (-Z straight down, the
  // vertical angle's 0; the horizontal angle atan2(x, y) + pi, Cycles' convention).
  float eval(Vec3 dir) const;
  // The same at a vertical and a horizontal angle in radians (v from 0 to pi, h 0 to 2 pi).
  float eval_angles(float v_angle, float h_angle) const;
  size_t num_horizontal() const { return h_.size(); }

 private:
  bool process_type_b(std::string &error);
  bool process_type_c(std::string &error);
  float vertical(size_t h, size_t v, float frac) const;
  std::vector<float> v_, h_;                 // angles: degrees while read, radians after
  std::vector<std::vector<float>> columns_;  // per horizontal angle, the intensities over v_
};

}  // namespace rdv
