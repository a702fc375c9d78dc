#include "core/params.h"
#include <functional>
#include <limits>
#include "core/limits.h"

namespace rdv {

Params::Params(std::string_view json_text, std::string what) : what_(std::move(what)) {
  if (json_text.empty()) { json_ = nlohmann::json::object(); return; }
  check_json_depth(json_text, what_);  // before any recursive JSON code sees it
  try {
    json_ = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::exception &e) {
    fail(what_ + ": malformed parameter JSON: " + e.what());
  }
  if (!json_.is_object()) fail(what_ + ": parameters must be a JSON object");
}

void Params::bad(const char *key, const std::string &problem) const {
  fail(what_ + ": parameter '" + key + "' " + problem);
}

const nlohmann::json &Params::lookup(const char *key) {
  used_.insert(key);
  return json_.at(key);
}

// Finite as the engine's float: 1e39 is a finite double but infinite as a float.
static float finite_number(const nlohmann::json &v, const std::function<void(const std::string &)> &bad) {
  if (!v.is_number()) bad("must be a number");
  float f = static_cast<float>(v.get<double>());
  if (!std::isfinite(f)) bad("is " + v.dump() + ", not a finite number");
  return f;
}

float Params::get_float(const char *key, float fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  return finite_number(lookup(key), [&](const std::string &p) { bad(key, p); });
}

int Params::get_int(const char *key, int fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  const auto &v = lookup(key);
  if (!v.is_number_integer()) bad(key, "must be an integer");
  // get<int>() would wrap 4294967297 to 1: out of range is an error, not a different value.
  if (v.is_number_unsigned() ? v.get<uint64_t>() > uint64_t(std::numeric_limits<int>::max())
                             : (v.get<int64_t>() < std::numeric_limits<int>::min() ||
                                v.get<int64_t>() > std::numeric_limits<int>::max()))
    bad(key, "is " + v.dump() + ", outside the integer range (at most " +
                 std::to_string(std::numeric_limits<int>::max()) + ")");
  return v.get<int>();
}

bool Params::get_bool(const char *key, bool fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  const auto &v = lookup(key);
  if (!v.is_boolean()) bad(key, "must be true or false");
  return v.get<bool>();
}

std::string Params::get_string(const char *key, const std::string &fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  const auto &v = lookup(key);
  if (!v.is_string()) bad(key, "must be a string");
  return v.get<std::string>();
}

const nlohmann::json *Params::get_json(const char *key) {
  used_.insert(key);
  return has(key) ? &json_.at(key) : nullptr;
}

std::vector<float> Params::get_floats(const char *key, size_t count, std::vector<float> fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  const auto &v = lookup(key);
  if (!v.is_array() || v.size() != count) bad(key, "must be an array of " + std::to_string(count) + " numbers");
  std::vector<float> out;
  for (const auto &e : v) out.push_back(finite_number(e, [&](const std::string &p) { bad(key, p); }));
  return out;
}

Vec3 Params::get_vec3(const char *key, Vec3 fallback) {
  if (has(key) && json_.at(key).is_number()) {  // a grey value is accepted for a colour
    float s = get_float(key, 0);
    return Vec3(s);
  }
  auto v = get_floats(key, 3, {fallback.x, fallback.y, fallback.z});
  return {v[0], v[1], v[2]};
}

Transform Params::get_transform(const char *key, const Transform &fallback) {
  if (!has(key)) { used_.insert(key); return fallback; }
  return parse_transform(lookup(key), what_ + " '" + key + "'");
}

void Params::check_all_used() const {
  std::string unknown;
  for (auto it = json_.begin(); it != json_.end(); ++it)
    if (!used_.count(it.key())) unknown += (unknown.empty() ? "'" : ", '") + it.key() + "'";
  if (!unknown.empty())
    fail(what_ + ": unknown parameter " + unknown + " (see docs/scene-format.md)", RDV_ERROR_UNKNOWN_PARAMETER);
}

static Vec3 json_vec3(const nlohmann::json &j, const std::string &what, const char *field) {
  if (j.is_number()) {
    float s = j.get<float>();
    if (!std::isfinite(s)) fail(what + ": '" + field + "' must be finite");
    return Vec3(s);
  }
  if (!j.is_array() || j.size() != 3) fail(what + ": '" + field + "' must be 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[i].is_number()) fail(what + ": '" + field + "' must be 3 numbers");
    v[i] = j[i].get<float>();
  }
  if (!is_finite(v)) fail(what + ": '" + field + "' must be finite");
  return v;
}

Transform parse_transform(const nlohmann::json &j, const std::string &what) {
  Transform t;
  if (j.is_array()) {
    if (j.size() != 16) fail(what + ": a transform matrix needs 16 numbers, got " + std::to_string(j.size()));
    float v[16];
    for (int i = 0; i < 16; ++i) {
      if (!j[i].is_number()) fail(what + ": transform entries must be numbers");
      v[i] = j[i].get<float>();
    }
    t = Transform::from_row_major(v);
    if (!t.is_finite()) fail(what + ": transform has non-finite entries");
    return t;
  }
  if (!j.is_object()) fail(what + ": transform must be 16 numbers or an object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "translate" && it.key() != "rotate" && it.key() != "scale" && it.key() != "look_at")
      fail(what + ": unknown transform key '" + it.key() + "'", RDV_ERROR_UNKNOWN_PARAMETER);
  if (j.contains("look_at")) {
    const auto &la = j["look_at"];
    Vec3 from = json_vec3(la.value("from", nlohmann::json::array({0, 0, 0})), what, "from");
    Vec3 to = json_vec3(la.value("to", nlohmann::json::array({0, 0, -1})), what, "to");
    Vec3 up = json_vec3(la.value("up", nlohmann::json::array({0, 0, 1})), what, "up");
    Vec3 z = from - to;
    if (length(z) == 0) fail(what + ": look_at 'from' and 'to' coincide");
    z = normalize(z);
    Vec3 x = cross(up, z);
    if (length(x) < 1e-6f) x = cross(Vec3(0, 1, 0), z);
    x = normalize(x);
    Vec3 y = cross(z, x);
    for (int r = 0; r < 3; ++r) { t.m[r][0] = x[r]; t.m[r][1] = y[r]; t.m[r][2] = z[r]; t.m[r][3] = from[r]; }
    return t;
  }
  Vec3 tr = j.contains("translate") ? json_vec3(j["translate"], what, "translate") : Vec3(0.0f);
  Vec3 rot = j.contains("rotate") ? json_vec3(j["rotate"], what, "rotate") * (kPi / 180.0f) : Vec3(0.0f);
  Vec3 sc = j.contains("scale") ? json_vec3(j["scale"], what, "scale") : Vec3(1.0f);
  // Blender's XYZ Euler: R = Rz * Ry * Rx.
  float cx = std::cos(rot.x), sx = std::sin(rot.x), cy = std::cos(rot.y), sy = std::sin(rot.y);
  float cz = std::cos(rot.z), sz = std::sin(rot.z);
  float r[3][3] = {{cy * cz, sx * sy * cz - cx * sz, cx * sy * cz + sx * sz},
                   {cy * sz, sx * sy * sz + cx * cz, cx * sy * sz - sx * cz},
                   {-sy, sx * cy, cx * cy}};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) t.m[i][k] = r[i][k] * sc[k];
    t.m[i][3] = tr[i];
  }
  return t;
}

}  // namespace rdv
