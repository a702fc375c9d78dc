// What every integrator shares: the render settings, the first-hit AOV record, ray
// statistics, and the registry that builds one by name.
#pragma once
#include <memory>
#include <string>
#include "core/params.h"
#include "film/film.h"
#include "samplers/sampler.h"
#include "scene/scene.h"

namespace rdv {

struct RenderSettings {
  int width = 640, height = 480;
  std::string integrator = "path";
  std::string sampler = "sobol";  // or "independent"
  uint32_t samples = 128;  // 0 = no sample limit (then time_limit > 0)
  double time_limit = 0;   // seconds, 0 = off
  int max_bounces = 12;
  uint32_t seed = 0;
  int threads = 0;         // 0 = all cores
  float clamp = 0;         // 0 = off
  float filter_width = 1.5f;
  Rect border;             // the rendered region

  static RenderSettings from_params(Params &p);
};

struct RayStats {
  uint64_t rays = 0;
};

struct FirstHit {
  bool valid = false;
  float depth = 1e10f;
  Vec3 normal{0.0f};
  Color albedo{0.0f};
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Radiance arriving at the camera along `ray`.
  virtual Color Li(const Ray &ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit) const = 0;
};

// The registry: one line per integrator.
std::unique_ptr<Integrator> make_integrator(const RenderSettings &settings, const Scene &scene);

}  // namespace rdv
