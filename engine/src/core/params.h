// A parameter description (a JSON object of key/value pairs) as the C ABI takes it.
// Every key that is read is remembered, so keys nobody read can be reported: an
// unknown key is an error naming the object, never silently ignored.
#pragma once
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>
#include "core/error.h"
#include "core/math.h"

namespace rdv {

class Params {
 public:
  // what: the object, for messages, e.g. "material 'Red'".
  Params(std::string_view json_text, std::string what);

  const std::string &what() const { return what_; }
  bool has(const char *key) const { return json_.contains(key); }
  float get_float(const char *key, float fallback);
  int get_int(const char *key, int fallback);
  bool get_bool(const char *key, bool fallback);
  std::string get_string(const char *key, const std::string &fallback);
  Vec3 get_vec3(const char *key, Vec3 fallback);
  Transform get_transform(const char *key, const Transform &fallback);
  std::vector<float> get_floats(const char *key, size_t count, std::vector<float> fallback);
  // The raw JSON value of a key (marked as used), or nullptr if absent: for values
  // that may be a number, a colour or a nested object (texture graphs, shaders).
  const nlohmann::json *get_json(const char *key);

  // Throws RDV_ERROR_UNKNOWN_PARAMETER listing the keys nobody asked for.
  void check_all_used() const;

 private:
  const nlohmann::json &lookup(const char *key);
  [[noreturn]] void bad(const char *key, const std::string &problem) const;
  nlohmann::json json_;
  std::string what_;
  std::set<std::string> used_;
};

// Parses a transform: 16 row-major numbers, {"translate","rotate"(deg, XYZ Euler),"scale"}
// or {"look_at":{"from","to","up"}} (a camera or light looking from -> to along local -Z).
Transform parse_transform(const nlohmann::json &j, const std::string &what);

}  // namespace rdv
