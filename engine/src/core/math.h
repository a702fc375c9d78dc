// Small vector and matrix types. Float everywhere: Embree works in float, and the
// robust ray offset (ray_offset.h) makes float safe at scene scales 1e-4 .. 1e5.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rdv {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv4Pi = 0.07957747154594766788f;
constexpr float kInf = INFINITY;

struct Vec2 {
  float x = 0, y = 0;
  Vec2() = default;
  constexpr Vec2(float x_, float y_) : x(x_), y(y_) {}
  Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  Vec2 operator*(float s) const { return {x * s, y * s}; }
};

struct Vec3 {
  float x = 0, y = 0, z = 0;
  Vec3() = default;
  constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  float &operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3 operator+(Vec3 o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3 operator-(Vec3 o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3 operator*(Vec3 o) const { return {x * o.x, y * o.y, z * o.z}; }
  Vec3 operator/(Vec3 o) const { return {x / o.x, y / o.y, z / o.z}; }
  Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
  Vec3 operator/(float s) const { float r = 1.0f / s; return {x * r, y * r, z * r}; }
  Vec3 operator-() const { return {-x, -y, -z}; }
  Vec3 &operator+=(Vec3 o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3 &operator*=(Vec3 o) { x *= o.x; y *= o.y; z *= o.z; return *this; }
  Vec3 &operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
  bool operator==(const Vec3 &o) const { return x == o.x && y == o.y && z == o.z; }
};
inline Vec3 operator*(float s, Vec3 v) { return v * s; }

// RGB radiance / reflectance. Scene-linear Rec.709.
using Color = Vec3;

inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float absdot(Vec3 a, Vec3 b) { return std::fabs(dot(a, b)); }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length_squared(Vec3 v) { return dot(v, v); }
inline float length(Vec3 v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(Vec3 v) { return v / length(v); }
inline Vec3 vmin(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float max_component(Vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float min_component(Vec3 v) { return std::min(v.x, std::min(v.y, v.z)); }
inline float average(Color c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }
// Rec.709 luminance.
inline float luminance(Color c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool is_black(Color c) { return c.x == 0 && c.y == 0 && c.z == 0; }
inline bool is_finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }
inline float sqr(float v) { return v * v; }
// Hermite step from 0 at e0 to 1 at e1 (Cycles' smoothstep, which Blender's nodes use).
inline float smoothstep(float e0, float e1, float x) {
  if (x < e0) return 0.0f;
  if (x >= e1) return 1.0f;
  const float t = (x - e0) / (e1 - e0);
  return (3.0f - 2.0f * t) * (t * t);
}
inline float safe_sqrt(float v) { return std::sqrt(std::max(v, 0.0f)); }
inline Vec3 face_forward(Vec3 n, Vec3 v) { return dot(n, v) < 0 ? -n : n; }

// Orthonormal basis around a unit normal (Duff et al. 2017, branchless).
struct Frame {
  Vec3 s, t, n;
  Frame() = default;
  explicit Frame(Vec3 normal) : n(normal) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
  }
  Frame(Vec3 s_, Vec3 t_, Vec3 n_) : s(s_), t(t_), n(n_) {}
  Vec3 to_local(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 to_world(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

// Affine 4x4 transform, row-major (Blender's matrix_world layout).
struct Transform {
  float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  static Transform from_row_major(const float *v) {
    Transform t;
    for (int i = 0; i < 16; ++i) t.m[i / 4][i % 4] = v[i];
    return t;
  }
  Vec3 point(Vec3 p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  Vec3 vector(Vec3 v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Transforms a normal with the inverse transpose: call on the INVERSE transform.
  Vec3 normal_by_inverse(Vec3 n) const {
    return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
            m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
            m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
  }
  Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
  Transform operator*(const Transform &o) const {
    Transform r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        float s = 0;
        for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  float det3() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  bool is_finite() const {
    for (auto &r : m)
      for (float v : r)
        if (!std::isfinite(v)) return false;
    return true;
  }
  // Inverse of an affine transform; callers check det3() != 0 first.
  Transform inverse() const {
    Transform r;
    float id = 1.0f / det3();
    r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    Vec3 t{m[0][3], m[1][3], m[2][3]};
    for (int i = 0; i < 3; ++i) r.m[i][3] = -(r.m[i][0] * t.x + r.m[i][1] * t.y + r.m[i][2] * t.z);
    r.m[3][0] = r.m[3][1] = r.m[3][2] = 0;
    r.m[3][3] = 1;
    return r;
  }
};

struct Ray {
  Vec3 o, d;
  float tmax = kInf;
  // The kind of ray (scene/ray_visibility.h): it meets only instances visible to one of
  // these bits. All ones: every instance.
  uint32_t mask = 0xffffffffu;
};

}  // namespace rdv
