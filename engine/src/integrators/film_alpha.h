// Cycles' transparent film (Film > Transparent, Transparent Glass) and holdouts: which
// camera paths see "through" to the background, and what they leave in the alpha.
//
// As Cycles 3.4 (kernel/integrator/path_state.h, shade_background.h, shade_surface.h):
// a camera ray sees through until it scatters, but a Transparent BSDF keeps it seeing
// through, and so does a refraction by a lobe no rougher than film_transparent_roughness
// (alpha_x alpha_y <= roughness^2) when Transparent Glass is on. Such a path that
// escapes to the world with the film transparent, or meets a holdout, adds the average
// of its throughput to the sample's transparency, and the world's radiance there is not
// added (suns still are: they are lights, not the background). A pixel's alpha is 1 minus
// its samples' mean transparency. Media on the way attenuate the throughput, so fog in
// front of a transparent background gives partial alpha, as in Cycles. A holdout (object
// or Holdout closure) seen through adds its weight times that average, film transparent or
// not; what it holds out scatters nothing (black wherever it is seen).
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv {

struct FilmAlpha {
  bool film_transparent = false;   // scene.render.film_transparent
  bool transparent_glass = false;  // scene.cycles.film_transparent_glass
  float glass_roughness = 0.1f;    // scene.cycles.film_transparent_roughness (Cycles' default)
  // The scene has holdout objects or materials (Scene::has_holdouts): camera paths track
  // seeing through with an opaque film too, as a holdout cuts alpha either way.
  bool holdouts = false;
  // View Layer > Passes > Alpha Threshold (view_layer.pass_alpha_threshold): the Object and
  // Material Index passes take the first surface at least this opaque (film/data_passes.h).
  float pass_alpha_threshold = 0.5f;

  // Whether camera paths need to know if they still see through (else: no cost at all).
  bool tracked() const { return film_transparent || holdouts; }
  // Whether a camera path that saw through before scattering as `bs` still does.
  bool keeps_seeing_through(const BsdfSample &bs) const {
    if (bs.pass_through) return true;
    return transparent_glass && bs.refraction_alpha2 >= 0 && bs.refraction_alpha2 <= glass_roughness * glass_roughness;
  }
};

}  // namespace rdv
