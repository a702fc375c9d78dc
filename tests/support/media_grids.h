// Analytic density grids for tests of grid media, as scene-file "grid" objects.
#pragma once
#include <nlohmann/json.hpp>

namespace rdv::test {

// A cloud of three Gaussian puffs on an n^3 grid filling `bounds` ([[min],[max]]),
// zero in the outer shell (so the majorant cells there are empty).
nlohmann::json puff_grid(int n, const nlohmann::json &bounds);

// A grid of nx x ny x nz voxels over `bounds` whose values (0.1 .. 1.9) vary from voxel to
// voxel along every axis: a smooth wave plus a fixed pseudo-random part.
nlohmann::json varied_grid(int nx, int ny, int nz, const nlohmann::json &bounds);

// The Cornell box (cornell_box.json) with a box of grid fog under its ceiling, x and y in
// [-0.9, 0.9], z in [1.3, 1.9] (varied_grid(7, 6, 5) times `density`, albedo 0.9, g 0.3);
// `volume` is merged into the fog's volume parameters (e.g. emission).
nlohmann::json cornell_grid_fog(const nlohmann::json &cornell_box, double density,
                                const nlohmann::json &volume = nlohmann::json::object());

}  // namespace rdv::test
