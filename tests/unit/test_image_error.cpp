// relative_mse (film/image_error.h): known values, the regulariser, and refusals
// (mismatched sizes, NaN / Inf) instead of a NaN result.
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>
#include "film/image_error.h"

namespace test_image_error {

using rdv::relative_mse;

TEST(ImageError, KnownValues) {
  // (2-1)^2/(1+0.01) and (0-0)^2/(0+0.01) and (0.1-0)^2/0.01 = 1, mean of the three.
  std::vector<float> x = {2.0f, 0.0f, 0.1f};
  std::vector<double> ref = {1.0, 0.0, 0.0};
  const double expected = (1.0 / 1.01 + 0.0 + double(0.1f) * double(0.1f) / 0.01) / 3.0;
  EXPECT_NEAR(relative_mse(x, ref), expected, 1e-12);
  std::vector<float> reff(ref.begin(), ref.end());
  EXPECT_NEAR(relative_mse(x, reff), expected, 1e-12);
}

TEST(ImageError, IdenticalImagesHaveNoError) {
  std::vector<float> x = {0.0f, 1e-6f, 3.5f, 1e6f};
  EXPECT_EQ(relative_mse(x, x), 0.0);
  EXPECT_EQ(relative_mse(std::vector<float>{}, std::vector<double>{}), 0.0);
}

TEST(ImageError, RelativeWhereBrightAbsoluteWhereDark) {
  // 10% off a bright pixel costs ~0.01 however bright; 0.01 off a black pixel costs 0.01.
  for (double level : {10.0, 1000.0}) {
    std::vector<float> x = {float(1.1 * level)};
    std::vector<double> ref = {level};
    EXPECT_NEAR(relative_mse(x, ref), 0.01, 1e-5) << level;
  }
  std::vector<float> x = {0.01f};
  std::vector<double> ref = {0.0};
  EXPECT_NEAR(relative_mse(x, ref), 0.01, 1e-6);
}

TEST(ImageError, RefusesMismatchedOrNonFiniteInput) {
  std::vector<float> x = {1.0f, 2.0f};
  EXPECT_THROW(relative_mse(x, std::vector<double>{1.0}), std::invalid_argument);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::vector<float> y = {1.0f, bad};
    EXPECT_THROW(relative_mse(y, std::vector<double>{1.0, 2.0}), std::invalid_argument);
    EXPECT_THROW(relative_mse(x, std::vector<double>{double(bad), 2.0}), std::invalid_argument);
  }
  try {
    std::vector<float> y = {1.0f, std::numeric_limits<float>::quiet_NaN()};
    relative_mse(y, std::vector<double>{1.0, 2.0});
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("value 1"), std::string::npos) << e.what();
  }
}

}  // namespace test_image_error
