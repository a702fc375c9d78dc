// The error of an image against a reference: relative MSE, the figure the convergence
// study (`rendezvous study`, docs/trade.md), the noise-target halt and the benchmarks
// all quote. Mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01) (pbrt's and
// Mitsuba's convention: relative where the reference is bright, absolute below ~0.1,
// so black pixels neither divide by zero nor dominate).
#pragma once
#include <span>

namespace rdv {

// The regulariser added to ref^2 in the denominator.
constexpr double kRelativeMseEpsilon = 0.01;

// `image` and `reference` hold the same channels in the same order (e.g. RGB, no
// alpha). Throws std::invalid_argument when the sizes differ, and when a value of
// either is NaN or infinite (naming its index), so the result is never NaN. An empty
// image has error 0.
double relative_mse(std::span<const float> image, std::span<const double> reference);
double relative_mse(std::span<const float> image, std::span<const float> reference);

}  // namespace rdv
