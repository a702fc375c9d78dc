// Cycles' ray visibility (Object > Visibility > Ray Visibility, a light object's, the
// world's): which kinds of ray see an instance, a light or the world. A ray of a kind
// passes straight through what is invisible to it. Instances carry their bits as
// Embree instance masks, so a ray's mask selects what it can hit at no cost.
//
// The kind of a ray (Cycles 3.4's path_state_ray_visibility): camera rays; rays leaving a
// diffuse or a glossy reflection; any transmission (refraction, translucency) is
// Transmission only; a volume scattering is Scatter and counts as Diffuse too; shadow
// rays (next-event estimation and BDPT's connections to a light) are Shadow. A pass
// through a transparent surface, a lamp or a medium boundary keeps the ray's kind.
#pragma once
#include <cstdint>
#include <string>
#include "bsdfs/scatter_kind.h"
#include "core/params.h"

namespace rdv::visibility {

constexpr uint32_t kCamera = 1, kDiffuse = 2, kGlossy = 4, kTransmission = 8, kShadow = 16, kScatter = 32;
constexpr uint32_t kAll = 63;
constexpr uint32_t kNonCamera = kAll & ~kCamera;
// The mask of rays that meet every instance whatever its visibility (internal queries:
// which media a point is in; the default of Ray::mask).
constexpr uint32_t kAnyRay = 0xffffffffu;

// Shadow catchers (integrators/path/shadow_catcher.h): the rays of a catcher pass meet
// shadow-catcher instances only. As Cycles 3.4 (SHADOW_CATCHER_VISIBILITY_SHIFT), their
// kinds sit kCatcherShift bits up: a catcher instance's mask carries its visibility there
// too, every other instance's nothing, so catcher_rays(kind) meets the catchers visible to
// that kind and nothing else. The bits no kind uses stay set on every instance, so rays of
// every kind (kAnyRay) meet them all, and masks of kinds below the shift are as before.
constexpr int kCatcherShift = 8;
// Mixed visibility: an instance seen by some kinds of ray after a scattering and not by
// others (or by shadow rays alone) carries kMixed too, so one query with that mask finds
// the nearest such surface (BDPT's test of what light subpaths can follow,
// integrators/bdpt/bdpt.h). It is no kind: no ray of the kinds above asks for it.
constexpr uint32_t kMixed = 64;
inline bool is_mixed(uint32_t visibility) {
  const uint32_t rest = visibility & kNonCamera;
  return rest != 0 && rest != kNonCamera;
}
inline uint32_t instance_mask(uint32_t visibility, bool shadow_catcher) {
  const uint32_t own = visibility | (is_mixed(visibility) ? kMixed : 0u);
  const uint32_t used = kAll | kMixed;
  return own | ~(used | (used << kCatcherShift)) | (shadow_catcher ? own << kCatcherShift : 0u);
}
// The mask of a catcher pass's ray of the kinds in `mask` (kAnyRay: every kind; kMixed:
// the catchers of mixed visibility).
inline uint32_t catcher_rays(uint32_t mask) { return (mask & (kAll | kMixed)) << kCatcherShift; }

// The kind of the ray leaving a scattering of kind k.
inline uint32_t after(ScatterKind k) {
  switch (k) {
    case ScatterKind::Diffuse: return kDiffuse;
    case ScatterKind::Glossy: return kGlossy;
    case ScatterKind::Transmission:
    case ScatterKind::Translucent: return kTransmission;
    case ScatterKind::Volume: return kScatter | kDiffuse;
    case ScatterKind::Transparent: return kAnyRay;  // no scattering: the caller keeps the kind it had
  }
  return kAnyRay;
}

// {"camera": true, "diffuse": true, "glossy": true, "transmission": true, "shadow": true,
// "volume_scatter": true}, every key optional (absent: `fallback`'s bit); anything else is
// an error naming `what`. `value` null: fallback.
uint32_t parse(const nlohmann::json *value, const std::string &what, uint32_t fallback = kAll);
// The parameter "visibility" of p, as parse().
inline uint32_t from_params(Params &p, uint32_t fallback = kAll) {
  return parse(p.get_json("visibility"), p.what(), fallback);
}

}  // namespace rdv::visibility
