#include "study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include "equal_time.h"
#include "film/image_error.h"
#include "halt_check.h"
#include "study_output.h"

#ifndef RDV_TOOLS_DIR
#define RDV_TOOLS_DIR "."
#endif

namespace rdv_tools {

namespace fs = std::filesystem;
using nlohmann::json;

void print_study_usage() {
  std::fprintf(stderr,
               "usage: rendezvous study SCENE.json... [options]\n"
               "  Renders each scene with each integrator at each time budget and measures the relative\n"
               "  MSE against a long reference: study.csv, a Markdown table and one error-vs-time plot\n"
               "  per scene (docs/trade.md).\n"
               "  --integrators LIST     comma-separated (default path,bdpt,pssmlt,mmlt)\n"
               "  --budgets LIST         seconds per render, comma-separated (default 5,15,45,135)\n"
               "  --reference SECONDS    time of the reference, two halves (default 4 x the largest budget)\n"
               "  --reference-integrator NAME   integrator of the reference (default bdpt)\n"
               "  --out DIR              study.csv and the plots <scene>.png (default study)\n"
               "  --markdown FILE        the table and plots; a file with <!-- study:begin --> and\n"
               "                         <!-- study:end --> has only that part replaced (default DIR/study.md)\n"
               "  --cache DIR            reference cache (default .study-cache next to each scene)\n"
               "  --width N              image width, the scene's aspect kept (default 128)\n"
               "  --threads N            worker threads (0 = all cores)\n"
               "  --seed N               seed of the timed renders (default 17)\n"
               "  --fresh                render these scenes' rows again (default: rows already in\n"
               "                         DIR/study.csv for the same scene file, settings and reference\n"
               "                         are kept; other scenes' rows are kept either way)\n"
               "  --no-plots             CSV and table only\n"
               "  --halt-targets LIST    instead of the budgets, check the noise-target halt: render with\n"
               "                         each target (a relative MSE, or Nx: N times the scene's reference\n"
               "                         noise) and compare the true error at the halt with it (halt.csv,\n"
               "                         a table between <!-- halt:begin --> / <!-- halt:end -->)\n"
               "  --halt-cap SECONDS     a halt render's time limit (default the largest budget)\n"
               "  --halt-seeds N         seeds per target, from --seed on (default 1)\n"
               "  --quiet                no progress bar\n");
}

namespace {

std::vector<std::string> split(const std::string &text, char sep) {
  std::vector<std::string> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, sep)) v.push_back(item);
  if (!text.empty() && text.back() == sep) v.push_back("");
  return v;
}

// A positive finite number, the whole text.
bool parse_seconds(const std::string &text, double &out) {
  try {
    size_t used = 0;
    out = std::stod(text, &used);
    return used == text.size() && std::isfinite(out) && out > 0;
  } catch (const std::exception &) {
    return false;
  }
}

bool parse_int(const std::string &text, int lo, int hi, int &out) {
  try {
    size_t used = 0;
    long v = std::stol(text, &used);
    if (used != text.size() || v < lo || v > hi) return false;
    out = int(v);
    return true;
  } catch (const std::exception &) {
    return false;
  }
}

// One render of the study: the CSV's row.
struct StudyRow {
  std::string scene, scene_hash, integrator, reference_integrator;
  int width = 0, height = 0, seed = 0;
  double budget = 0, seconds = 0, rel_mse = 0, reference_seconds = 0, reference_noise = 0;
  uint32_t spp = 0;
  bool same_run(const StudyRow &o) const {  // same render asked for: the measurement may be reused
    return scene == o.scene && scene_hash == o.scene_hash && integrator == o.integrator && width == o.width &&
           height == o.height && seed == o.seed && format_seconds(budget) == format_seconds(o.budget) &&
           reference_integrator == o.reference_integrator &&
           format_seconds(reference_seconds) == format_seconds(o.reference_seconds);
  }
};

const char *kCsvHeader =
    "scene,scene_hash,width,height,seed,integrator,budget_s,time_s,spp,rel_mse,reference_integrator,reference_s,"
    "reference_noise";

