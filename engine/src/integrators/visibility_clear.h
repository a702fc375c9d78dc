// Ray visibility's rule for the last segment of a path, shared by the path tracer and
// BDPT (scene/ray_visibility.h): from a scattering vertex to a light, the segment is
// blocked by what casts that light's shadows (Light::occluders), whichever strategy made
// it. Next-event estimation tests exactly that; a scattered ray that found the light
// passed only what is invisible to its own kind, so in scenes with mixed visibility it
// also asks whether a shadow caster lies between; and next-event estimation asks
// whether a scattered ray could have reached the light at all (else its MIS weight is 1).
#pragma once
#include "bsdfs/transparency.h"
#include "core/ray_offset.h"
#include "scene/scene.h"

namespace rdv {

// Whether nothing that rays of the kinds in `mask` meet lies along s (mask 0: nothing
// does). see_through_transparent: partly transparent surfaces let the rays through,
// as the path tracer's transparent shadows and pass-throughs do (plain_layers_only: only
// those BDPT's walks pass without making them vertices, Scene::is_plain_layer).
inline bool visibility_clear(const Scene &scene, const ShadowRay &s, uint32_t mask, bool see_through_transparent,
                             uint64_t &rays, bool plain_layers_only = false) {
  if (!mask) return true;
  ++rays;
  if (!scene.occluded(s.o, s.d, s.tmax, mask)) return true;
  return see_through_transparent && scene.has_transparency() &&
         !is_black(transparent_shadow(scene, s.o, s.d, s.tmax, rays, mask, kShadowLayers, plain_layers_only));
}

}  // namespace rdv
