// The default render loop, shared by integrators that estimate each pixel from camera
// samples of its own (path tracing, BDPT): progressive passes of a growing batch of
// samples over 16 x 16 tiles on the session's threads. Light-side contributions
// (BDPT's t = 1 strategies) are kept per tile and applied in tile order after each
// pass, so the image is the same on any number of threads. When the settings estimate
// the noise, the odd samples, and the splats of their light paths, also make half image
// B (film/noise_estimate.h).
#pragma once
#include "integrators/integrator.h"

namespace rdv {

// What a tile's samples reached beyond their own pixels in one pass: the splats of the
// light paths of half A's and of half B's samples, and how many light paths half B traced.
struct TileSplats {
  std::vector<Splat> a, b;
  uint64_t paths = 0, half_b_paths = 0;
};

class TileIntegrator : public Integrator {
 public:
  void render(RenderContext &ctx) override;
  // Radiance arriving at the camera along the ray. Integrators that also reach the
  // camera from the light side append those contributions to `splats`.
  virtual Color Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
                   std::vector<Splat> &splats) const = 0;

  // Samples [first, last) of every pixel of `tile` but those marked in `converged`
  // (adaptive sampling; may be empty): the camera ray through the pixel filter and the
  // lens, Li, then the film (never NaN / Inf). Stops early on ctx.control.should_stop()
  // (cancel latency: one pixel's batch of samples).
  void render_tile(RenderContext &ctx, const Rect &tile, uint32_t first, uint32_t last,
                   const std::vector<uint8_t> &converged, TileSplats &splats) const;
  // The 16 x 16 tiles that cover a region, row by row.
  static std::vector<Rect> tiles(const Rect &region);
};

}  // namespace rdv
