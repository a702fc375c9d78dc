// The image positions of Veach's lens subpath mutation (Veach 1997, sec. 11.4.4): a chain
// cycles through the pixels of its sample region in a random order (a new permutation each
// cycle, Kensler's hash permutation, so no table), a point uniform in each pixel. Every
// pixel is proposed once per cycle, so no region of the image is left to the other
// mutations' random walk. Each position is uniform on the region taken alone (its pixel
// uniform over the cycle's permutations, the point uniform in it); the sequence is not
// independent (no pixel twice in a cycle), which is what the stratification changes about
// the chain (docs/mlt.md, "The lens subpath mutation").
#pragma once
#include <cmath>
#include <cstdint>
#include "core/hash.h"
#include "core/math.h"

namespace rdv::mlt {

class ImageStrata {
 public:
  ImageStrata() = default;
  // The sample region [origin, origin + size) in raster units, cut into unit cells (the
  // last row and column may stick out of it: a point there is outside, no proposal).
  ImageStrata(Vec2 origin, Vec2 size, uint32_t seed)
      : origin_(origin), seed_(seed), columns_(cells(size.x)), rows_(cells(size.y)) {}

  // The next position of the sequence; the jitter in the cell from rng.
  Vec2 next(Pcg32 &rng) {
    const uint32_t count = columns_ * rows_;
    if (count == 0) return origin_;
    const uint32_t cycle = uint32_t(index_ / count), i = uint32_t(index_ % count);
    ++index_;
    const uint32_t cell = permute(i, count, hash_combine(seed_, cycle));
    const float jx = rng.next_float(), jy = rng.next_float();
    return {origin_.x + float(cell % columns_) + jx, origin_.y + float(cell / columns_) + jy};
  }

  // Kensler's permutation of 0 .. l-1 keyed by p (Correlated Multi-Jittered Sampling, 2013):
  // a hash on the next power of two, cycle-walked into [0, l).
  static uint32_t permute(uint32_t i, uint32_t l, uint32_t p) {
    uint32_t w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    do {
      i ^= p;
      i *= 0xe170893d;
      i ^= p >> 16;
      i ^= (i & w) >> 4;
      i ^= p >> 8;
      i *= 0x0929eb3f;
      i ^= p >> 23;
      i ^= (i & w) >> 1;
      i *= 1 | p >> 27;
      i *= 0x6935fa69;
      i ^= (i & w) >> 11;
      i *= 0x74dcb303;
      i ^= (i & w) >> 2;
      i *= 0x9e501cc3;
      i ^= (i & w) >> 2;
      i *= 0xc860a3df;
      i &= w;
      i ^= i >> 5;
    } while (i >= l);
    return (i + p) % l;
  }

 private:
  static uint32_t cells(float extent) { return extent > 0 && extent < 65536.0f ? uint32_t(std::ceil(extent)) : 0u; }
  Vec2 origin_{0, 0};
  uint32_t seed_ = 0, columns_ = 0, rows_ = 0;
  uint64_t index_ = 0;
};

}  // namespace rdv::mlt