std::string csv_line(const StudyRow &r) {
  char b[512];
  std::snprintf(b, sizeof b, "%s,%s,%d,%d,%d,%s,%s,%.3f,%u,%.6e,%s,%s,%.6e", r.scene.c_str(), r.scene_hash.c_str(),
                r.width, r.height, r.seed, r.integrator.c_str(), format_seconds(r.budget).c_str(), r.seconds, r.spp,
                r.rel_mse, r.reference_integrator.c_str(), format_seconds(r.reference_seconds).c_str(),
                r.reference_noise);
  return b;
}

// The rows of an earlier run (a file that is missing or not a study CSV gives none).
std::vector<StudyRow> read_csv(const std::string &file) {
  std::vector<StudyRow> rows;
  for (const std::vector<std::string> &f : read_csv_records(file, kCsvHeader, 13)) {
    try {
      StudyRow r;
      r.scene = f[0];
      r.scene_hash = f[1];
      r.width = std::stoi(f[2]);
      r.height = std::stoi(f[3]);
      r.seed = std::stoi(f[4]);
      r.integrator = f[5];
      r.budget = std::stod(f[6]);
      r.seconds = std::stod(f[7]);
      r.spp = uint32_t(std::stoul(f[8]));
      r.rel_mse = std::stod(f[9]);
      r.reference_integrator = f[10];
      r.reference_seconds = std::stod(f[11]);
      r.reference_noise = std::stod(f[12]);
      if (std::isfinite(r.rel_mse)) rows.push_back(r);
    } catch (const std::exception &) {
    }
  }
  return rows;
}

void write_csv(const std::string &file, const std::vector<StudyRow> &rows) {
  std::vector<std::string> lines;
  for (const StudyRow &r : rows) lines.push_back(csv_line(r));
  write_csv_lines(file, kCsvHeader, lines);
}

// The table (one row per scene and integrator, one column per budget, the lowest error
// of each scene and budget in bold), the references, and the plots.
std::string markdown_table(const std::vector<StudyRow> &rows, const std::string &markdown_file,
                           const std::string &out_dir, bool plots) {
  std::vector<std::string> scenes;
  std::set<double> budgets;
  for (const StudyRow &r : rows) {
    if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    budgets.insert(r.budget);
  }
  std::ostringstream md;
  md << "Relative MSE (mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01)) at equal time; lowest per "
        "scene and budget in **bold**. The reference's own noise (the relative MSE of one of its two halves against "
        "their mean) is in every figure: errors near it are a floor, not the integrator's.\n\n";
  md << "| scene | integrator |";
  for (double b : budgets) md << " " << format_seconds(b) << " s |";
  md << " spp at " << format_seconds(*budgets.rbegin()) << " s |\n| --- | --- |";
  for (size_t i = 0; i <= budgets.size(); ++i) md << " ---: |";
  md << "\n";
  for (const std::string &scene : scenes) {
    std::vector<std::string> integrators;
    std::map<double, double> best;
    for (const StudyRow &r : rows)
      if (r.scene == scene) {
        if (std::find(integrators.begin(), integrators.end(), r.integrator) == integrators.end())
          integrators.push_back(r.integrator);
        best[r.budget] = best.count(r.budget) ? std::min(best[r.budget], r.rel_mse) : r.rel_mse;
      }
    for (const std::string &integrator : integrators) {
      md << "| " << scene << " | " << integrator << " |";
      std::string spp = "";
      for (double b : budgets) {
        auto it = std::find_if(rows.begin(), rows.end(), [&](const StudyRow &r) {
          return r.scene == scene && r.integrator == integrator && r.budget == b;
        });
        if (it == rows.end()) {
          md << " |";
          continue;
        }
        const bool lowest = it->rel_mse == best[b];
        md << " " << (lowest ? "**" : "") << format_error(it->rel_mse) << (lowest ? "**" : "") << " |";
        spp = std::to_string(it->spp);
      }
      md << " " << spp << " |\n";
    }
  }
  md << "\nReferences:";
  for (const std::string &scene : scenes) {
    const StudyRow &r = *std::find_if(rows.begin(), rows.end(), [&](const StudyRow &x) { return x.scene == scene; });
    md << (scene == scenes.front() ? " " : "; ") << scene << " " << r.reference_integrator << " "
       << format_seconds(r.reference_seconds) << " s (own noise " << format_error(r.reference_noise) << ", "
       << r.width << "x" << r.height << ")";
  }
  md << ".\n";
  if (plots) {
    const fs::path md_dir = fs::absolute(markdown_file).parent_path();
    md << "\n";
    for (const std::string &scene : scenes) {
      const fs::path png = fs::absolute(fs::path(out_dir) / (scene + ".png"));
      md << "![" << scene << ": relative MSE against time](" << fs::relative(png, md_dir).generic_string() << ")\n";
    }
  }
  return md.str();
}

