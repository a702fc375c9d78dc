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
#pragma once
#include <cmath>
#include <vector>
#include "core/math.h"

namespace rdv {

// The transform at shutter time u in [0, 1] of steps spanning the open shutter.
inline Transform transform_at(const std::vector<Transform> &steps, float u) {
  const float segments = float(steps.size() - 1);
  const float scaled = u * segments;
  const float segment = std::fmin(std::fmax(std::floor(scaled), 0.0f), segments - 1.0f);
  const float f = scaled - segment;
  const Transform &a = steps[size_t(segment)], &b = steps[size_t(segment) + 1];
  Transform t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.m[r][c] = (1.0f - f) * a.m[r][c] + f * b.m[r][c];
  return t;
}

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
