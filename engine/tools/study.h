// `rendezvous study`: the speed-for-accuracy trade, measured. Each scene is rendered
// with each integrator at several time budgets; each image's relative MSE against a long
// reference (made with one integrator, cached next to the scene) goes into a CSV file, a
// Markdown table and one log-log error-vs-time plot per scene (PNG, drawn by
// plot_study.py with matplotlib). docs/trade.md is its output on scenes/.
#pragma once
#include <string>
#include <vector>
#include "equal_time.h"

namespace rdv_tools {

struct StudyOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> integrators = {"path", "bdpt", "pssmlt", "mmlt"};
  std::vector<double> budgets = {5, 15, 45, 135};  // seconds, rendered in increasing order
  double reference_seconds = 0;                    // 0: 4 x the largest budget
  std::string reference_integrator = "bdpt";
  std::string out_dir = "study";  // study.csv and one <scene>.png per scene
  std::string markdown;           // "": <out_dir>/study.md
  std::string cache_dir;          // "": .study-cache next to each scene
  int width = 128;
  int threads = 0;
  int seed = 17;
  bool plots = true;
  bool fresh = false;  // render these scenes' rows again (otherwise rows already in study.csv are kept;
                       // other scenes' rows are kept either way)
  bool quiet = false;  // no progress bar

  // The noise-target check (`--halt-targets`, halt_check.h): instead of the time budgets,
  // each scene and integrator renders with each noise target, and the true error at the
  // halt is compared with the target.
  struct HaltTarget {
    double value = 0;
    bool of_reference_noise = false;  // "10x": 10 times the scene's reference noise
  };
  std::vector<HaltTarget> halt_targets;
  double halt_cap = 0;  // seconds a render may run without reaching its target; 0: the largest budget
  int halt_seeds = 1;   // seeds seed, seed + 1, ...
};

// Parses `rendezvous study ...` (argv[0] = "rendezvous", argv[1] = "study"). Returns
// false with a message naming the argument and the problem in `error`.
bool parse_study_options(int argc, char **argv, StudyOptions &options, std::string &error);

// Runs the study; returns the process exit code (0: every file written, 1: an error,
// printed to stderr naming the scene, integrator or file).
int run_study(const StudyOptions &options);

// The study's scene files, read and checked (names distinct, no comma), and the output
// directory made. Throws std::runtime_error naming the file.
std::vector<EqualTimeScene> load_study_scenes(const StudyOptions &options);
// The reference every measurement of `scene` is made against (cached next to it or in --cache).
ReferenceRequest study_reference(const StudyOptions &options, const EqualTimeScene &scene);

// The whole subcommand: parse, then run (2 on bad arguments).
int study_main(int argc, char **argv);

void print_study_usage();

}  // namespace rdv_tools
