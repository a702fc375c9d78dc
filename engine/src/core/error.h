// The engine reports bad input by throwing rdv::Error; the C ABI boundary
// (api/api.cpp) turns it into a status code and rdv_last_error().
#pragma once
#include <stdexcept>
#include <string>
#include "rendezvous.h"

namespace rdv {

struct Error : std::runtime_error {
  rdv_status status;
  Error(rdv_status s, const std::string &message) : std::runtime_error(message), status(s) {}
};

[[noreturn]] inline void fail(const std::string &message, rdv_status s = RDV_ERROR_INVALID_ARGUMENT) {
  throw Error(s, message);
}

}  // namespace rdv
