#include "textures/math_nodes.h"
#include <cmath>

namespace rdv {

const std::vector<std::string> kVectorMathOps = {
    "ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "CROSS_PRODUCT", "PROJECT", "REFLECT", "REFRACT",
    "FACEFORWARD", "DOT_PRODUCT", "DISTANCE", "LENGTH", "SCALE", "NORMALIZE", "SNAP", "FLOOR", "CEIL", "MODULO",
    "WRAP", "FRACTION", "ABSOLUTE", "MINIMUM", "MAXIMUM", "SINE", "COSINE", "TANGENT"};

namespace {

float safe_divide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }
Vec3 safe_divide(Vec3 a, Vec3 b) { return {safe_divide(a.x, b.x), safe_divide(a.y, b.y), safe_divide(a.z, b.z)}; }
template <class F>
Vec3 each(Vec3 a, F f) { return {f(a.x), f(a.y), f(a.z)}; }
template <class F>
Vec3 each(Vec3 a, Vec3 b, F f) { return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)}; }
float wrap(float v, float hi, float lo) {
  const float range = hi - lo;
  return range != 0.0f ? v - range * std::floor((v - lo) / range) : lo;
}
Vec3 safe_normalize(Vec3 a) {
  const float t = length(a);
  return t != 0.0f ? a * (1.0f / t) : a;
}

}  // namespace

Vec3 vector_math(int op, Vec3 a, Vec3 b, Vec3 c, float scale, bool &value) {
  value = false;
  switch (op) {
    case 0: return a + b;
    case 1: return a - b;
    case 2: return a * b;
    case 3: return safe_divide(a, b);
    case 4: return a * b + c;
    case 5: return cross(a, b);
    case 6: {  // project a onto b
      const float l2 = dot(b, b);
      return l2 != 0.0f ? b * (dot(a, b) / l2) : Vec3(0.0f);
    }
    case 7: {  // reflect a about the plane of normal b
      const Vec3 n = normalize(b);
      return a - n * (2.0f * dot(a, n));
    }
    case 8: {  // refract a through normal b with ior ratio `scale`
      const Vec3 n = safe_normalize(b);
      const float d = dot(n, a), k = 1.0f - scale * scale * (1.0f - d * d);
      return k < 0.0f ? Vec3(0.0f) : a * scale - n * (scale * d + std::sqrt(k));
    }
    case 9: return dot(c, b) < 0.0f ? a : -a;  // faceforward(a, incident b, reference c)
    case 10: value = true; return Vec3(dot(a, b));
    case 11: value = true; return Vec3(length(a - b));
    case 12: value = true; return Vec3(length(a));
    case 13: return a * scale;
    case 14: return safe_normalize(a);
    case 15: return each(safe_divide(a, b), [](float x) { return std::floor(x); }) * b;
    case 16: return each(a, [](float x) { return std::floor(x); });
    case 17: return each(a, [](float x) { return std::ceil(x); });
    case 18: return each(a, b, [](float x, float y) { return y != 0.0f ? std::fmod(x, y) : 0.0f; });
    case 19: return {wrap(a.x, b.x, c.x), wrap(a.y, b.y, c.y), wrap(a.z, b.z, c.z)};
    case 20: return a - each(a, [](float x) { return std::floor(x); });
    case 21: return each(a, [](float x) { return std::fabs(x); });
    case 22: return vmin(a, b);
    case 23: return vmax(a, b);
    case 24: return each(a, [](float x) { return std::sin(x); });
    case 25: return each(a, [](float x) { return std::cos(x); });
    case 26: return each(a, [](float x) { return std::tan(x); });
    default: return Vec3(0.0f);
  }
}

namespace {
float smootherstep(float e0, float e1, float x) {
  x = clampf(safe_divide(x - e0, e1 - e0), 0.0f, 1.0f);
  return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}
float clamp_between(float v, float a, float b) { return a > b ? clampf(v, b, a) : clampf(v, a, b); }
}  // namespace

float map_range(float value, float from_min, float from_max, float to_min, float to_max, float steps, MapRangeType type,
                bool clamp) {
  if (from_max == from_min) return 0.0f;
  float f = (value - from_min) / (from_max - from_min);
  switch (type) {
    case MapRangeType::Linear: break;
    case MapRangeType::Stepped: f = steps > 0.0f ? std::floor(f * (steps + 1.0f)) / steps : 0.0f; break;
    case MapRangeType::SmoothStep:
      f = from_min > from_max ? 1.0f - smoothstep(from_max, from_min, value) : smoothstep(from_min, from_max, value);
      break;
    case MapRangeType::SmootherStep:
      f = from_min > from_max ? 1.0f - smootherstep(from_max, from_min, value)
                              : smootherstep(from_min, from_max, value);
      break;
  }
  const float r = to_min + f * (to_max - to_min);
  // Blender clamps the linear and stepped results to the target range (Cycles adds a Clamp).
  return clamp && (type == MapRangeType::Linear || type == MapRangeType::Stepped) ? clamp_between(r, to_min, to_max) : r;
}

Vec3 map_range(Vec3 value, Vec3 from_min, Vec3 from_max, Vec3 to_min, Vec3 to_max, Vec3 steps, MapRangeType type,
               bool clamp) {
  Vec3 f = safe_divide(value - from_min, from_max - from_min);
  for (int k = 0; k < 3; ++k) {
    switch (type) {
      case MapRangeType::Linear: break;
      case MapRangeType::Stepped: f[k] = steps[k] > 0.0f ? std::floor(f[k] * (steps[k] + 1.0f)) / steps[k] : 0.0f; break;
      case MapRangeType::SmoothStep: f[k] = smoothstep(0.0f, 1.0f, f[k]); break;
      case MapRangeType::SmootherStep: {
        const float t = clampf(f[k], 0.0f, 1.0f);
        f[k] = t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
        break;
      }
    }
  }
  Vec3 r = to_min + f * (to_max - to_min);
  if (clamp && (type == MapRangeType::Linear || type == MapRangeType::Stepped))
    for (int k = 0; k < 3; ++k) r[k] = clamp_between(r[k], to_min[k], to_max[k]);
  return r;
}

}  // namespace rdv