// plot_study.py next to this file's source (or RDV_STUDY_PLOT), run by Debian's Python
// (or RDV_PYTHON): matplotlib comes from python3-matplotlib, which a pyenv python lacks.
bool write_plots(const std::string &csv, const std::string &out_dir) {
  const char *script = std::getenv("RDV_STUDY_PLOT");
  const char *python = std::getenv("RDV_PYTHON");
  std::string s = script ? script : std::string(RDV_TOOLS_DIR) + "/plot_study.py";
  std::string py = python ? python : "/usr/bin/python3";
  auto quote = [](const std::string &t) {
    std::string q = "'";
    for (char c : t) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  const std::string command = quote(py) + " " + quote(s) + " " + quote(csv) + " " + quote(out_dir);
  int rc = std::system(command.c_str());
  if (rc != 0) {
    std::fprintf(stderr,
                 "rendezvous study: the plots were not drawn (%s exited with %d); they need matplotlib "
                 "(Debian: apt-get install python3-matplotlib), or --no-plots\n",
                 command.c_str(), rc);
    return false;
  }
  return true;
}

}  // namespace

bool parse_study_options(int argc, char **argv, StudyOptions &o, std::string &error) {
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string &v) {
      if (i + 1 >= argc) {
        error = a + " needs a value";
        return false;
      }
      v = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--integrators") {
      if (!value(v)) return false;
      o.integrators = split(v, ',');
      for (const std::string &name : o.integrators)
        if (name.empty()) {
          error = "--integrators " + v + ": an empty name";
          return false;
        }
      std::set<std::string> unique(o.integrators.begin(), o.integrators.end());
      if (unique.size() != o.integrators.size()) {
        error = "--integrators " + v + ": a name twice";
        return false;
      }
    } else if (a == "--budgets") {
      if (!value(v)) return false;
      o.budgets.clear();
      for (const std::string &item : split(v, ',')) {
        double s = 0;
        if (!parse_seconds(item, s)) {
          error = "--budgets " + v + ": '" + item + "' is not a positive number of seconds";
          return false;
        }
        o.budgets.push_back(s);
      }
      std::sort(o.budgets.begin(), o.budgets.end());
      if (std::adjacent_find(o.budgets.begin(), o.budgets.end()) != o.budgets.end()) {
        error = "--budgets " + v + ": a budget twice";
        return false;
      }
    } else if (a == "--reference") {
      if (!value(v)) return false;
      if (!parse_seconds(v, o.reference_seconds)) {
        error = "--reference " + v + ": not a positive number of seconds";
        return false;
      }
    } else if (a == "--reference-integrator") {
      if (!value(v)) return false;
      o.reference_integrator = v;
    } else if (a == "--out") {
      if (!value(o.out_dir)) return false;
    } else if (a == "--markdown") {
      if (!value(o.markdown)) return false;
    } else if (a == "--cache") {
      if (!value(o.cache_dir)) return false;
    } else if (a == "--width" || a == "--threads" || a == "--seed") {
      if (!value(v)) return false;
      const int lo = a == "--width" ? 1 : 0, hi = a == "--width" ? 16384 : a == "--threads" ? 4096 : 2147483647;
      int &out = a == "--width" ? o.width : a == "--threads" ? o.threads : o.seed;
      if (!parse_int(v, lo, hi, out)) {
        error = a + " " + v + ": not a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
        return false;
      }
    } else if (a == "--halt-targets") {
      if (!value(v)) return false;
      o.halt_targets.clear();
      for (const std::string &item : split(v, ',')) {
        StudyOptions::HaltTarget t;
        t.of_reference_noise = !item.empty() && item.back() == 'x';
        if (!parse_seconds(t.of_reference_noise ? item.substr(0, item.size() - 1) : item, t.value)) {
          error = "--halt-targets " + v + ": '" + item +
                  "' is neither a positive relative MSE nor a positive multiple of the reference's noise (e.g. 10x)";
          return false;
        }
        o.halt_targets.push_back(t);
      }
    } else if (a == "--halt-cap") {
      if (!value(v)) return false;
      if (!parse_seconds(v, o.halt_cap)) {
        error = "--halt-cap " + v + ": not a positive number of seconds";
        return false;
      }
    } else if (a == "--halt-seeds") {
      if (!value(v)) return false;
      if (!parse_int(v, 1, 1000, o.halt_seeds)) {
        error = "--halt-seeds " + v + ": not a whole number from 1 to 1000";
        return false;
      }
    } else if (a == "--fresh") {
      o.fresh = true;
    } else if (a == "--no-plots") {
      o.plots = false;
    } else if (a == "--quiet") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      error = "unknown option " + a;
      return false;
    } else {
      o.scenes.push_back(a);
    }
  }
  if (o.scenes.empty()) {
    error = "no scene given";
    return false;
  }
  return true;
}

