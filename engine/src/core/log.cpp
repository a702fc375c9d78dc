#include "core/log.h"
#include <cstdio>
#include <cstdlib>

namespace rdv {
void log_warning(const std::string &message) {
  static const bool verbose = std::getenv("RDV_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "rendezvous: warning: %s\n", message.c_str());
}
}  // namespace rdv
