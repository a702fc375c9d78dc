// `rendezvous study --halt-targets ...`: is the noise-target halt honest on these scenes?
// Each scene is rendered with each integrator and each noise target (a time cap in case
// the target is out of reach); the true relative MSE of the halted image is measured
// against the study's long reference, less the reference's own noise, and set beside the
// target and beside the engine's estimate. docs/trade.md holds its output on scenes/.
#pragma once
#include "study.h"

namespace rdv_tools {

// Writes DIR/halt.csv and the table (into --markdown between <!-- halt:begin --> and
// <!-- halt:end -->, or DIR/halt.md). Returns the process exit code (0: written, 1: an
// error printed to stderr naming the scene, integrator or file). An integrator that
// refuses a scene is listed with its message, not an error.
int run_halt_check(const StudyOptions &options);

}  // namespace rdv_tools
