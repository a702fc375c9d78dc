// Where on its stream every random decision of a path draws (samplers/sampler.h): each
// path vertex owns a fixed block of positions, so what one vertex did (scatter in a
// medium, cross a boundary or a transparent layer, run next-event estimation, need
// more tracking steps) never moves the dimensions of any later vertex. A small step
// in primary-sample space (MLT) is then a small change of the path, and a decision
// is stratified across the samples of a pixel. The path tracer and BDPT share it.
//
// Walk streams (Camera: the camera path; Light: the light subpath). Positions:
//   0                   Camera: pixel filter (2D)      Light: light choice (1D)
//   1                   Camera: lens (2D)              Light: point on the light (2D)
//   2                   Camera: shutter time (1D;      Light: direction (2D)
//                       motion blur only: one time for the whole sample, both subpaths)
//   3, 4                                               Light: volume-light point (kVolumePoint)
//   kWalkStart + k * kBounceDims + offset: bounce k, the segment leaving vertex k and
//                       the decisions at the vertex k + 1 it reaches:
//     kRoulette         1D   Russian roulette after vertex k + 1
//     kScatterLobe      1D   BSDF lobe (or transparency: pass through or not)
//     kScatterDirection 2D   BSDF or phase-function direction
//     kMedium           kMediumRun x 1D: the segment's free flight (homogeneous: channel,
//                            distance; grids: tracking steps, see below)
//     kGather           kGatherRun x 1D: emission gathered along the segment (offset,
//                            then its transmittance's tracking steps)
// Crossing streams (CameraCrossing, LightCrossing): the c-th segment (c >= 1) of bounce
// k, after c boundaries or transparent layers, has its own block at
//   ((c - 1) * max_vertices + k) * kCrossingDims + offset, offsets as in a bounce:
//     kScatterLobe, kScatterDirection   the transparency decision at the surface it
//                            reaches, once one layer of this bounce has passed through
//                            (the first surface decides on the bounce's own dimensions)
//     kMedium, kGather       the segment's free flight and gathered emission
// LightPoint: next-event estimation at vertex v (the path tracer's vertex v = its
// bounce v - 1's end; BDPT's s = 1 at camera vertex t - 1 = v), block v * kNeeDims:
//     0  light choice (1D)    1  point on the light (2D)   2, 3  volume-light point
//     4  kMediumRun x 1D: the shadow ray's transmittance through media
// Lens: light tracing (BDPT's t = 1) from light vertex s - 1, block (s - 1) * kLensDims:
//     0  lens point (2D)      1  kMediumRun x 1D: transmittance to the lens
// Connection: BDPT's inner connection (s, t >= 2), block connection_index(s, t) *
//     kMediumRun: its transmittance.
//
// Media need an unbounded number of draws (delta and ratio tracking take one or two per
// tentative collision): a SampleRun (samplers/sample_run.h) draws its first kMediumRun
// numbers from the sampler at these fixed dimensions and only then continues with a
// generator seeded by them.
#pragma once
#include <cstdint>
#include "samplers/sampler.h"

namespace rdv::dims {

// Sampler draws per medium estimate before the seeded generator takes over. Measured
// (8 spp, PT and BDPT): the free flight of 99.4% of segments in scenes/smoke_spot.json
// (99th percentile 29-31 draws) and of all in fire.json (8), the transmittance of all
// shadow rays and connections in both (99th percentile 17-19). Emission gathering takes
// one run over a whole segment (fire.json: median ~26 draws, 99th percentile 55).
constexpr uint32_t kMediumRun = 32;
constexpr uint32_t kGatherRun = 64;

// The start of a walk stream.
constexpr uint32_t kCameraFilter = 0, kCameraLens = 1, kCameraTime = 2;
constexpr uint32_t kLightChoice = 0, kLightPosition = 1, kLightDirection = 2, kLightVolumePoint = 3;
constexpr uint32_t kWalkStart = 5;

// Within a bounce's (or a crossing's) block.
constexpr uint32_t kRoulette = 0, kScatterLobe = 1, kScatterDirection = 2, kMedium = 3,
                   kGather = kMedium + kMediumRun;
constexpr uint32_t kBounceDims = kGather + kGatherRun;
constexpr uint32_t kCrossingDims = kBounceDims;

// Within a next-event estimation block.
constexpr uint32_t kNeeLightChoice = 0, kNeeLightPoint = 1, kNeeVolumePoint = 2, kNeeMedia = 4;
constexpr uint32_t kNeeDims = kNeeMedia + kMediumRun;
// A volume light's point takes two more positions: a 2D draw then a 1D draw.
constexpr uint32_t kVolumePointDims = 2;

// Within a light-tracing block.
constexpr uint32_t kLensPoint = 0, kLensMedia = 1;
constexpr uint32_t kLensDims = kLensMedia + kMediumRun;

inline uint32_t bounce(uint32_t k, uint32_t offset) { return kWalkStart + k * kBounceDims + offset; }
inline uint32_t crossing(uint32_t k, uint32_t c, uint32_t max_vertices, uint32_t offset) {
  return ((c - 1) * max_vertices + k) * kCrossingDims + offset;
}
inline uint32_t next_event(uint32_t vertex, uint32_t offset) { return vertex * kNeeDims + offset; }
inline uint32_t lens(uint32_t light_vertex, uint32_t offset) { return light_vertex * kLensDims + offset; }
// Inner connections (s, t >= 2) numbered by depth d = s + t - 2, then s.
inline uint32_t connection(uint32_t s, uint32_t t) {
  uint32_t d = s + t - 2;
  return (d * (d + 1) / 2 + s) * kMediumRun;
}

// The segment's media block: bounce k's own for its first segment (c = 0), a crossing
// block after c boundaries or layers.
struct SegmentDims {
  SampleStream stream;
  uint32_t position;
};
inline SegmentDims segment(bool camera, uint32_t k, uint32_t c, uint32_t max_vertices, uint32_t offset) {
  if (c == 0) return {camera ? SampleStream::Camera : SampleStream::Light, bounce(k, offset)};
  return {camera ? SampleStream::CameraCrossing : SampleStream::LightCrossing, crossing(k, c, max_vertices, offset)};
}

// The largest paths the settings allow (max_bounces 1024, 256 crossings per path) fit.
constexpr uint32_t kMaxVertices = 1026, kMaxCrossings = 256;
static_assert(uint64_t(kMaxCrossings - 1) * kMaxVertices * kCrossingDims + uint64_t(kMaxVertices) * kCrossingDims <=
              kMaxStreamPosition);
static_assert(uint64_t(kWalkStart) + uint64_t(kMaxVertices) * kBounceDims <= kMaxStreamPosition);
static_assert((uint64_t(kMaxVertices) * (kMaxVertices + 1) / 2 + kMaxVertices) * kMediumRun <= kMaxStreamPosition);

// The sample's shutter time in [0, 1) (scene/motion.h), drawn only in scenes that move.
inline float shutter_time(Sampler &sampler) {
  sampler.start_stream(SampleStream::Camera, kCameraTime);
  return sampler.get_1d();
}

// A volume light's point numbers at `position` of `stream` (a 2D, then a 1D draw):
// drawn only when the light chosen is a volume light.
inline Vec3 volume_point(Sampler &sampler, SampleStream stream, uint32_t position) {
  sampler.start_stream(stream, position);
  Vec2 a = sampler.get_2d();
  return Vec3(a.x, a.y, sampler.get_1d());
}

}  // namespace rdv::dims
