// The random sequence of a sample depends on (seed, pixel, sample index) only, so an
// image is bit-identical on 1 and 2 threads, and a different seed gives a different one.
#include <gtest/gtest.h>
#include <cstring>
#include "render_helpers.h"

namespace test_determinism {

using namespace rdv::test;

TEST(Determinism, SameImageOnOneAndTwoThreads) {
  std::string scene = source_path("scenes/cornell_box.json");
  Image a = render_file(scene, R"({"width":48,"height":48,"samples":8,"threads":1,"seed":3})");
  Image b = render_file(scene, R"({"width":48,"height":48,"samples":8,"threads":2,"seed":3})");
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  EXPECT_EQ(0, std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)));
  Image c = render_file(scene, R"({"width":48,"height":48,"samples":8,"threads":2,"seed":4})");
  EXPECT_NE(0, std::memcmp(a.rgba.data(), c.rgba.data(), a.rgba.size() * sizeof(float)));
}

TEST(Determinism, IndependentSamplerToo) {
  std::string scene = source_path("scenes/cornell_box.json");
  Image a = render_file(scene, R"({"width":32,"height":32,"samples":4,"threads":1,"sampler":"independent"})");
  Image b = render_file(scene, R"({"width":32,"height":32,"samples":4,"threads":2,"sampler":"independent"})");
  EXPECT_EQ(0, std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)));
}

}  // namespace test_determinism
