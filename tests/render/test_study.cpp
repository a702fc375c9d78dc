// `rendezvous study` (engine/tools/study.cpp): a tiny study writes its CSV, table and
// plots with the rows asked for and keeps them on a second run; the error falls with
// the time budget; the reference cache follows the scene's bytes; bad arguments and
// missing files are refused with a message naming them.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include "equal_time.h"
#include "study.h"

namespace test_study {

namespace fs = std::filesystem;
using rdv_tools::StudyOptions;

namespace {

const std::string kScenes = std::string(RDV_SOURCE_DIR) + "/scenes/";

std::string read_text(const fs::path &p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> lines(const std::string &text) {
  std::vector<std::string> v;
  std::stringstream ss(text);
  std::string l;
  while (std::getline(ss, l)) v.push_back(l);
  return v;
}

// A fresh directory per test under the system's temporary directory.
fs::path scratch(const std::string &name) {
  fs::path d = fs::temp_directory_path() / ("rdv_study_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// parse_study_options on a command line (after "rendezvous study").
bool parse(std::vector<std::string> args, StudyOptions &o, std::string &error) {
  args.insert(args.begin(), {"rendezvous", "study"});
  std::vector<char *> argv;
  for (std::string &a : args) argv.push_back(a.data());
  return rdv_tools::parse_study_options(int(argv.size()), argv.data(), o, error);
}

// The CSV's value in `column` of every data row.
std::vector<std::string> column(const std::string &csv, int column) {
  std::vector<std::string> values;
  std::vector<std::string> ls = lines(csv);
  for (size_t i = 1; i < ls.size(); ++i) {
    std::stringstream ss(ls[i]);
    std::string field;
    for (int c = 0; c <= column; ++c) std::getline(ss, field, ',');
    values.push_back(field);
  }
  return values;
}

// A quiet study of the Cornell box, 16 pixels wide, writing under `dir`.
StudyOptions tiny_study(const fs::path &dir, std::vector<std::string> integrators, std::vector<double> budgets,
                        double reference_seconds) {
  StudyOptions o;
  o.scenes = {kScenes + "cornell_box.json"};
  o.integrators = std::move(integrators);
  o.budgets = std::move(budgets);
  o.reference_seconds = reference_seconds;
  o.width = 16;
  o.out_dir = (dir / "out").string();
  o.cache_dir = (dir / "cache").string();
  o.quiet = true;
  return o;
}

}  // namespace

TEST(Study, WritesCsvTableAndPlotsAndKeepsRowsOnASecondRun) {
  const fs::path dir = scratch("files");
  StudyOptions o = tiny_study(dir, {"path", "bdpt"}, {0.2, 0.4}, 1);
  ASSERT_EQ(rdv_tools::run_study(o), 0);
  const std::string csv = read_text(dir / "out" / "study.csv");
  std::vector<std::string> ls = lines(csv);
  ASSERT_EQ(ls.size(), 5u) << csv;
  EXPECT_EQ(ls[0].rfind("scene,scene_hash,width,height,seed,integrator,budget_s,time_s,spp,rel_mse", 0), 0u);
  EXPECT_EQ(column(csv, 0), (std::vector<std::string>{"cornell_box", "cornell_box", "cornell_box", "cornell_box"}));
  EXPECT_EQ(column(csv, 5), (std::vector<std::string>{"path", "path", "bdpt", "bdpt"}));
  EXPECT_EQ(column(csv, 6), (std::vector<std::string>{"0.2", "0.4", "0.2", "0.4"}));
  for (const std::string &e : column(csv, 9)) {
    const double v = std::stod(e);
    EXPECT_TRUE(std::isfinite(v) && v > 0) << e;
  }
  const std::string md = read_text(dir / "out" / "study.md");
  EXPECT_NE(md.find("| scene | integrator | 0.2 s | 0.4 s |"), std::string::npos) << md;
  EXPECT_NE(md.find("| cornell_box | path |"), std::string::npos) << md;
  EXPECT_NE(md.find("| cornell_box | bdpt |"), std::string::npos) << md;
  EXPECT_NE(md.find("](cornell_box.png)"), std::string::npos) << md;
  const std::string png = read_text(dir / "out" / "cornell_box.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "cache"), fs::directory_iterator{}), 1);

  // Second run, same settings: nothing is rendered again (the same measurements), and
  // the table goes between the markers of an existing file.
  std::ofstream(dir / "doc.md") << "# Doc\n\nprose\n\n<!-- study:begin -->\nOLD TABLE\n<!-- study:end -->\n\nmore prose\n";
  o.markdown = (dir / "doc.md").string();
  ASSERT_EQ(rdv_tools::run_study(o), 0);
  EXPECT_EQ(read_text(dir / "out" / "study.csv"), csv);
  const std::string doc = read_text(dir / "doc.md");
  EXPECT_EQ(doc.rfind("# Doc\n\nprose\n\n<!-- study:begin -->\n", 0), 0u) << doc;
  EXPECT_EQ(doc.find("OLD TABLE"), std::string::npos) << doc;
  EXPECT_NE(doc.find("](out/cornell_box.png)"), std::string::npos) << doc;
  EXPECT_NE(doc.find("<!-- study:end -->\n\nmore prose\n"), std::string::npos) << doc;
  fs::remove_all(dir);
}

// Path tracing on the Cornell box at 0.25 s and 2 s: 8x the time, ~8x the samples and
// ~1/8 the error. The longer render's error exceeding the shorter's needs the relMSE of
// 16x16x3 values to be off by more than 2.8x (its relative spread is a few percent here):
// false-alarm rate far below 1e-6, as long as the longer render gets at least twice the
// samples (checked first, so a starved machine shows as that, not as a wrong error).
TEST(Study, ErrorFallsWithTheBudget) {
  const fs::path dir = scratch("falls");
  StudyOptions o = tiny_study(dir, {"path"}, {0.25, 2}, 4);
  o.plots = false;
  ASSERT_EQ(rdv_tools::run_study(o), 0);
  const std::string csv = read_text(dir / "out" / "study.csv");
  std::vector<std::string> spp = column(csv, 8), err = column(csv, 9);
  ASSERT_EQ(spp.size(), 2u) << csv;
  ASSERT_GE(std::stod(spp[1]), 2 * std::stod(spp[0])) << csv;
  EXPECT_LT(std::stod(err[1]), std::stod(err[0])) << csv;
  fs::remove_all(dir);
}

TEST(Study, ReferenceCacheFollowsTheSceneAndSettings) {
  rdv_tools::EqualTimeScene a = rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 32);
  rdv_tools::ReferenceRequest r{"bdpt", 60, "/cache"};
  const std::string file = rdv_tools::reference_cache_file(a, r);
  EXPECT_EQ(file.rfind("/cache/cornell_box-", 0), 0u) << file;
  EXPECT_EQ(rdv_tools::reference_cache_file(a, r), file);
  rdv_tools::EqualTimeScene changed = a;
  changed.text += " ";
  EXPECT_NE(rdv_tools::reference_cache_file(changed, r), file);
  rdv_tools::ReferenceRequest longer = r, other = r;
  longer.seconds = 120;
  other.integrator = "path";
  EXPECT_NE(rdv_tools::reference_cache_file(a, longer), file);
  EXPECT_NE(rdv_tools::reference_cache_file(a, other), file);
  EXPECT_NE(rdv_tools::reference_cache_file(rdv_tools::load_equal_time_scene(kScenes + "cornell_box.json", 64), r),
            file);
}

TEST(Study, BadArgumentsAreRefusedNamingThem) {
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{}, "no scene given"},
      {{"s.json", "--budgets", "1,x"}, "--budgets 1,x: 'x' is not a positive number of seconds"},
      {{"s.json", "--budgets", "1,-2"}, "'-2' is not a positive number"},
      {{"s.json", "--budgets", "nan"}, "'nan' is not a positive number"},
      {{"s.json", "--budgets", "1,"}, "'' is not a positive number"},
      {{"s.json", "--budgets", "2,2"}, "a budget twice"},
      {{"s.json", "--reference", "0"}, "--reference 0: not a positive number of seconds"},
      {{"s.json", "--integrators", "path,,bdpt"}, "an empty name"},
      {{"s.json", "--integrators", "path,path"}, "a name twice"},
      {{"s.json", "--width", "0"}, "--width 0: not a whole number"},
      {{"s.json", "--seed", "1.5"}, "--seed 1.5: not a whole number from 0"},
      {{"s.json", "--frobnicate"}, "unknown option --frobnicate"},
      {{"s.json", "--out"}, "--out needs a value"},
      {{"s.json", "--halt-targets", "0.01,-1"}, "'-1' is neither a positive relative MSE nor a positive multiple"},
      {{"s.json", "--halt-targets", "x"}, "'x' is neither"},
      {{"s.json", "--halt-cap", "0"}, "--halt-cap 0: not a positive number of seconds"},
      {{"s.json", "--halt-seeds", "0"}, "--halt-seeds 0: not a whole number from 1"},
  };
  for (const Case &c : cases) {
    StudyOptions o;
    std::string error;
    EXPECT_FALSE(parse(c.args, o, error)) << c.message;
    EXPECT_NE(error.find(c.message), std::string::npos) << "got: " << error;
  }
  StudyOptions o;
  std::string error;
  EXPECT_TRUE(parse({"a.json", "b.json", "--budgets", "9,1,3", "--integrators", "bdpt"}, o, error)) << error;
  EXPECT_EQ(o.scenes, (std::vector<std::string>{"a.json", "b.json"}));
  EXPECT_EQ(o.budgets, (std::vector<double>{1, 3, 9}));
  EXPECT_TRUE(parse({"a.json", "--halt-targets", "0.01,10x", "--halt-seeds", "2"}, o, error)) << error;
  ASSERT_EQ(o.halt_targets.size(), 2u);
  EXPECT_EQ(o.halt_targets[0].value, 0.01);
  EXPECT_FALSE(o.halt_targets[0].of_reference_noise);
  EXPECT_EQ(o.halt_targets[1].value, 10);
  EXPECT_TRUE(o.halt_targets[1].of_reference_noise);
  EXPECT_EQ(o.halt_seeds, 2);
}

// The noise-target check (halt_check.cpp) on the Cornell box, 16 pixels wide: path
// tracing with a target of 10x the reference's noise stops on it within the 4 s cap (it
// gets there in ~1/20 of the reference's time), with a finite estimate below the target
// and a true error measured; a row per seed, the table between the markers.
TEST(Study, HaltCheckMeasuresTheErrorAtTheHalt) {
  const fs::path dir = scratch("halt");
  StudyOptions o = tiny_study(dir, {"path"}, {1}, 2);
  o.halt_targets = {{10, true}};
  o.halt_cap = 4;
  o.halt_seeds = 2;
  std::ofstream(dir / "doc.md") << "# Doc\n\n<!-- halt:begin -->\nOLD\n<!-- halt:end -->\n";
  o.markdown = (dir / "doc.md").string();
  ASSERT_EQ(rdv_tools::run_study(o), 0);
  const std::string csv = read_text(dir / "out" / "halt.csv");
  ASSERT_EQ(lines(csv).size(), 3u) << csv;
  EXPECT_EQ(column(csv, 4), (std::vector<std::string>{"17", "18"}));
  EXPECT_EQ(column(csv, 8), (std::vector<std::string>{"1", "1"})) << "stopped on the target: " << csv;
  std::vector<std::string> target = column(csv, 6), estimate = column(csv, 11), error = column(csv, 12);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_LT(std::stod(estimate[i]), std::stod(target[i])) << csv;
    EXPECT_TRUE(std::isfinite(std::stod(error[i])) && std::stod(error[i]) > 0) << csv;
  }
  const std::string doc = read_text(dir / "doc.md");
  EXPECT_EQ(doc.find("OLD"), std::string::npos) << doc;
  EXPECT_NE(doc.find("| cornell_box | path | 17 |"), std::string::npos) << doc;
  EXPECT_NE(doc.find("2 of 2 renders stopped on their target"), std::string::npos) << doc;
  fs::remove_all(dir);
}

TEST(Study, MissingSceneOrUnknownIntegratorStopsBeforeRendering) {
  const fs::path dir = scratch("refusals");
  StudyOptions o = tiny_study(dir, {"path"}, {0.1}, 1);
  o.scenes = {kScenes + "cornell_box.json", (dir / "no_such_scene.json").string()};
  testing::internal::CaptureStderr();
  EXPECT_EQ(rdv_tools::run_study(o), 1);
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("no_such_scene.json: cannot read the file"), std::string::npos) << err;

  std::ofstream(dir / "broken.json") << "{ not json";
  o.scenes = {(dir / "broken.json").string()};
  testing::internal::CaptureStderr();
  EXPECT_EQ(rdv_tools::run_study(o), 1);
  err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("broken.json: not a JSON scene"), std::string::npos) << err;

  o.scenes = {kScenes + "cornell_box.json"};
  o.integrators = {"path", "pathh"};
  testing::internal::CaptureStderr();
  EXPECT_EQ(rdv_tools::run_study(o), 1);
  err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("unknown integrator 'pathh'"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "cache")) << "nothing rendered";
  fs::remove_all(dir);
}

}  // namespace test_study