double study_reference_seconds(const StudyOptions &options) {
  return options.reference_seconds > 0 ? options.reference_seconds
                                       : 4 * *std::max_element(options.budgets.begin(), options.budgets.end());
}

std::vector<EqualTimeScene> load_study_scenes(const StudyOptions &options) {
  std::vector<EqualTimeScene> scenes;
  for (const std::string &path : options.scenes) {
    scenes.push_back(load_equal_time_scene(path, options.width));
    scenes.back().common["threads"] = options.threads;
    if (scenes.back().name.find(',') != std::string::npos)
      throw std::runtime_error(path + ": a comma in the scene's name (it names rows of the CSV file)");
    for (size_t i = 0; i + 1 < scenes.size(); ++i)
      if (scenes[i].name == scenes.back().name)
        throw std::runtime_error(path + ": two scenes named " + scenes.back().name + " (" + scenes[i].path + ")");
  }
  fs::create_directories(options.out_dir);
  return scenes;
}

ReferenceRequest study_reference(const StudyOptions &options, const EqualTimeScene &scene) {
  return {options.reference_integrator, study_reference_seconds(options),
          options.cache_dir.empty() ? (fs::path(scene.base) / ".study-cache").string() : options.cache_dir};
}

int run_study(const StudyOptions &options) {
  if (!options.halt_targets.empty()) return run_halt_check(options);
  const double reference_seconds = study_reference_seconds(options);
  // Read every scene file first: a wrong path stops the study before hours of rendering.
  std::vector<EqualTimeScene> scenes;
  try {
    scenes = load_study_scenes(options);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "rendezvous study: %s\n", e.what());
    return 1;
  }
  const std::string csv = (fs::path(options.out_dir) / "study.csv").string();
  const std::string markdown = options.markdown.empty() ? (fs::path(options.out_dir) / "study.md").string() : options.markdown;

  // The rows asked for; those an earlier run measured with the same everything are kept.
  const std::vector<StudyRow> previous = read_csv(csv);
  std::vector<StudyRow> rows;
  std::set<std::string> studied;
  for (const EqualTimeScene &s : scenes) studied.insert(s.name);
  for (const StudyRow &r : previous)  // other scenes' rows stay: a study of all scenes may run in parts
    if (!studied.count(r.scene)) rows.push_back(r);
  struct Todo {
    size_t scene;
    StudyRow row;
  };
  std::vector<Todo> todo;
  std::vector<std::vector<StudyRow>> kept(scenes.size());
  std::vector<ReferenceRequest> references;
  double planned = 0;
  int reference_renders = 0;
  for (size_t si = 0; si < scenes.size(); ++si) {
    const EqualTimeScene &s = scenes[si];
    const std::string hash = content_hash(s.text);
    for (const std::string &integrator : options.integrators)
      for (double budget : options.budgets) {
        StudyRow r;
        r.scene = s.name;
        r.scene_hash = hash;
        r.integrator = integrator;
        r.width = s.common["width"];
        r.height = s.common["height"];
        r.seed = options.seed;
        r.budget = budget;
        r.reference_integrator = options.reference_integrator;
        r.reference_seconds = reference_seconds;
        auto earlier = std::find_if(previous.begin(), previous.end(), [&](const StudyRow &p) { return p.same_run(r); });
        if (earlier != previous.end() && !options.fresh) {
          kept[si].push_back(*earlier);
        } else {
          todo.push_back({si, r});
          planned += budget;
        }
      }
    references.push_back(study_reference(options, s));
    const bool renders = !todo.empty() && todo.back().scene == si;
    if (renders && !fs::exists(reference_cache_file(s, references.back()))) {
      planned += reference_seconds;
      ++reference_renders;
    }
  }
  std::string error;
  std::vector<std::string> names = options.integrators;
  names.push_back(options.reference_integrator);
  if (!todo.empty() && !check_integrators(names, error)) {
    std::fprintf(stderr, "rendezvous study: %s\n", error.c_str());
    return 1;
  }

  StudyProgress progress(planned, int(todo.size()) + reference_renders, options.quiet);
  size_t next = 0;
  for (size_t si = 0; si < scenes.size(); ++si) {
    const EqualTimeScene &s = scenes[si];
    std::vector<StudyRow> scene_rows = kept[si];
    std::string what = s.name;
    try {
      if (next < todo.size() && todo[next].scene == si) {
        EngineScene loaded(s);
        for (const std::string &problem : loaded.problems())
          std::fprintf(stderr, "%srendezvous study: %s: warning: %s\n", options.quiet ? "" : "\r\033[K",
                       s.name.c_str(), problem.c_str());
        what = s.name + " reference (" + options.reference_integrator + ")";
        Reference reference = make_reference(s, loaded.get(), references[si], [&](int half, const rdv_progress &p) {
          progress.update(half * reference_seconds / 2 + std::min(p.elapsed_seconds, reference_seconds / 2), what);
        });
        if (!reference.from_cache) progress.finish_render(reference_seconds, what);
        for (; next < todo.size() && todo[next].scene == si; ++next) {
          StudyRow r = todo[next].row;
          what = s.name + " " + r.integrator + " " + format_seconds(r.budget) + " s";
          json settings = render_settings(s, {{"integrator", r.integrator}, {"time_limit", r.budget}, {"seed", r.seed}});
          TimedRender render = render_loaded(loaded.get(), settings, [&](const rdv_progress &p) {
            progress.update(std::min(p.elapsed_seconds, r.budget), what);
          });
          r.seconds = render.progress.elapsed_seconds;
          r.spp = render.progress.samples_done;
          r.rel_mse = rdv::relative_mse(render.rgb, reference.image);
          r.reference_noise = reference.noise;
          scene_rows.push_back(r);
          progress.finish_render(r.budget, what);
        }
      }
    } catch (const std::exception &e) {
      std::fprintf(stderr, "\nrendezvous study: %s: %s\n", what.c_str(), e.what());
      return 1;
    }
    // In the order asked for: integrators, then budgets.
    std::stable_sort(scene_rows.begin(), scene_rows.end(), [&](const StudyRow &a, const StudyRow &b) {
      auto ia = std::find(options.integrators.begin(), options.integrators.end(), a.integrator);
      auto ib = std::find(options.integrators.begin(), options.integrators.end(), b.integrator);
      return ia != ib ? ia < ib : a.budget < b.budget;
    });
    rows.insert(rows.end(), scene_rows.begin(), scene_rows.end());
    try {
      write_csv(csv, rows);  // after every scene: an interrupted study keeps what it measured
    } catch (const std::exception &e) {
      std::fprintf(stderr, "rendezvous study: %s\n", e.what());
      return 1;
    }
  }
  bool plotted = true;
  try {
    if (options.plots) plotted = write_plots(csv, options.out_dir);
    const std::string table = markdown_table(rows, markdown, options.out_dir, options.plots && plotted);
    write_markdown(markdown, table, "study", "Convergence study (`rendezvous study`)");
    if (!options.quiet) std::printf("%s", table.c_str());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "rendezvous study: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "rendezvous study: wrote %s, %s%s\n", csv.c_str(), markdown.c_str(),
               options.plots && plotted ? (" and the plots in " + options.out_dir).c_str() : "");
  return plotted ? 0 : 1;
}

int study_main(int argc, char **argv) {
  if (argc > 2 && (std::string(argv[2]) == "-h" || std::string(argv[2]) == "--help")) {
    print_study_usage();
    return 0;
  }
  StudyOptions options;
  std::string error;
  if (!parse_study_options(argc, argv, options, error)) {
    std::fprintf(stderr, "rendezvous study: %s (rendezvous study --help)\n", error.c_str());
    return 2;
  }
  return run_study(options);
}

}  // namespace rdv_tools
