// MIP levels of an image texture, in scene-linear colour, built so that a filtered lookup (a
// camera path's ray cone) sees the mean of what unfiltered lookups (light paths, mlt) see:
// one texture for every strategy. Level 1 averages each 2 x 2 block of level 0's texel
// means, each the mean over the texel's square of a lookup without a footprint (which
// interpolates the file's values and converts the result, as Cycles does); every further
// level averages 2 x 2 blocks of the one before (odd sizes: the last row / column joins the
// one before), down to 1 x 1. Rows stream through: an image too large to stay in memory (read
// through OpenImageIO's tile cache) keeps only its coarse levels.
#pragma once
#include <functional>
#include <vector>
#include "core/math.h"

namespace rdv {

struct MipLevel {
  int w = 0, h = 0;
  std::vector<float> texels;  // scene-linear colour, straight alpha; rows top first
};

// Image rows [y0, y1) (0 <= y0 < y1 <= h) of the file's values as floats, channels
// interleaved; false: the file could not be read.
using ReadImageRows = std::function<bool(int y0, int y1, float *dst)>;
// A value in the file's space (channels as filtered: grey, grey + alpha, RGB, RGBA) to
// scene-linear colour: the lookups' own conversion.
using ToSceneLinear = std::function<Color(const float value[4])>;

struct MipSource {
  int w = 0, h = 0, channels = 3;
  bool nonlinear = false;  // the conversion is not linear (8-bit sRGB, most of Blender's spaces)
  ReadImageRows read;
  ToSceneLinear to_scene_linear;
};

// Levels keep_from (>= 1), keep_from + 1, ... down to 1 x 1; false where a read failed.
bool build_mip_levels(const MipSource &source, int keep_from, std::vector<MipLevel> &levels);

}  // namespace rdv
