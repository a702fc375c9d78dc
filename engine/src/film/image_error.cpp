#include "film/image_error.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rdv {

namespace {

template <typename Reference>
double relative_mse_of(std::span<const float> image, std::span<const Reference> reference) {
  if (image.size() != reference.size())
    throw std::invalid_argument("relative MSE: the image has " + std::to_string(image.size()) +
                                " values, the reference " + std::to_string(reference.size()));
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const double x = image[i], r = double(reference[i]);
    if (!std::isfinite(x) || !std::isfinite(r))
      throw std::invalid_argument("relative MSE: value " + std::to_string(i) + " is not finite (" +
                                  (std::isfinite(x) ? "reference" : "image") + ")");
    sum += (x - r) * (x - r) / (r * r + kRelativeMseEpsilon);
  }
  return image.empty() ? 0.0 : sum / double(image.size());
}

}  // namespace

double relative_mse(std::span<const float> image, std::span<const double> reference) {
  return relative_mse_of(image, reference);
}

double relative_mse(std::span<const float> image, std::span<const float> reference) {
  return relative_mse_of(image, reference);
}

}  // namespace rdv
