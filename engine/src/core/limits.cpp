#include "core/limits.h"
#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>
#include "core/error.h"

namespace rdv {

int json_text_depth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > deepest && (deepest = depth) > limit) return deepest;
    } else if (c == ']' || c == '}') --depth;
  }
  return deepest;
}

int json_depth(const nlohmann::json &j, int limit) {
  if (!j.is_structured()) return 0;
  int deepest = 0;
  std::vector<std::pair<const nlohmann::json *, int>> stack{{&j, 1}};
  while (!stack.empty()) {
    auto [v, d] = stack.back();
    stack.pop_back();
    if (d > deepest && (deepest = d) > limit) return deepest;
    for (const nlohmann::json &child : *v)  // array elements or object values
      if (child.is_structured()) stack.push_back({&child, d + 1});
  }
  return deepest;
}

void check_json_depth(std::string_view text, const std::string &what) {
  int depth = json_text_depth(text);
  if (depth > kMaxJsonDepth)
    fail(what + ": the description nests more than " + std::to_string(kMaxJsonDepth) +
             " levels of JSON arrays / objects (a Mix shader or texture node adds one); too deep to be a real "
             "material or scene",
         RDV_ERROR_LIMIT);
}

double memory_budget_bytes() {
  if (const char *cap = std::getenv("RDV_MEMORY_LIMIT_MB")) {
    double mb = std::atof(cap);
    if (mb > 0) return mb * 1048576.0;
  }
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 16.0 * 1073741824.0;
}

std::string format_bytes(double bytes) {
  const char *unit[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) { bytes /= 1024.0; ++u; }
  char text[48];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", bytes, unit[u]);
  return text;
}

void check_memory(const std::string &what, const std::string &for_what, double bytes) {
  double budget = memory_budget_bytes();
  if (!(bytes <= budget))
    fail(what + ": " + for_what + " needs about " + format_bytes(bytes) + ", more than the " + format_bytes(budget) +
             " of memory available to the engine" +
             (std::getenv("RDV_MEMORY_LIMIT_MB") ? " (RDV_MEMORY_LIMIT_MB)" : " (this machine's memory)"),
         RDV_ERROR_LIMIT);
}

}  // namespace rdv
