// What the fuzz targets count as a finding, beyond what AddressSanitizer and UBSan
// catch: the engine's promises to a host process (README, Limits; rendezvous.h).
//  - no call fails with RDV_ERROR_INTERNAL: hostile input is an error naming the object
//    (RDV_ERROR_INVALID_ARGUMENT, _UNKNOWN_PARAMETER, _IO, _STATE or _LIMIT), never a bug;
//  - every failure has a message (rdv_last_error);
//  - no pixel read from the film is NaN or infinite;
//  - no scene or session outlives the input (rdv_live_objects).
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include "rendezvous.h"

namespace rdv_fuzz {

[[noreturn]] inline void finding(const std::string &what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// RDV_FUZZ_TRACE=1: every checked call is printed with its status (to cut a finding down).
inline bool tracing() {
  static const bool on = std::getenv("RDV_FUZZ_TRACE") != nullptr;
  return on;
}

// Checks a C ABI call's status; returns it so the caller can go on.
inline rdv_status checked(rdv_status status, const char *call) {
  if (tracing()) std::fprintf(stderr, "%s -> %d %s\n", call, int(status), status ? rdv_last_error() : "");
  if (status == RDV_ERROR_INTERNAL) finding(std::string(call) + " failed with RDV_ERROR_INTERNAL: " + rdv_last_error());
  if (status != RDV_OK && !*rdv_last_error()) finding(std::string(call) + " failed without a message");
  return status;
}

inline void check_finite(const float *values, size_t count, const char *what) {
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(values[i])) finding(std::string(what) + ": value " + std::to_string(i) + " is not finite");
}

inline void check_no_live_objects() {
  uint32_t scenes = 0, sessions = 0;
  rdv_live_objects(&scenes, &sessions);
  if (scenes || sessions)
    finding(std::to_string(scenes) + " scenes and " + std::to_string(sessions) + " sessions outlive the input");
}

}  // namespace rdv_fuzz
