#include "study_output.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include "rendezvous.h"

namespace rdv_tools {

std::string format_seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", s);
  return b;
}

std::string format_error(double e) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", e);
  return b;
}

std::string format_clock(double s) {
  char b[32];
  int t = int(std::lround(std::max(0.0, s)));
  std::snprintf(b, sizeof b, "%d:%02d", t / 60, t % 60);
  return b;
}

void write_markdown(const std::string &file, const std::string &table, const std::string &section,
                    const std::string &heading) {
  const std::string begin = "<!-- " + section + ":begin -->", end = "<!-- " + section + ":end -->";
  std::string text;
  {
    std::ifstream in(file);
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  size_t b = text.find(begin), e = text.find(end);
  if (b != std::string::npos && e != std::string::npos && e > b) {
    text = text.substr(0, b + begin.size()) + "\n" + table + text.substr(e);
  } else {
    text = "# " + heading + "\n\n" + table;
  }
  std::ofstream out(file);
  out << text;
  if (!out) throw std::runtime_error(file + ": cannot write");
}

std::vector<std::vector<std::string>> read_csv_records(const std::string &file, const std::string &header,
                                                       size_t fields) {
  std::vector<std::vector<std::string>> records;
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != header) return records;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string item; std::getline(ss, item, ',');) f.push_back(item);
    if (!line.empty() && line.back() == ',') f.push_back("");
    if (f.size() == fields) records.push_back(std::move(f));
  }
  return records;
}

void write_csv_lines(const std::string &file, const std::string &header, const std::vector<std::string> &lines) {
  const std::string partial = file + ".partial";
  {
    std::ofstream out(partial);
    out << header << "\n";
    for (const std::string &line : lines) out << line << "\n";
    if (!out) throw std::runtime_error(file + ": cannot write");
  }
  std::filesystem::rename(partial, file);
}

bool check_integrators(const std::vector<std::string> &names, std::string &error) {
  rdv_scene *scene = nullptr;
  if (rdv_scene_create(&scene) != RDV_OK) {
    error = rdv_last_error();
    return false;
  }
  bool ok = rdv_scene_set_camera(scene, "{}") == RDV_OK;  // a session needs one; the default camera
  if (!ok) error = rdv_last_error();
  for (const std::string &name : names) {
    if (!ok) break;
    nlohmann::json settings = {{"width", 1}, {"height", 1}, {"samples", 1}, {"integrator", name}};
    rdv_session *session = nullptr;
    if (rdv_session_create(scene, settings.dump().c_str(), &session) != RDV_OK) {
      error = "integrator '" + name + "': " + rdv_last_error();
      ok = false;
      break;
    }
    rdv_session_destroy(session);
  }
  rdv_scene_destroy(scene);
  return ok;
}

StudyProgress::StudyProgress(double planned, int renders, bool quiet)
    : planned_(std::max(planned, 1e-9)), renders_(renders), quiet_(quiet), tty_(isatty(2)) {}

void StudyProgress::update(double done_in_render, const std::string &what) {
  if (quiet_ || !tty_) return;
  show(done_ + done_in_render, what, false);
}

void StudyProgress::finish_render(double planned_seconds, const std::string &what) {
  done_ += planned_seconds;
  ++finished_;
  if (quiet_) return;
  show(done_, what, true);
}

void StudyProgress::show(double done, const std::string &what, bool render_done) {
  const double f = std::min(1.0, done / planned_);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int bar = int(f * 30);
  std::string left = f > 0.01 ? "about " + format_clock(wall / f - wall) + " left" : "";
  if (tty_)
    std::fprintf(stderr, "\r\033[K[%-30s] %3d%%  %d/%d  %s  %s  %s", std::string(bar, '#').c_str(), int(f * 100),
                 finished_ + (render_done ? 0 : 1), renders_, what.c_str(), format_clock(wall).c_str(), left.c_str());
  else if (render_done)
    std::fprintf(stderr, "rendezvous study: %3d%%  %d/%d  %s  %s  %s\n", int(f * 100), finished_, renders_,
                 what.c_str(), format_clock(wall).c_str(), left.c_str());
  if (render_done && tty_ && finished_ == renders_) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace rdv_tools
