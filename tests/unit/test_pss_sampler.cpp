// The primary-sample-space sampler of the Metropolis integrators: a rejected proposal
// restores every number exactly, streams own disjoint dimensions (mutating the light
// subpath's numbers never moves the camera subpath's), and small steps are symmetric
// with the set width (sqrt(k) wider for a number skipped k steps). Seeds are fixed;
// the statistical checks have false-alarm rates stated at each.
#include <gtest/gtest.h>
#include <cmath>
#include <vector>
#include "samplers/pss_sampler.h"

namespace test_pss_sampler {

using rdv::PssSampler;
using rdv::SampleStream;

namespace {

// Reads `n` 1D and `n` 2D numbers from each of the streams given.
std::vector<float> read(PssSampler &s, std::initializer_list<SampleStream> streams, int n) {
  std::vector<float> v;
  for (SampleStream stream : streams) {
    s.start_stream(stream, 0);
    for (int i = 0; i < n; ++i) {
      v.push_back(s.get_1d());
      rdv::Vec2 u = s.get_2d();
      v.push_back(u.x);
      v.push_back(u.y);
    }
  }
  return v;
}

const auto kAll = {SampleStream::Camera, SampleStream::Light, SampleStream::LightPoint, SampleStream::Lens,
                   SampleStream::CameraCrossing, SampleStream::LightCrossing, SampleStream::Connection,
                   SampleStream::Strategy};

// The numbers read(s, kAll, n) reads, as they stand: a 1D draw at position 2i
// (component 0), a 2D draw at 2i + 1 (components 0 and 1).
std::vector<float> snapshot(const PssSampler &s, int n) {
  std::vector<float> v;
  for (SampleStream stream : kAll)
    for (uint32_t i = 0; i < uint32_t(n); ++i) {
      v.push_back(s.peek(stream, 2 * i, 0));
      v.push_back(s.peek(stream, 2 * i + 1, 0));
      v.push_back(s.peek(stream, 2 * i + 1, 1));
    }
  return v;
}

}  // namespace

TEST(PssSampler, RejectRestoresEveryNumberExactly) {
  PssSampler s(7, 1, 0.01f, 0.3f);
  s.start_iteration();
  std::vector<float> state = read(s, kAll, 6);
  s.accept();
  uint64_t iteration = 1;
  for (int k = 0; k < 200; ++k) {
    std::vector<float> before = snapshot(s, 6);
    s.start_iteration();
    // A proposal reading more numbers than the state did (new dimensions too).
    std::vector<float> proposal = read(s, kAll, 6 + k % 5);
    bool changed = false;
    for (size_t i = 0; i < state.size(); ++i) changed |= proposal[i] != state[i];
    EXPECT_TRUE(changed);
    if (k % 3 == 0) {  // accepted now and then, so later rejections start from new states
      s.accept();
      ++iteration;
      state.assign(proposal.begin(), proposal.begin() + long(state.size()));
      continue;
    }
    s.reject();
    // The state's numbers (numbers a proposal reads beyond them are made afresh by the
    // next one that needs them).
    std::vector<float> after = snapshot(s, 6);
    for (size_t i = 0; i < before.size(); ++i) {
      ASSERT_GE(before[i], 0.0f) << "number " << i;
      ASSERT_EQ(before[i], after[i]) << "number " << i << ", step " << k;
    }
    EXPECT_EQ(s.iteration(), iteration);  // a rejected proposal's iteration is undone too
  }
}

// A proposal that reads only the light subpath's numbers leaves every camera-stream
// number as it was; and the camera stream's numbers are the same whatever the light
// stream read before them (disjoint dimensions).
TEST(PssSampler, StreamsAreSeparate) {
  PssSampler s(11, 2, 0.05f, 0.0f);
  s.start_iteration();
  std::vector<float> camera = read(s, {SampleStream::Camera}, 8);
  std::vector<float> light = read(s, {SampleStream::Light, SampleStream::LightPoint}, 8);
  s.accept();
  for (int k = 0; k < 50; ++k) {
    s.start_iteration();
    std::vector<float> light2 = read(s, {SampleStream::Light, SampleStream::LightPoint}, 8 + k % 4);
    s.accept();
    EXPECT_NE(light2[0], light[0]);
    light = light2;
  }
  // The camera numbers as they stand after 50 accepted light-only proposals, at their
  // dimensions: a 1D draw at position p is component 0 of p, a 2D draw both components.
  for (uint32_t i = 0; i < 8; ++i) {
    ASSERT_EQ(s.peek(SampleStream::Camera, 2 * i, 0), camera[3 * i]) << "camera 1D draw " << i;
    ASSERT_EQ(s.peek(SampleStream::Camera, 2 * i + 1, 0), camera[3 * i + 1]) << "camera 2D draw " << i;
    ASSERT_EQ(s.peek(SampleStream::Camera, 2 * i + 1, 1), camera[3 * i + 2]) << "camera 2D draw " << i;
  }
}

// Small steps: the change of a number, wrapped to [-0.5, 0.5), is a normal of the set
// width (here 0.01) with mean 0, and a number not read for k steps moves by sqrt(k)
// widths at once. 200,000 steps: the mean is within 4.4 standard errors (false alarm
// 1e-5), the width within 2% (its standard error is 0.16%), and the counts of positive
// and negative steps within 4.4 sigma of equal. The depth choice (Strategy stream,
// position 0) never moves on a small step.
TEST(PssSampler, SmallStepsAreSymmetricWithTheSetWidth) {
  const float width = 0.01f;
  for (int skip : {1, 4}) {
    PssSampler s(3, 5, width, 0.0f);
    s.start_iteration();
    s.start_stream(SampleStream::Strategy, 0);
    float depth_choice = s.get_1d();
    s.start_stream(SampleStream::Camera, 0);
    float x = s.get_1d();
    s.accept();
    const int n = 200000 / skip;
    double sum = 0, sum2 = 0;
    int positive = 0;
    for (int k = 0; k < n; ++k) {
      for (int j = 1; j < skip; ++j) {  // steps that do not read the number
        s.start_iteration();
        s.accept();
      }
      s.start_iteration();
      s.start_stream(SampleStream::Strategy, 0);
      ASSERT_EQ(s.get_1d(), depth_choice);
      s.start_stream(SampleStream::Camera, 0);
      float y = s.get_1d();
      ASSERT_GE(y, 0.0f);
      ASSERT_LT(y, 1.0f);
      double d = double(y) - x;
      d -= std::floor(d + 0.5);
      sum += d;
      sum2 += d * d;
      positive += d > 0;
      s.accept();
      x = y;
    }
    double sigma = width * std::sqrt(double(skip));
    double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_LT(std::fabs(mean), 4.4 * sigma / std::sqrt(double(n))) << "skip " << skip;
    EXPECT_NEAR(sd / sigma, 1.0, 0.02) << "skip " << skip;
    EXPECT_LT(std::fabs(positive - n / 2.0), 4.4 * std::sqrt(n / 4.0)) << "skip " << skip;
  }
}

// Large steps draw every number afresh, uniformly (the depth choice too).
TEST(PssSampler, LargeStepsAreFresh) {
  PssSampler s(5, 9, 0.01f, 1.0f);
  s.start_iteration();
  float first = read(s, kAll, 1)[0];
  s.accept();
  int same = 0;
  double sum = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    s.start_iteration();
    ASSERT_TRUE(s.large_step());
    s.start_stream(SampleStream::Strategy, 0);
    float v = s.get_1d();
    sum += v;
    same += v == first;
    s.accept();
  }
  EXPECT_LT(same, 3);
  EXPECT_NEAR(sum / n, 0.5, 4.4 * std::sqrt(1.0 / 12 / n));  // false alarm 1e-5
}

}  // namespace test_pss_sampler
