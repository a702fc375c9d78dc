#include "halt_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>
#include "film/image_error.h"
#include "study_output.h"

namespace rdv_tools {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct HaltRow {
  std::string scene, scene_hash, integrator;
  int width = 0, height = 0, seed = 0;
  double target = 0, cap = 0;
  bool halted = false;  // on the target (else on the cap)
  double seconds = 0, estimate = 0, rel_mse = 0, reference_noise = 0;
  uint32_t spp = 0;
  // The image's own error: what it measures against the reference, less the reference's
  // noise (E relMSE(x, ref) = E_x + E_ref for independent renders).
  double true_error() const { return std::max(0.0, rel_mse - reference_noise); }
};

const char *kHaltHeader =
    "scene,scene_hash,width,height,seed,integrator,target,cap_s,halted,time_s,spp,estimate,rel_mse,reference_noise";

std::string halt_line(const HaltRow &r) {
  char b[512];
  std::snprintf(b, sizeof b, "%s,%s,%d,%d,%d,%s,%.6e,%s,%d,%.3f,%u,%.6e,%.6e,%.6e", r.scene.c_str(),
                r.scene_hash.c_str(), r.width, r.height, r.seed, r.integrator.c_str(), r.target,
                format_seconds(r.cap).c_str(), r.halted ? 1 : 0, r.seconds, r.spp, r.estimate, r.rel_mse,
                r.reference_noise);
  return b;
}

std::vector<HaltRow> read_halt_csv(const std::string &file) {
  std::vector<HaltRow> rows;
  for (const std::vector<std::string> &f : read_csv_records(file, kHaltHeader, 14)) {
    try {
      HaltRow r;
      r.scene = f[0];
      r.scene_hash = f[1];
      r.width = std::stoi(f[2]);
      r.height = std::stoi(f[3]);
      r.seed = std::stoi(f[4]);
      r.integrator = f[5];
      r.target = std::stod(f[6]);
      r.cap = std::stod(f[7]);
      r.halted = f[8] == "1";
      r.seconds = std::stod(f[9]);
      r.spp = uint32_t(std::stoul(f[10]));
      r.estimate = std::stod(f[11]);
      r.rel_mse = std::stod(f[12]);
      r.reference_noise = std::stod(f[13]);
      rows.push_back(r);
    } catch (const std::exception &) {
    }
  }
  return rows;
}

void write_halt_csv(const std::string &file, const std::vector<HaltRow> &rows) {
  std::vector<std::string> lines;
  for (const HaltRow &r : rows) lines.push_back(halt_line(r));
  write_csv_lines(file, kHaltHeader, lines);
}

std::string ratio_text(double r) {
  const bool within = r >= 0.5 && r <= 2;
  return within ? format_error(r) : "**" + format_error(r) + "**";
}

// One line per render, the honesty figures in bold where they leave [0.5, 2], and a summary.
std::string halt_table(const std::vector<HaltRow> &rows, const std::vector<std::string> &refused) {
  std::ostringstream md;
  md << "Noise-target halt: each render stops when its estimated relative MSE falls below the target (or at the "
        "time cap). *true* is the relative MSE against the reference less the reference's own noise; the halt is "
        "honest where true / target is within [0.5, 2] (outside in **bold**).\n\n";
  md << "| scene | integrator | seed | target | stopped on | time s | estimate | true | true / target | true / "
        "estimate |\n| --- | --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |\n";
  int halted = 0, honest = 0, estimated = 0, estimate_within = 0;
  double lo = INFINITY, hi = 0, elo = INFINITY, ehi = 0;
  for (const HaltRow &r : rows) {
    const double t = r.true_error(), over_target = t / r.target;
    const bool has_estimate = std::isfinite(r.estimate) && r.estimate > 0;
    const double over_estimate = has_estimate ? t / r.estimate : NAN;
    md << "| " << r.scene << " | " << r.integrator << " | " << r.seed << " | " << format_error(r.target) << " | "
       << (r.halted ? "target" : "time cap") << " | " << format_seconds(std::round(r.seconds * 10) / 10) << " | "
       << (has_estimate ? format_error(r.estimate) : "none") << " | " << format_error(t) << " | "
       << (r.halted ? ratio_text(over_target) : format_error(over_target)) << " | "
       << (has_estimate ? ratio_text(over_estimate) : "") << " |\n";
    if (r.halted) {
      ++halted;
      honest += over_target >= 0.5 && over_target <= 2;
      lo = std::min(lo, over_target);
      hi = std::max(hi, over_target);
    }
    if (has_estimate) {
      ++estimated;
      estimate_within += over_estimate >= 0.5 && over_estimate <= 2;
      elo = std::min(elo, over_estimate);
      ehi = std::max(ehi, over_estimate);
    }
  }
  md << "\n" << halted << " of " << rows.size() << " renders stopped on their target";
  if (halted)
    md << "; the true error within 2x of the target on " << honest << " of them (true / target from "
       << format_error(lo) << " to " << format_error(hi) << ")";
  md << ". The estimate within 2x of the true error on " << estimate_within << " of " << estimated << " renders";
  if (estimated) md << " (from " << format_error(elo) << " to " << format_error(ehi) << ")";
  md << ".\n";
  if (!refused.empty()) {
    md << "\nRefused (not an error of the halt):\n";
    for (const std::string &r : refused) md << "- " << r << "\n";
  }
  return md.str();
}

}  // namespace

