#include "lights/ies_profile.h"
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rdv {

namespace {

// The numbers of an LM-63 file after its TILT line, read one after another as Cycles reads
// them (commas count as spaces; a count is read as an integer).
class IesNumbers {
 public:
  explicit IesNumbers(const char *at) : at_(at) {}
  bool ok() const { return at_ != nullptr; }
  double real() {
    if (!at_) return 0.0;
    char *end = nullptr;
    const double v = std::strtod(at_, &end);
    at_ = end == at_ ? nullptr : end;
    return v;
  }
  long integer() {
    if (!at_) return 0;
    char *end = nullptr;
    const long v = std::strtol(at_, &end, 10);
    at_ = end == at_ ? nullptr : end;
    return v;
  }

 private:
  const char *at_;
};

// Cycles' (and LM-63's) unit: candela to watts per steradian for a D65 white (177.83 lumens
// per watt), times 4 pi because a lamp's strength is its power over the whole sphere.
constexpr double kCandelaToLampUnits = 0.0706650768394;
constexpr long kMaxAngles = 100000;            // far beyond any published file
constexpr long kMaxIntensities = 10 * 1000000;  // bounds what a malformed header allocates

bool ascending(const std::vector<float> &a) {
  for (size_t i = 1; i < a.size(); ++i)
    if (!(a[i] > a[i - 1])) return false;
  return true;
}

float catmull_rom(float a, float b, float c, float d, float x) {
  return 0.5f * (((d + 3.0f * (b - c) - a) * x + (2.0f * a - 5.0f * b + 4.0f * c - d)) * x + (c - a)) * x + b;
}

// Where x lies in the ascending table a: the interval [i, i + 1] and the fraction in it.
size_t interval(const std::vector<float> &a, float x, float &frac) {
  size_t i = 0;
  while (i + 2 < a.size() && a[i + 1] < x) ++i;
  frac = clampf((x - a[i]) / (a[i + 1] - a[i]), 0.0f, 1.0f);
  return i;
}

}  // namespace

bool IesProfile::parse(const std::string &file, std::string &error) {
  v_.clear();
  h_.clear();
  columns_.clear();
  std::string text = file;
  std::replace(text.begin(), text.end(), ',', ' ');
  const char *tilt = std::strstr(text.c_str(), "\nTILT=");
  if (!tilt) {
    error = "no TILT= line (not an IES LM-63 file)";
    return false;
  }
  IesNumbers in(nullptr);
  if (std::strncmp(tilt, "\nTILT=INCLUDE", 13) == 0) {
    in = IesNumbers(tilt + 13);
    in.real();  // lamp-to-luminaire geometry
    const long n = std::clamp(in.integer(), 0L, kMaxAngles);
    for (long i = 0; in.ok() && i < 2 * n; ++i) in.real();  // tilt angles and factors: unused, as in Cycles
  } else {
    const char *line_end = std::strchr(tilt + 1, '\n');
    in = IesNumbers(line_end ? line_end + 1 : nullptr);
  }
  in.integer();                // number of lamps
  in.real();                   // lumens per lamp
  double factor = in.real();   // candela multiplier
  const long nv = in.integer(), nh = in.integer();
  const long type = in.integer();
  in.integer();                // units of the dimensions
  in.real(), in.real(), in.real();  // width, length, height
  factor *= in.real();         // ballast factor
  factor *= in.real();         // ballast-lamp photometric factor
  in.real();                   // input watts
  if (!in.ok()) {
    error = "its header ends early";
    return false;
  }
  if (type != 1 && type != 2) {
    error = "photometric type " + std::to_string(type) + " (types C and B are read, as in Cycles)";
    return false;
  }
  if (nv < 1 || nh < 1 || nv > kMaxAngles || nh > kMaxAngles || nv * nh > kMaxIntensities) {
    error = "its header gives " + std::to_string(nv) + " vertical and " + std::to_string(nh) + " horizontal angles";
    return false;
  }
  factor *= kCandelaToLampUnits;
  for (long i = 0; i < nv; ++i) v_.push_back(float(in.real()));
  for (long i = 0; i < nh; ++i) h_.push_back(float(in.real()));
  columns_.assign(size_t(nh), std::vector<float>(size_t(nv)));
  bool finite = std::isfinite(factor);
  for (auto &column : columns_)
    for (float &value : column) finite &= std::isfinite(value = float(factor * in.real()));
  for (float a : v_) finite &= std::isfinite(a);
  for (float a : h_) finite &= std::isfinite(a);
  if (!in.ok()) {
    error = "it ends before its " + std::to_string(nv) + " x " + std::to_string(nh) + " intensities";
    return false;
  }
  if (!finite) {
    error = "an angle, an intensity or a factor is not a finite number";
    return false;
  }
  if (!(type == 2 ? process_type_b(error) : process_type_c(error))) return false;
  if (!ascending(v_) || !ascending(h_) || h_.front() != 0.0f || h_.back() != 360.0f) {
    error = "its angles do not increase over the ranges of its photometric type";
    return false;
  }
  for (float &a : v_) a *= kPi / 180.0f;
  for (float &a : h_) a *= kPi / 180.0f;
  return true;
}

bool IesProfile::load(const std::string &path, std::string &error) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in) {
    error = "no such file, or it cannot be read";
    return false;
  }
  return parse(text.str(), error);
}

