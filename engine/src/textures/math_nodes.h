// Blender's Vector Math and Map Range nodes as Cycles 3.4 computes them (its svm/math_util.h
// and svm/map_range.h): every Vector Math operation, Map Range's linear, stepped, smooth-step
// and smoother-step interpolations on floats and on vectors, with their clamps.
#pragma once
#include <string>
#include <vector>
#include "core/math.h"

namespace rdv {

// Blender's Vector Math operations, in the order of kVectorMathOps.
extern const std::vector<std::string> kVectorMathOps;
// The result of operation op on a, b, c and scale: a vector, or a value for DOT_PRODUCT,
// DISTANCE and LENGTH (`value` true then).
Vec3 vector_math(int op, Vec3 a, Vec3 b, Vec3 c, float scale, bool &value);

enum class MapRangeType : uint8_t { Linear, Stepped, SmoothStep, SmootherStep };
// Float Map Range: 0 when from_min == from_max, as Cycles; clamp applies to linear and stepped.
float map_range(float value, float from_min, float from_max, float to_min, float to_max, float steps, MapRangeType type,
                bool clamp);
// Vector Map Range: per component, a zero-width source range maps to to_min.
Vec3 map_range(Vec3 value, Vec3 from_min, Vec3 from_max, Vec3 to_min, Vec3 to_max, Vec3 steps, MapRangeType type,
               bool clamp);

}  // namespace rdv
