// Motion blur: transforms that change while the shutter is open, and the time each
// sample is traced at.
//
// Time. A sample draws one shutter time u in [0, 1) (the Camera stream's kCameraTime
// dimension, samplers/dimension_layout.h) and traces every ray of its path at u: the
// camera ray, the bounces, next-event estimation and, in BDPT, the light subpath and
// every connection, so all strategies of one sample see one frozen scene and one path
// contribution holds whatever strategy made it. The integrator opens a SampleTime scope
// for the sample; the ray queries (scene/embree_accel.cpp, Scene::surface_at) read it.
// u = 0 is the shutter's opening, 1 its closing; outside any sample (commit-time
// queries) it is the shutter's middle.
//
// Transforms. A moving transform is given as n >= 2 steps at evenly spaced times from
// the shutter's opening (step 0) to its closing (step n - 1), and between two steps the
// 3x4 matrices are interpolated linearly: exactly what Embree does with an instance's
// time steps (rtcSetGeometryTimeStepCount; Embree's getTimeSegment and lerp), so the
// point rebuilt from a hit's barycentrics lies where Embree found it. (A rotation between
// two steps is interpolated as a matrix, not an angle: more steps follow it closer.)
//
// Deformation. A deforming mesh gives its vertex positions (and normals, if smooth) at
// n >= 2 evenly spaced shutter times the same way (Mesh::position_steps); Embree holds
// one vertex buffer per step and blends the triangle's vertices at the ray's time, and
// Scene::surface_at blends the same vertices with the same weights (step_blend, blend),
// so the hit point, its geometric normal and its shading normal belong to the triangle
// Embree hit.
#pragma once
#include <cmath>
#include <vector>
#include "core/math.h"

namespace rdv {

// Where shutter time u in [0, 1] falls among n >= 2 evenly spaced steps: between step
// `first` and the next, a fraction f of the way. Embree's getTimeSegment, so what we
// interpolate at a hit is what Embree intersected.
struct StepBlend {
  size_t first;
  float f;
};
inline StepBlend step_blend(size_t num_steps, float u) {
  const float segments = float(num_steps - 1);
  const float scaled = u * segments;
  const float segment = std::fmin(std::fmax(std::floor(scaled), 0.0f), segments - 1.0f);
  return {size_t(segment), scaled - segment};
}

// The transform at shutter time u in [0, 1] of steps spanning the open shutter.
inline Transform transform_at(const std::vector<Transform> &steps, float u) {
  const StepBlend s = step_blend(steps.size(), u);
  const Transform &a = steps[s.first], &b = steps[s.first + 1];
  Transform t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.m[r][c] = (1.0f - s.f) * a.m[r][c] + s.f * b.m[r][c];
  return t;
}

// A vertex attribute between two steps, blended as Embree blends vertex time steps
// (lerp: (1 - f) a + f b).
inline Vec3 blend(Vec3 a, Vec3 b, float f) { return a * (1.0f - f) + b * f; }

namespace shutter {

// The shutter time of the sample this thread traces (see above).
inline thread_local float sample_time = 0.5f;
inline float now() { return sample_time; }

// Traces a sample at time u: every ray query on this thread until the scope ends.
class SampleTime {
 public:
  explicit SampleTime(float u) : previous_(sample_time) { sample_time = u; }
  ~SampleTime() { sample_time = previous_; }
  SampleTime(const SampleTime &) = delete;
  SampleTime &operator=(const SampleTime &) = delete;

 private:
  float previous_;
};

}  // namespace shutter
}  // namespace rdv
