// Analytic density grids for tests of grid media, as scene-file "grid" objects.
#pragma once
#include <nlohmann/json.hpp>

namespace rdv::test {

// A cloud of three Gaussian puffs on an n^3 grid filling `bounds` ([[min],[max]]),
// zero in the outer shell (so the majorant cells there are empty).
nlohmann::json puff_grid(int n, const nlohmann::json &bounds);

}  // namespace rdv::test
