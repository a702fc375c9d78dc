// What `rendezvous study` and its noise-target check share: number formats, the
// progress bar, the Markdown file they write their tables into, and the check that
// every integrator asked for exists before hours of rendering.
#pragma once
#include <chrono>
#include <string>
#include <vector>

namespace rdv_tools {

std::string format_seconds(double s);  // "%g"
std::string format_error(double e);    // three significant digits
std::string format_clock(double s);    // m:ss

// Writes `table` into `file` between "<!-- SECTION:begin -->" and "<!-- SECTION:end -->"
// when the file has both markers, else as the whole file under `heading`.
void write_markdown(const std::string &file, const std::string &table, const std::string &section,
                    const std::string &heading);

// The data rows of a CSV file written under `header`, split at commas, those with
// `fields` fields only (a file that is missing or has another header gives none).
std::vector<std::vector<std::string>> read_csv_records(const std::string &file, const std::string &header,
                                                       size_t fields);
// Writes the header and the lines whole or not at all (a .partial file renamed): an
// interrupted run never leaves half a table. Throws std::runtime_error naming the file.
void write_csv_lines(const std::string &file, const std::string &header, const std::vector<std::string> &lines);

// Every integrator named exists: a session on an empty scene (the engine's own message
// names the unknown one and those available). False with that message in `error`.
bool check_integrators(const std::vector<std::string> &names, std::string &error);

// The progress bar on stderr: planned seconds done of all planned, the render under way,
// the time left at the rate so far. A line per render when stderr is not a terminal.
class StudyProgress {
 public:
  StudyProgress(double planned, int renders, bool quiet);
  void update(double done_in_render, const std::string &what);
  void finish_render(double planned_seconds, const std::string &what);

 private:
  void show(double done, const std::string &what, bool render_done);
  double planned_, done_ = 0;
  int renders_, finished_ = 0;
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace rdv_tools
