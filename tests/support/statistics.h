// Two-sample tests for images rendered K times with independent seeds: per-block
// Welch t-tests, the way to check that two integrators converge to the same image
// (../shared/guides/testing.md). Student's t distribution via the incomplete beta.
#pragma once
#include <string>
#include <vector>

namespace rdv::test {

// Regularised incomplete beta I_x(a, b) (Numerical Recipes' continued fraction).
double incomplete_beta(double a, double b, double x);
// Two-sided tail probability P(|T| > t) for Student's t with dof degrees of freedom.
double student_t_two_sided(double t, double dof);

struct BlockComparison {
  int blocks = 0, failed = 0;
  double worst_p = 1, worst_t = 0, mean_ratio = 1;
  std::string detail;
};

// runs_a / runs_b: K images each (RGB summed per pixel, row-major width x height).
// Compares every block of block x block pixels with Welch's t-test; a block fails when
// its two-sided p-value is below alpha_per_block.
BlockComparison compare_blocks(const std::vector<std::vector<double>> &runs_a,
                               const std::vector<std::vector<double>> &runs_b, int width, int height, int block,
                               double alpha_per_block);

// The brightness of runs_a against runs_b: each run's mean pixel, the mean over the runs
// and its standard error, and z = (mean_a - mean_b) / (their combined standard error).
struct BrightnessComparison {
  double mean_a = 0, mean_b = 0, error = 0, z = 0;
  double error_a = 0, error_b = 0;  // each side's standard error of its mean (error: both)
};
BrightnessComparison compare_brightness(const std::vector<std::vector<double>> &runs_a,
                                        const std::vector<std::vector<double>> &runs_b);

}  // namespace rdv::test
