#include "lights/environment.h"
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include "core/error.h"
#include "textures/image_texture.h"

namespace rdv {

namespace {

Vec3 mul(const Vec3 r[3], Vec3 v) { return {dot(r[0], v), dot(r[1], v), dot(r[2], v)}; }
Vec3 mul_transpose(const Vec3 r[3], Vec3 v) { return r[0] * v.x + r[1] * v.y + r[2] * v.z; }

}  // namespace

std::shared_ptr<EnvironmentMap> EnvironmentMap::load(const std::string &path, const std::string &colorspace,
                                                     Vec3 rotation, Color tint) {
  OIIO::ImageBuf buf(path);
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    fail("world: cannot read environment image '" + path + "': " + buf.geterror(), RDV_ERROR_IO);
  const OIIO::ImageSpec &spec = buf.spec();
  int w = spec.width, h = spec.height, nc = spec.nchannels;
  if (w < 1 || h < 1) fail("world: environment image '" + path + "' is empty", RDV_ERROR_IO);
  std::vector<float> px(size_t(w) * h * nc);
  buf.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, nc), OIIO::TypeDesc::FLOAT, px.data());
  std::string cs = colorspace.empty() ? (spec.format.is_floating_point() ? "Linear" : "sRGB") : colorspace;
  std::vector<float> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    Color c = nc >= 3 ? Color(px[i * nc], px[i * nc + 1], px[i * nc + 2]) : Color(px[i * nc]);
    if (!to_scene_linear(cs, c)) fail("world: unknown colour space '" + cs + "' for '" + path + "'");
    for (int k = 0; k < 3; ++k) rgb[i * 3 + k] = std::isfinite(c[k]) ? std::max(c[k], 0.0f) : 0.0f;
  }
  return std::make_shared<EnvironmentMap>(w, h, std::move(rgb), rotation, tint);
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<float> rgb, Vec3 r, Color tint)
    : w_(width), h_(height), rgb_(std::move(rgb)), tint_(tint) {
  // Rotation R = Rz Ry Rx (Blender's XYZ Euler); lookups use R d.
  float cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y), cz = std::cos(r.z),
        sz = std::sin(r.z);
  rot_[0] = {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx};
  rot_[1] = {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx};
  rot_[2] = {-sy, cy * sx, cy * cx};
  // Sampling weights: the maximum luminance of the pixel and its neighbours (so that
  // bilinear lookups never have radiance where the pdf is 0), times sin(theta).
  std::vector<float> row_w(static_cast<size_t>(h_), 0.0f);
  cols_.reserve(size_t(h_));
  double mean_w = 0;
  Color mean(0.0f);
  for (int y = 0; y < h_; ++y) {
    float sin_t = std::sin(kPi * (y + 0.5f) / h_);
    std::vector<float> f(static_cast<size_t>(w_), 0.0f);
    for (int x = 0; x < w_; ++x) {
      float m = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int yy = std::clamp(y + dy, 0, h_ - 1), xx = ((x + dx) % w_ + w_) % w_;
          m = std::max(m, luminance(texel(xx, yy)));
        }
      f[size_t(x)] = m * sin_t;
      mean += texel(x, y) * sin_t;
    }
    mean_w += double(sin_t) * w_;
    cols_.emplace_back(f);
    row_w[size_t(y)] = cols_.back().total();
  }
  rows_ = Distribution1D(row_w);
  mean_ = mean_w > 0 ? mean * float(1.0 / mean_w) * tint_ : Color(0.0f);
}

size_t EnvironmentMap::memory_bytes() const { return rgb_.size() * 4 + size_t(w_) * h_ * 8 + size_t(h_) * 8; }

Color EnvironmentMap::texel(int x, int y) const {
  const float *p = &rgb_[(size_t(y) * w_ + x) * 3];
  return {p[0], p[1], p[2]};
}

Vec3 EnvironmentMap::to_local(Vec3 d) const { return mul(rot_, d); }
Vec3 EnvironmentMap::to_world(Vec3 d) const { return mul_transpose(rot_, d); }

Color EnvironmentMap::eval(Vec3 dir) const {
  Vec3 d = to_local(dir);
  float u = 0.5f - std::atan2(d.y, d.x) * (0.5f / kPi);
  float v = 1.0f - std::acos(clampf(d.z, -1, 1)) * kInvPi;
  // Bilinear: wrap in u, clamp in v (Blender's Linear interpolation, Repeat extension).
  float fx = u * w_ - 0.5f, fy = (1.0f - v) * h_ - 0.5f;
  int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  float tx = fx - x0, ty = fy - y0;
  auto at = [&](int x, int y) { return texel(((x % w_) + w_) % w_, std::clamp(y, 0, h_ - 1)); };
  Color c = (at(x0, y0) * (1 - tx) + at(x0 + 1, y0) * tx) * (1 - ty) + (at(x0, y0 + 1) * (1 - tx) + at(x0 + 1, y0 + 1) * tx) * ty;
  return c * tint_;
}

bool EnvironmentMap::sample(Vec2 u, Vec3 &dir, Color &L, float &pdf_out) const {
  if (rows_.total() <= 0) return false;
  float row_pmf, col_pmf, ur, uc;
  size_t y = rows_.sample_discrete(u.y, &row_pmf, &ur);
  size_t x = cols_[y].sample_discrete(u.x, &col_pmf, &uc);
  if (!(row_pmf > 0) || !(col_pmf > 0)) return false;
  // Uniform within the pixel in (u, v): pdf_uv = row_pmf col_pmf w h.
  float pu = (x + uc) / w_, pv = 1.0f - (y + ur) / h_;
  float theta = (1.0f - pv) * kPi, phi = (0.5f - pu) * 2.0f * kPi;
  float sin_t = std::sin(theta);
  if (!(sin_t > 0)) return false;
  Vec3 local(sin_t * std::cos(phi), sin_t * std::sin(phi), std::cos(theta));
  dir = to_world(local);
  // The density of the pixel the direction falls in, recomputed from the direction so
  // that sample() and pdf() agree exactly even at pixel borders (MIS needs that).
  pdf_out = pdf(dir);
  L = eval(dir);
  return std::isfinite(pdf_out) && pdf_out > 0;
}

float EnvironmentMap::pdf(Vec3 dir) const {
  if (rows_.total() <= 0) return 0;
  Vec3 d = to_local(dir);
  float u = 0.5f - std::atan2(d.y, d.x) * (0.5f / kPi);
  float theta = std::acos(clampf(d.z, -1, 1));
  float sin_t = std::sin(theta);
  if (!(sin_t > 0)) return 0;
  u -= std::floor(u);
  int x = std::min(int(u * w_), w_ - 1), y = std::min(int(theta * kInvPi * h_), h_ - 1);
  float p = rows_.pmf(size_t(y)) * cols_[size_t(y)].pmf(size_t(x)) * w_ * h_;
  return p / (2.0f * kPi * kPi * sin_t);
}

}  // namespace rdv
