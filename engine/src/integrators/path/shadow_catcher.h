// Cycles 3.4's shadow catcher in the path tracer (kernel/integrator/shadow_catcher.h,
// intersect_closest.h: integrator_split_shadow_catcher).
//
// A camera path splits at the first shadow catcher its see-through chain meets (the
// camera ray, on through lamps, Transparent BSDFs and, with Transparent Glass, smooth
// refractions: the chain that sees the transparent film; a holdout object never splits):
// - the path itself (the main path) goes on as if the catcher were an ordinary object:
//   all it adds is Combined's (C). What it added before the split is the matte's too
//   (M), and a path that never meets a catcher adds everything to both; at the split
//   the throughput's average joins the matte's transparency (the catcher is a hole in
//   it). Cycles writes no light passes after the split, so neither does this;
// - a copy of the path at the split (Cycles' second integrator state) traces on from the
//   catcher with rays that meet shadow catchers only (scene/ray_visibility.h,
//   catcher_rays), shadow rays included, and without the light of emitting objects that
//   are not catchers: all it gathers is the catcher pass's (S).
// The copy is made by tracing the sample again from the camera (Role::Copy): every
// decision draws at a position fixed by its path vertex (samplers/dimension_layout.h), so
// the prefix is the main path's, bit for bit, and from the split on both use the same
// random numbers, as Cycles' copy of the state does. The prefix is the camera ray and the
// transparent layers before the catcher: a few rays more per split sample. A scene
// without a catcher never splits and runs no copy.
// The film turns C, M, S into Cycles' passes (film/shadow_catcher_passes.h).
#pragma once
#include <cstdint>

namespace rdv::shadow_catcher {

// Which of a sample's paths the path tracer traces.
enum class Role : uint8_t {
  None,  // no shadow catcher sums kept: the catcher is an ordinary object
  Main,  // the sample's path: Combined, the matte, the split
  Copy   // again from the camera: from the split on, the catcher pass
};

}  // namespace rdv::shadow_catcher