// Type B (floodlights): the file's horizontal angles are about the vertical axis of type C and
// the other way round; both run from -90 (or 0, one side of a symmetric beam) to 90 degrees.
// Mirrored and shifted to type C's ranges, as Cycles does.
bool IesProfile::process_type_b(std::string &error) {
  std::vector<std::vector<float>> transposed(v_.size(), std::vector<float>(h_.size()));
  for (size_t i = 0; i < h_.size(); ++i)
    for (size_t j = 0; j < v_.size(); ++j) transposed[j][i] = columns_[i][j];
  columns_.swap(transposed);
  h_.swap(v_);
  if (h_.back() != 90.0f || v_.back() != 90.0f) {
    error = "a type B file whose angles do not end at 90 degrees";
    return false;
  }
  if (h_.front() == 0.0f) {  // one side: mirror it to -90..90 (then shifted by 90 below)
    const size_t n = h_.size();
    std::vector<float> angles;
    std::vector<std::vector<float>> columns;
    for (size_t i = n - 1; i > 0; --i) angles.push_back(-h_[i]), columns.push_back(columns_[i]);
    for (size_t i = 0; i < n; ++i) angles.push_back(h_[i]), columns.push_back(columns_[i]);
    h_.swap(angles);
    columns_.swap(columns);
  }
  if (h_.front() == -90.0f)
    for (float &a : h_) a += 90.0f;
  // The horizontal range wraps: 360 degrees is 0, for the cubic interpolation to be seamless.
  h_.push_back(360.0f);
  columns_.push_back(columns_.front());
  if (v_.front() == 0.0f) {  // mirrored likewise (each angle with its own intensity; Cycles
    const size_t n = v_.size();  // 3.4 pairs the mirrored half's angles one entry off)
    std::vector<float> angles;
    for (size_t i = n - 1; i > 0; --i) angles.push_back(-v_[i]);
    for (size_t i = 0; i < n; ++i) angles.push_back(v_[i]);
    v_.swap(angles);
    for (auto &column : columns_) {
      std::vector<float> mirrored(column.rbegin(), column.rend() - 1);
      mirrored.insert(mirrored.end(), column.begin(), column.end());
      column.swap(mirrored);
    }
  }
  if (v_.front() == -90.0f)
    for (float &a : v_) a += 90.0f;
  return true;
}

// Type C (most luminaires): vertical angles from the nadir, horizontal around the lamp's
// axis. A file symmetric about one or two planes gives 0..90 or 0..180 degrees of horizontal
// angle; mirrored to the full circle.
bool IesProfile::process_type_c(std::string &error) {
  if (h_.front() == 90.0f)  // some files store 90..270
    for (float &a : h_) a -= 90.0f;
  if (h_.front() != 0.0f) {
    error = "a type C file whose horizontal angles do not start at 0 or 90 degrees";
    return false;
  }
  if (h_.size() == 1) {  // rotationally symmetric
    h_.push_back(360.0f);
    columns_.push_back(columns_.front());
  }
  for (const float half : {90.0f, 180.0f}) {  // one quadrant to two, two to four
    if (h_.back() != half) continue;
    for (size_t i = h_.size() - 1; i-- > 0;) {
      h_.push_back(2.0f * half - h_[i]);
      columns_.push_back(columns_[i]);
    }
  }
  // Some files leave out the 360 degree entry (it is the 0 degree one): added when the
  // spacing makes that plain, as Cycles does.
  if (h_.back() != 360.0f) {
    const size_t n = h_.size();
    const float missing = 360.0f - h_[n - 1];
    if (n < 2 || (h_[n - 1] - h_[n - 2] != missing && h_[1] - h_[0] != missing)) {
      error = "a type C file whose horizontal angles neither end at 360 degrees nor stop one step short of it";
      return false;
    }
    h_.push_back(360.0f);
    columns_.push_back(columns_.front());
  }
  if (v_.front() != 0.0f && !(v_.front() == 90.0f && v_.back() == 180.0f)) {
    error = "a type C file whose vertical angles run neither from 0 nor from 90 to 180 degrees";
    return false;
  }
  return true;
}

float IesProfile::eval(Vec3 dir) const {
  const float len = length(dir);
  if (!(len > 0)) return 0.0f;
  dir = dir / len;
  return eval_angles(std::acos(clampf(-dir.z, -1.0f, 1.0f)), std::atan2(dir.x, dir.y) + kPi);
}

float IesProfile::eval_angles(float v_angle, float h_angle) const {
  if (v_.size() < 2 || !(v_angle < v_.back()) || !(v_angle >= v_.front())) return 0.0f;
  float v_frac, h_frac;
  const size_t v = interval(v_, v_angle, v_frac), h = interval(h_, h_angle, h_frac);
  // Around the circle the neighbours wrap: the entry before 0 is the one before 360 (which
  // repeats 0), the entry after 360 the one after 0.
  const size_t n = h_.size();
  const float a = vertical(h == 0 ? n - 2 : h - 1, v, v_frac);
  const float b = vertical(h, v, v_frac);
  const float c = vertical(h + 1, v, v_frac);
  const float d = vertical(h + 2 == n ? 1 : h + 2, v, v_frac);
  return std::max(catmull_rom(a, b, c, d, h_frac), 0.0f);  // the cubic can undershoot
}

// Along one horizontal angle's column, between vertical entries v and v + 1. Before the first
// entry the profile is taken as symmetric about the pole (its second entry), as Cycles does.
float IesProfile::vertical(size_t h, size_t v, float frac) const {
  const std::vector<float> &I = columns_[h];
  return catmull_rom(I[v == 0 ? 1 : v - 1], I[v], I[v + 1], I[std::min(v + 2, I.size() - 1)], frac);
}

}  // namespace rdv
