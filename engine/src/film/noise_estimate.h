// The noise of a frame, estimated from two independent half images of it (Cycles'
// adaptive-sampling idea; in Monte Carlo terms, two replicates). The image is
// I = (1 - f) A + f B, where half B holds a share f of the samples (path, bdpt: the odd
// camera samples, from a second, independently scrambled replicate of the sequence,
// each with its light path's splats; MLT: the odd chains, and with direct light left to the
// path tracer also its odd camera samples, whose variance adds to the chains').
// A and B are independent estimates with variances s^2 / n_A and s^2 / n_B, so
// E[(A - B)^2] f (1 - f) = s^2 / n = Var(I): the squared difference of the halves, scaled,
// estimates the variance of each pixel of the image without a reference. Per-pixel
// variance of the samples could not: BDPT's and MLT's splats are no pixel's samples,
// and MLT's samples are correlated. Divided by (I^2 + 0.01) and averaged over pixels
// and channels, it estimates the relative MSE that docs/trade.md measures against a
// reference.
#pragma once
#include "film/film.h"

namespace rdv {

// The estimated relative variance of one pixel, averaged over its channels: the variance
// v = (A - B)^2 f (1 - f), plus the frame's scale error (MLT's b) times I^2, over
// (max(0, I^2 - v) + 0.01), the reference's square estimated without the noise in I^2
// (and, where the halves differ by more than 2x, at most 2 min(A, B)^2: an outlier in one
// half must not brighten the denominator of its own error).
// False when the pixel has no estimate yet (a half without samples).
bool pixel_relative_variance(const PixelSum &pixel, const HalfSum &half, const SplatSums &splats, const SplatSums &half_splats,
                             const FrameState &frame, double *relative_variance);

}  // namespace rdv