int run_halt_check(const StudyOptions &options) {
  const double cap = options.halt_cap > 0 ? options.halt_cap : *std::max_element(options.budgets.begin(), options.budgets.end());
  std::vector<EqualTimeScene> scenes;
  try {
    scenes = load_study_scenes(options);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "rendezvous study: %s\n", e.what());
    return 1;
  }
  std::vector<std::string> names = options.integrators;
  names.push_back(options.reference_integrator);
  std::string error;
  if (!check_integrators(names, error)) {
    std::fprintf(stderr, "rendezvous study: %s\n", error.c_str());
    return 1;
  }
  const std::string csv = (fs::path(options.out_dir) / "halt.csv").string();
  const std::string markdown = options.markdown.empty() ? (fs::path(options.out_dir) / "halt.md").string() : options.markdown;
  std::set<std::string> studied;
  for (const EqualTimeScene &s : scenes) studied.insert(s.name);
  std::vector<HaltRow> rows;
  for (const HaltRow &r : read_halt_csv(csv))  // other scenes' rows stay: the check may run in parts
    if (!studied.count(r.scene)) rows.push_back(r);

  const int per_scene = int(options.integrators.size() * options.halt_targets.size()) * options.halt_seeds;
  double planned = 0;
  int renders = 0;
  std::vector<ReferenceRequest> references;
  for (const EqualTimeScene &s : scenes) {
    references.push_back(study_reference(options, s));
    if (!fs::exists(reference_cache_file(s, references.back()))) {
      planned += references.back().seconds;
      ++renders;
    }
    planned += per_scene * cap;
    renders += per_scene;
  }
  StudyProgress progress(planned, renders, options.quiet);
  std::vector<std::string> refused;
  for (size_t si = 0; si < scenes.size(); ++si) {
    const EqualTimeScene &s = scenes[si];
    std::string what = s.name;
    try {
      EngineScene loaded(s);
      const double reference_seconds = references[si].seconds;
      what = s.name + " reference (" + options.reference_integrator + ")";
      Reference reference = make_reference(s, loaded.get(), references[si], [&](int half, const rdv_progress &p) {
        progress.update(half * reference_seconds / 2 + std::min(p.elapsed_seconds, reference_seconds / 2), what);
      });
      if (!reference.from_cache) progress.finish_render(reference_seconds, what);
      for (const std::string &integrator : options.integrators)
        for (const StudyOptions::HaltTarget &target : options.halt_targets)
          for (int k = 0; k < options.halt_seeds; ++k) {
            HaltRow r;
            r.scene = s.name;
            r.scene_hash = content_hash(s.text);
            r.integrator = integrator;
            r.width = s.common["width"];
            r.height = s.common["height"];
            r.seed = options.seed + k;
            r.target = target.of_reference_noise ? target.value * reference.noise : target.value;
            r.cap = cap;
            r.reference_noise = reference.noise;
            what = s.name + " " + integrator + " target " + format_error(r.target);
            json settings = render_settings(
                s, {{"integrator", integrator}, {"noise_target", r.target}, {"time_limit", cap}, {"seed", r.seed}});
            TimedRender render;
            try {
              render = render_loaded(loaded.get(), settings,
                                     [&](const rdv_progress &p) { progress.update(std::min(p.elapsed_seconds, cap), what); });
            } catch (const std::runtime_error &e) {
              const std::string message = e.what();
              if (message.rfind("session: ", 0) != 0) throw;  // only a refusal to start is not an error
              refused.push_back(s.name + " " + integrator + ": " + message.substr(9));
              progress.finish_render(cap, what);
              continue;
            }
            r.halted = render.progress.noise_reached != 0;
            r.seconds = render.progress.elapsed_seconds;
            r.spp = render.progress.samples_done;
            r.estimate = render.progress.noise_estimate;
            r.rel_mse = rdv::relative_mse(render.rgb, reference.image);
            rows.push_back(r);
            progress.finish_render(cap, what);
          }
      write_halt_csv(csv, rows);  // after every scene: an interrupted check keeps what it measured
    } catch (const std::exception &e) {
      std::fprintf(stderr, "\nrendezvous study: %s: %s\n", what.c_str(), e.what());
      return 1;
    }
  }
  try {
    const std::string table = halt_table(rows, refused);
    write_markdown(markdown, table, "halt", "Noise-target halt check (`rendezvous study --halt-targets`)");
    if (!options.quiet) std::printf("%s", table.c_str());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "rendezvous study: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "rendezvous study: wrote %s and %s\n", csv.c_str(), markdown.c_str());
  return 0;
}

}  // namespace rdv_tools
