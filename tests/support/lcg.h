// A fixed linear congruential sequence (Numerical Recipes' constants) for tests that draw
// reproducible cases: uniform values in [0, 1) with 24 bits, the same on every machine.
#pragma once
#include <cstdint>

namespace rdv::test {

struct Lcg {
  uint32_t state;
  float next() {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  }
};

}  // namespace rdv::test
