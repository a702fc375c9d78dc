#include "integrators/mlt/metropolis.h"
#include "core/limits.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <nlohmann/json.hpp>
#include "core/log.h"
#include "samplers/dimension_layout.h"

namespace rdv::mlt {

namespace {

// A bootstrap sample's numbers come from a generator of their own (seed, index), so a
// chain can replay the sample it starts from.
uint64_t bootstrap_seed(uint32_t seed) { return uint64_t(hash_combine(seed, 0x6d6c7462u)) << 16; }
uint64_t chain_seed(uint32_t seed) { return uint64_t(hash_combine(seed, 0x6d6c7463u)) << 16; }
uint64_t pilot_seed(uint32_t seed) { return uint64_t(hash_combine(seed, 0x6d6c7470u)) << 16; }
// Relative target: pilot samples per pixel of the rendered region (per path depth,
// multiplexed), so the map's 8 x 8 blocks each average a few hundred samples.
constexpr uint64_t kPilotPerPixel = 4;
constexpr uint64_t kPilotLeaves = 16;  // the pilot's partial maps (memory: leaves x blocks floats)
constexpr uint64_t kChainStreams = 1ull << 48;  // chain streams: apart from bootstrap indices

constexpr uint32_t kFirstHitSamples = 4;  // camera rays per pixel for the Depth / Normal / Albedo passes
// With light passes, the colour passes divide Direct and Indirect: a pixel on a
// silhouette needs more rays than the AOVs for its colour to converge as the light does;
// and a compositor cuts objects out along Cryptomatte's and the shader AOVs' edges, which
// 4 rays would step in quarters. One ray per 8 mutations per pixel, 4 .. 64 (64 with a time
// limit): 64 rays a pixel are ~0.1% of 512 mutations' time.
constexpr uint32_t kMaxColorSamples = 64;
uint32_t first_hit_samples(bool edge_passes, uint32_t mutations) {
  if (!edge_passes) return kFirstHitSamples;
  return mutations == 0 ? kMaxColorSamples : std::clamp(mutations / 8, kFirstHitSamples, kMaxColorSamples);
}
// Vertices of a first-hit walk: the camera and up to 16 surfaces it sees through (Cycles'
// default Transparent max bounces is 8).
constexpr int kFirstHitVertices = 18;

// Samples per path depth of the pilot or the bootstrap, for `per_pixel` of the region's
// pixels (at least 4096). Up to kFullDepths depths (multiplexed) each get all of it; more
// share it, so the start-up grows with the region, not with the region times the depths:
// at 1000 bounces (a depth each) mmlt made no mutation in 18 s on a 128 x 128 furnace, and
// each deep sample traces its whole depth. Every depth's b stays the unbiased mean of its
// own samples (just noisier), and the large steps go on refining b while the chains run.
constexpr int kFullDepths = 16;
uint64_t samples_per_depth(uint64_t per_pixel, uint64_t region_pixels, int depths) {
  const double share = std::min(1.0, double(kFullDepths) / double(std::max(depths, 1)));
  return uint64_t(std::ceil(std::max(4096.0, double(per_pixel) * double(region_pixels)) * share));
}

// Path space: the large steps' weight of each vertex count n in first .. last (index
// n - first), the root of the sum of the bootstrap's (target / q)^2 over its paths of n vertices. The bootstrap drew the
// counts uniformly, so this is in proportion to their root mean square: the share of
// samples that minimises the variance of b (measured over 16 seeds, docs/mlt.md: b's
// spread 1.9% -> 1.4% on the volume caustic, 1.1% -> 1.0% on the fog door).
std::vector<double> length_weights(const std::vector<float> &weights, const std::vector<uint16_t> &vertices, int first,
                                   int last) {
  std::vector<double> sum2(size_t(last - first + 1), 0.0);
  for (size_t i = 0; i < weights.size(); ++i)
    if (vertices[i] >= first && vertices[i] <= last) sum2[size_t(vertices[i] - first)] += double(weights[i]) * weights[i];
  for (double &v : sum2) v = std::sqrt(v);
  return sum2;
}

// A state's splats and their light-pass shares into a chain's pass, weighted by w.
void record_splats(const State &state, float w, std::vector<Splat> &splats, std::vector<SlotShare> &shares) {
  const SlotShare *share = state.shares.data();
  for (const Splat &sp : state.splats) {
    if (!is_black(sp.L)) {
      splats.push_back({sp.raster, sp.L * w, Splat::kNoStrategy, sp.light_pass, sp.catcher});
      for (int k = 0; k < sp.light_pass.shares; ++k) shares.push_back({share[k].L * w, share[k].slot});
    }
    share += sp.light_pass.shares;
  }
}

}  // namespace

// A Markov chain: its sampler (the state's numbers), its state and proposal, and what it
// did in the current pass (splats, applied after the pass in chain order).
struct Chain {
  Chain(uint64_t seed, uint64_t stream, const MltSettings &mlt)
      : sampler(seed, stream, mlt.step_size, mlt.large_step_probability) {}
  PssSampler sampler;
  uint64_t start = 0;  // the bootstrap sample it started from
  Pcg32 acceptance;
  State current, proposal;
  std::vector<Splat> splats;
  std::vector<SlotShare> shares;  // light passes: the splats' slot shares (Splat::light_pass.shares)
  uint64_t small_steps = 0, small_accepted = 0, large_steps = 0, large_accepted = 0, large_found = 0, rays = 0;
  double large_sum = 0, large_sum2 = 0;  // targets of its large-step proposals
  std::vector<uint64_t> strategy_counts;
  // Path space: the state's path and the proposal's, and the mutations' generator.
  ExplicitPath path, path_proposal;
  Pcg32 mutation;
  ImageStrata strata;  // the lens subpath mutation's image positions
  uint64_t type_proposed[kMutationTypes] = {}, type_accepted[kMutationTypes] = {};
};

double Metropolis::memory_estimate(const RenderSettings &settings, bool multiplexed, bool path_space) {
  const double region_pixels = double(settings.border.width()) * double(settings.border.height());
  const double depths = multiplexed ? settings.max_bounces + 1 : 1;
  const double bootstrap =
      double(samples_per_depth(settings.mlt_bootstrap, uint64_t(region_pixels), int(depths))) * depths;
  // Per bootstrap sample: its target, the start distribution's function and CDF, its
  // strategy (multiplexed). Per chain: the chain, and its sampler's and states' buffers
  // (a few kB, grown with the path length).
  const double per_sample = 3 * sizeof(float) + (multiplexed ? 1 : 0);
  double per_chain = sizeof(Chain) + 4096 + 64.0 * (settings.max_bounces + 2);
  if (path_space) per_chain += 2.0 * sizeof(ExplicitVertex) * (settings.max_bounces + 2);  // two explicit paths
  // Relative target: the pilot's partial maps (a float per block of the sample region).
  const double r = PixelFilter(settings.filter_width).radius();
  const double blocks = std::ceil((settings.border.width() + 2 * r) / ImportanceMap::kBlock + 1) *
                        std::ceil((settings.border.height() + 2 * r) / ImportanceMap::kBlock + 1);
  const double pilot = settings.relative_mlt_target(path_space) ? double(2 * kPilotLeaves + 6) * blocks * sizeof(float) : 0.0;
  return bootstrap * per_sample + double(settings.mlt_chains) * per_chain + pilot;
}

Metropolis::Metropolis(const Scene &scene, const RenderSettings &settings, const bdpt::BdptSettings &bdpt_settings,
                       const MltSettings &mlt)
    : scene_(scene), settings_(settings), bdpt_(scene, bdpt_settings), mlt_(mlt) {
  const float r = PixelFilter(settings.filter_width).radius();
  const Rect &b = settings.border;
  sample_origin_ = {float(b.x0) - r, float(b.y0) - r};
  sample_size_ = {float(b.width()) + 2 * r, float(b.height()) + 2 * r};
  region_area_ = sample_size_.x * sample_size_.y;
  image_area_ = float(settings.width) * float(settings.height);
  if (mlt.path_space) {
    MutationSettings mutations = mlt.mutations;
    if (mlt.direct_samples > 0 && bdpt_settings.max_bounces >= 2) {
      direct_ = std::make_unique<PathTracer>(scene, 1, bdpt_settings.limits, bdpt_settings.alpha);
      mutations.min_vertices = 4;  // the chains' paths: three edges or more
    }
    path_space_ = std::make_unique<PathSpace>(scene, bdpt_settings.max_bounces, sample_origin_, sample_size_, image_area_,
                                              mlt.large_step_probability, mutations, bdpt_settings.limits);
    // Plain transparent layers are parts of edges (path_space.h); transparent surfaces that
    // emit, hold out or catch shadows stay path vertices (docs/mlt.md): light from a lamp
    // without a size reaches a surface through one only by the light side, which cannot join
    // the camera through one either, so where the camera sees that surface through one too
    // (or with an orthographic camera) the light is missing. Said, not hidden.
    const bool delta_light = std::any_of(scene.lights().begin(), scene.lights().end(),
                                         [](const Light &l) { return l.is_delta(); });
    if (delta_light && scene.has_transparent_non_layers()) {
      stats_.warning = std::string(name()) +
                       ": light from lamps without a size (point or spot radius 0, sun angle 0) that passes a "
                       "transparent surface (alpha, Transparent BSDF) that emits, holds out or catches shadows is "
                       "missing" +
                       (direct_ ? " after a bounce (the path tracer takes direct light)" : "") +
                       " where the camera sees its surface through one too, or through an orthographic camera "
                       "(docs/mlt.md); use bdpt, or give the lamps a size";
      log_warning(stats_.warning);
    }
  }
}

void Metropolis::direct_pass(RenderContext &ctx) const {
  const std::vector<Rect> tiles = TileIntegrator::tiles(settings_.border);
  // A farm part (sample_offset o, render_part.h) takes samples [o N, o N + N) of the
  // sequence: parts never repeat one, and their merged pixel sums average all of them.
  const uint64_t n = mlt_.direct_samples;
  const uint64_t first = std::min<uint64_t>(uint64_t(settings_.sample_offset) * n, UINT32_MAX - n);
  ctx.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t> &r) {
      TileSplats none;  // the path tracer reaches no pixel but its own
      for (size_t i = r.begin(); i != r.end(); ++i)
        direct_->render_tile(ctx, tiles[i], uint32_t(first), uint32_t(first + n), {}, none);
    });
  });
}

void Metropolis::first_hit_pass(RenderContext &ctx) const {
  const Rect &region = settings_.border;
  const bool media = scene_.has_media();
  const bool alpha = bdpt_.settings().alpha.tracked();
  const bool light_passes = ctx.film.has_light_passes();
  const bool denoising_passes = ctx.film.has_denoising_passes();
  const bool catchers = catchers_;
  const bool edge_passes = light_passes || !ctx.film.cryptomatte().empty() || !ctx.film.shader_aovs().empty();
  const uint32_t samples = first_hit_samples(edge_passes, settings_.samples);
  ctx.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(region.y0, region.y1, 1), [&](const tbb::blocked_range<int> &rows) {
      // Up to the camera's see-through chain's length (transparent layers in front).
      thread_local std::vector<bdpt::PathVertex> path(kFirstHitVertices);
      SobolSampler sampler(settings_.seed_for_chains());
      RayStats stats;
      thread_local FilmTile rows_tile;  // these rows' pixels, published whole
      ctx.film.take_tile(Rect{region.x0, rows.begin(), region.x1, rows.end()}, rows_tile);
      for (int y = rows.begin(); y != rows.end(); ++y) {
        if (ctx.control.should_stop()) break;
        for (int x = region.x0; x < region.x1; ++x) {
          for (uint32_t i = 0; i < samples; ++i) {
            sampler.start_sample(uint32_t(x), uint32_t(y), i);
            Vec2 uf = sampler.get_2d();
            Vec2 raster{x + 0.5f + ctx.filter.sample(uf.x), y + 0.5f + ctx.filter.sample(uf.y)};
            Vec2 u_lens = sampler.get_2d();
            shutter::SampleTime at(scene_.has_motion() ? dims::shutter_time(sampler) : shutter::now());
            CameraRay cr;
            cr.ray = scene_.camera_now().generate_ray(raster, u_lens, &cr.lens_point, &cr.cone);
            // The walk ends where the camera stops seeing through (its first scattering).
            DataPassSample data;
            data.denoising.active = denoising_passes;
            data.aovs.start(&ctx.film.shader_aovs());
            data.crypto.start(&ctx.film.cryptomatte());
            int n = media ? bdpt_.camera_subpath<true>(cr, sampler, stats, path.data(), nullptr, kFirstHitVertices,
                                                       &data, true)
                          : bdpt_.camera_subpath<false>(cr, sampler, stats, path.data(), nullptr, kFirstHitVertices,
                                                        &data, true);
            FirstHit hit = bdpt_.first_surface(path.data(), n);
            // The pixel's sample count averages the AOVs and the alpha (from first hits:
            // the world seen straight from the camera); the image itself is all splats.
            const float transparency = alpha ? bdpt_.transparency(path.data(), n) : 0.0f;
            rows_tile.add_sample(x, y, Color(0.0f), false, transparency);
            rows_tile.add_data_passes(x, y, data, i == 0 && settings_.sample_offset == 0);
            if (light_passes) {  // the colour passes: the closures the camera sees first (light_passes.cpp)
              LightPassSample colors;
              colors.clear();
              bdpt::Bdpt::add_color_passes(data, colors);
              rows_tile.add_light_passes(x, y, colors);
            }
            if (catchers) {  // the camera side of the shadow catcher's sums (contribution.cpp)
              CatcherSample catcher;
              bdpt_.camera_catcher_values(path.data(), n, catcher);
              const float clamp = settings_.clamp;  // as BDPT's tile loop clamps the world behind
              if (clamp > 0 && max_component(catcher.background) > clamp)
                catcher.background *= clamp / max_component(catcher.background);
              if (catcher.valid()) rows_tile.add_shadow_catcher(x, y, catcher);
            }
            if (hit.valid) rows_tile.add_first_hit(x, y, hit.depth, hit.normal, hit.albedo);
            else rows_tile.add_first_hit(x, y, 1e10f, Vec3(0.0f), Color(0.0f));
          }
        }
      }
      ctx.film.put_tile(rows_tile);
      ctx.control.add_rays(stats.rays);
    });
  });
}

ImportanceMap Metropolis::pilot(RenderContext &ctx, int depths) {
  constexpr int B = ImportanceMap::kBlock;
  const int blocks_x = (int(std::ceil(sample_size_.x)) + B - 1) / B;
  const int blocks_y = (int(std::ceil(sample_size_.y)) + B - 1) / B;
  const size_t blocks = size_t(blocks_x) * size_t(blocks_y);
  const uint64_t region_pixels = uint64_t(settings_.border.width()) * uint64_t(settings_.border.height());
  const uint64_t per_depth = samples_per_depth(kPilotPerPixel, region_pixels, depths);
  const uint64_t n = per_depth * uint64_t(depths);
  const uint64_t seed0 = pilot_seed(settings_.seed_for_chains());
  // Per block: the luminance, then the light-carrying splats.
  using Grid = std::vector<float>;
  // A deterministic reduction (fixed leaves, fixed join order): the map, and so the
  // image, is the same on any number of threads. kPilotLeaves grids at most.
  Grid sum;
  ctx.arena.execute([&] {
    sum = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<uint64_t>(0, n, std::max<uint64_t>(256, n / kPilotLeaves)), Grid(),
        [&](const tbb::blocked_range<uint64_t> &r, Grid grid) {
          if (grid.empty()) grid.assign(2 * blocks, 0.0f);
          if (ctx.control.should_stop()) return grid;
          RayStats stats;
          State state;
          for (uint64_t i = r.begin(); i != r.end(); ++i) {
            // A leaf holds 1/16 of the pilot (0.2 s at 320x240 in fog): look for a cancel
            // inside it too. A stopped pilot's map is never used.
            if ((i & 63) == 0 && ctx.control.should_stop()) break;
            PssSampler sampler(seed0, i, mlt_.step_size, mlt_.large_step_probability);
            sampler.start_iteration();
            evaluate(sampler, stats, state, mlt_.multiplexed ? int(i / per_depth) : -1);
            for (const Splat &sp : state.splats) {
              if (sp.catcher == CatcherSplat::Matte) continue;  // as target_of
              const float y = luminance(sp.L);
              if (!(y > 0)) continue;
              const size_t at = ImportanceMap::block_of(sp.raster, sample_origin_, blocks_x, blocks_y);
              grid[at] += y;
              grid[blocks + at] += 1;
            }
          }
          ctx.control.add_rays(stats.rays);
          return grid;
        },
        [&](Grid a, const Grid &b) {
          if (a.empty()) return b;
          for (size_t i = 0; i < b.size(); ++i) a[i] += b[i];
          return a;
        });
  });
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.pilot_samples = n;
  }
  if (sum.empty()) sum.assign(2 * blocks, 0.0f);
  // Each depth's samples estimate that depth's image: the map sums the depths' means.
  const std::vector<float> luminance_sum(sum.begin(), sum.begin() + std::ptrdiff_t(blocks));
  const std::vector<float> hits(sum.begin() + std::ptrdiff_t(blocks), sum.end());
  return ImportanceMap(luminance_sum, hits, blocks_x, blocks_y, sample_origin_, double(per_depth));
}

void Metropolis::render(RenderContext &ctx) {
  // Shadow catchers change the target (target_of): known before the pilot and bootstrap.
  catchers_ = ctx.film.has_shadow_catcher();
  if (path_space_) path_space_->set_film(catchers_, bdpt_.settings().alpha);
  if (direct_) direct_pass(ctx);
  else first_hit_pass(ctx);
  const Rect &region = settings_.border;
  const uint64_t region_pixels = uint64_t(region.width()) * uint64_t(region.height());
  const float p_large = mlt_.large_step_probability;
  const int depths = mlt_.multiplexed ? bdpt_.settings().max_bounces + 1 : 1;
  if (mlt_.relative_target) {
    importance_ = pilot(ctx, depths);
    if (ctx.control.should_stop()) return;
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.relative_share = importance_.relative_share();
  }

  // Bootstrap: independent samples (per path depth, multiplexed), their targets.
  const uint64_t per_depth = samples_per_depth(mlt_.bootstrap_per_pixel, region_pixels, depths);
  const uint64_t n_bootstrap = per_depth * uint64_t(depths);
  std::vector<float> weights(n_bootstrap);
  std::vector<uint8_t> strategy(mlt_.multiplexed ? n_bootstrap : 0);  // s of each (multiplexed)
  std::vector<uint16_t> vertices(path_space_ ? n_bootstrap : 0);       // path space: each path's length
  const uint64_t seed0 = bootstrap_seed(settings_.seed_for_chains());
  std::atomic<bool> specular_paths{false};  // path space: a bootstrap path with a specular vertex
  ctx.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, n_bootstrap, 256), [&](const tbb::blocked_range<uint64_t> &r) {
      if (ctx.control.should_stop()) return;
      RayStats stats;
      State state;
      ExplicitPath path;
      for (int t = 0; t < kMutationTypes; ++t) stats_.type_proposed[t] = stats_.type_accepted[t] = 0;
      for (uint64_t i = r.begin(); i != r.end(); ++i) {
        if (path_space_) {
          // An independent path from the sample's own generator (a chain replays it).
          Pcg32 rng(seed0, i);
          double q = path_space_->sample_independent(rng, stats, path);
          double w = q > 0 ? double(path_target(path)) / q : 0.0;
          weights[i] = std::isfinite(w) ? float(w) : 0.0f;
          vertices[i] = uint16_t(path.n);
          if (q > 0 && !specular_paths.load(std::memory_order_relaxed))
            for (int k = 1; k + 1 < path.n; ++k)
              if (path.x[size_t(k)].v.delta) specular_paths.store(true, std::memory_order_relaxed);
          continue;
        }
        PssSampler sampler(seed0, i, mlt_.step_size, p_large);
        sampler.start_iteration();
        evaluate(sampler, stats, state, mlt_.multiplexed ? int(i / per_depth) : -1);
        weights[i] = state.target;
        if (mlt_.multiplexed) strategy[i] = uint8_t(state.s);
      }
      ctx.control.add_rays(stats.rays);
    });
  });
  if (ctx.control.should_stop()) return;
  if (path_space_) path_space_->set_specular_paths(specular_paths.load());

  // b (the image's total luminance, in the targets' units) and its standard error,
  // per depth; sums in index order, the same on any thread count.
  std::vector<double> depth_b(size_t(depths), 0.0);
  double b = 0, variance = 0;
  for (int d = 0; d < depths; ++d) {
    double sum = 0, sum2 = 0;
    for (uint64_t i = uint64_t(d) * per_depth; i < uint64_t(d + 1) * per_depth; ++i) {
      sum += weights[i];
      sum2 += double(weights[i]) * weights[i];
    }
    double mean = sum / double(per_depth);
    depth_b[size_t(d)] = mean;
    b += mean;
    variance += std::max(0.0, sum2 / double(per_depth) - mean * mean) / double(per_depth);
  }
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.bootstrap_samples = n_bootstrap;
    stats_.b = b;
    stats_.b_standard_error = std::sqrt(variance);
    if (mlt_.multiplexed) {
      stats_.depth_b = depth_b;
      stats_.strategy_counts.assign(strategy_index(depths, 0), 0);
      stats_.strategy_b.assign(strategy_index(depths, 0), 0.0);
      for (uint64_t i = 0; i < n_bootstrap; ++i)
        stats_.strategy_b[strategy_index(int(i / per_depth), strategy[i])] += weights[i] / double(per_depth);
    }
  }
  if (direct_ && b == 0) {
    // Direct light may be all the scene has (one plane under a lamp): the path tracer's
    // samples are the image, the chains have nothing to do.
    Film::PassPublisher frame(ctx.film);
    frame.publish(mlt_.direct_samples, {});
    return;
  }
  if (!(b > 0) || !std::isfinite(b)) {
    std::string why = !(b > 0) ? "none of its " + std::to_string(n_bootstrap) +
                                     " bootstrap paths carried light to the camera (no light, every light blocked "
                                     "or facing away, or max_bounces too small): the image is black"
                               : "the bootstrap's light estimate overflowed: the image is black";
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const std::string warning = std::string(name()) + ": " + why;
    stats_.warning = stats_.warning.empty() ? warning : stats_.warning + "; " + warning;  // after the scene's own
    log_warning(warning);
    return;  // no pass is published: the frame stays black
  }
  if (mlt_.multiplexed) {
    // Each depth by its share of b, with a floor: a depth the bootstrap missed still
    // gets chosen (its paths exist), so no depth is left out of the image.
    std::vector<float> w(depth_b.size());
    for (size_t d = 0; d < w.size(); ++d) w[d] = float(depth_b[d] + 0.01 * b / double(depths));
    depth_distribution_ = Distribution1D(w);
  }

  // Chains: each starts from a bootstrap sample picked by importance (its target),
  // replayed from that sample's numbers, then mutates with a generator of its own.
  // Their states carry their light passes when the film keeps them (the pilot's and the
  // bootstrap's need none).
  light_passes_ = ctx.film.has_light_passes();
  const uint32_t n_chains = mlt_.chains;
  const Distribution1D starts(weights);
  std::vector<Chain> chains;
  chains.reserve(n_chains);
  const uint64_t chain_seed0 = chain_seed(settings_.seed_for_chains());
  for (uint32_t c = 0; c < n_chains; ++c) {
    Pcg32 pick(chain_seed0, kChainStreams + 2 * uint64_t(c));
    uint64_t i = starts.sample_discrete(pick.next_float(), nullptr);
    chains.emplace_back(seed0, i, mlt_);
    chains.back().start = i;
    chains.back().acceptance = Pcg32(chain_seed0, kChainStreams + 2 * uint64_t(c) + 1);
  }
  ctx.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n_chains, 1), [&](const tbb::blocked_range<uint32_t> &r) {
      RayStats stats;
      for (uint32_t c = r.begin(); c != r.end(); ++c) {
        Chain &chain = chains[c];
        if (path_space_) {
          Pcg32 rng(seed0, chain.start);
          path_space_->sample_independent(rng, stats, chain.path);
          path_state(chain.path, chain.current);
          chain.path_proposal.reserve(path_space_->max_vertices());
          chain.mutation = Pcg32(chain_seed0, kChainStreams + 2 * uint64_t(n_chains) + uint64_t(c));
          chain.strata = ImageStrata(sample_origin_, sample_size_, hash3(uint32_t(chain_seed0), uint32_t(chain_seed0 >> 32), c));
          continue;
        }
        chain.sampler.start_iteration();
        int depth = mlt_.multiplexed ? int(chain.start / per_depth) : -1;
        evaluate(chain.sampler, stats, chain.current, depth);
        if (mlt_.multiplexed) {
          // The state's depth number where that depth lies; its target is now per
          // depth choice (divided by the depth's probability).
          float pmf = depth_distribution_.cdf(size_t(depth) + 1) - depth_distribution_.cdf(size_t(depth));
          float u = depth_distribution_.cdf(size_t(depth)) + 0.5f * pmf;
          float sampled_pmf;
          if (depth_distribution_.sample_discrete(u, &sampled_pmf) != size_t(depth)) pmf = 0;
          chain.sampler.set(SampleStream::Strategy, 0, u);
          float inv = pmf > 0 ? 1.0f / sampled_pmf : 0.0f;
          for (Splat &sp : chain.current.splats) sp.L *= inv;
          for (SlotShare &share : chain.current.shares) share.L *= inv;
          chain.current.target *= inv;
          chain.strategy_counts.assign(strategy_index(depths, 0), 0);
        }
        chain.sampler.accept();
        chain.sampler.reseed(chain_seed0, kChainStreams + 2 * uint64_t(n_chains) + uint64_t(c));
      }
      ctx.control.add_rays(stats.rays);
    });
  });
  if (path_space_)
    path_space_->set_length_weights(
        length_weights(weights, vertices, path_space_->min_vertices(), path_space_->max_vertices()));

  // Passes: a deterministic schedule (each chain's share of the mutations, growing
  // passes up to a memory cap), so the splats are summed in the same order on any
  // number of threads. A pass the time limit interrupts still counts (its mutations are
  // as good as any): the image is normalised by the mutations actually made.
  // samples 0: until the time limit or the noise target, but never past the mutations per
  // pixel the tile integrators' film can count (a target the estimate cannot reach, e.g.
  // under b's own error, would otherwise run for ever).
  const uint64_t total = uint64_t(settings_.samples ? settings_.samples : kMaxSamplesPerPixel) * region_pixels;
  const uint64_t first_pass = std::max<uint64_t>(1, region_pixels / (16 * uint64_t(n_chains)));
  const uint64_t max_pass = std::max<uint64_t>(1, std::min<uint64_t>(region_pixels, 1u << 20) / n_chains);
  std::vector<uint64_t> made(n_chains, 0);
  uint64_t done = 0;
  uint64_t pass_limit = max_pass;  // lowered near the noise target
  for (int pass = 0; !ctx.control.should_stop() && done < total; ++pass) {
    const uint64_t pass_size = std::min({max_pass, pass_limit, first_pass << std::min(pass, 20)});
    ctx.arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n_chains, 1), [&](const tbb::blocked_range<uint32_t> &r) {
        for (uint32_t c = r.begin(); c != r.end(); ++c) {
          uint64_t quota = total / n_chains + (c < total % n_chains ? 1 : 0);
          uint64_t n = std::min(pass_size, quota - std::min(quota, made[c]));
          Chain &chain = chains[c];
          chain.splats.clear();
          chain.shares.clear();
          RayStats stats;
          uint64_t m = 0;
          for (; m < n; ++m) {
            if ((m & 15) == 0 && ctx.control.should_stop()) break;
            bool large;
            double ratio = 1;  // T(y -> x) / T(x -> y): 1 for primary sample space's symmetric steps
            int type = 0;
            if (path_space_) {
              Proposal p = path_space_->mutate(chain.path, chain.mutation, stats, chain.path_proposal, &chain.strata);
              large = p.type == MutationType::Large;
              type = int(p.type);
              ++chain.type_proposed[type];
              ratio = p.ratio;
              path_state(chain.path_proposal, chain.proposal);
              if (!(ratio > 0)) {
                chain.proposal.splats.clear();
                chain.proposal.shares.clear();
                chain.proposal.target = 0;
              }
              // An independent sample of b, the target's integral: target(y) / q(y).
              chain.proposal.independent =
                  importance_.empty() ? p.independent : p.independent * importance_.weight(chain.path_proposal.raster);
            } else {
              chain.sampler.start_iteration();
              large = chain.sampler.large_step();
              evaluate(chain.sampler, stats, chain.proposal);
            }
            const float fx = chain.current.target, fy = chain.proposal.target;
            const float a = fx > 0 ? float(std::min(1.0, double(fy) * ratio / fx)) : 1.0f;
            // Veach's expected values: proposal and state splatted with the
            // probabilities a and 1 - a of being the next state, each over its
            // target (the image is b / mutations times their sum).
            if (fy > 0 && a > 0) record_splats(chain.proposal, a / fy, chain.splats, chain.shares);
            if (fx > 0 && a < 1) record_splats(chain.current, (1 - a) / fx, chain.splats, chain.shares);
            // A large step's proposal is an independent uniform sample: one more
            // sample of b.
            if (large) {
              const double independent = chain.proposal.independent;
              chain.large_found += independent > 0;
              chain.large_sum += independent;
              chain.large_sum2 += independent * independent;
            }
            (large ? chain.large_steps : chain.small_steps) += 1;
            if (a >= 1 || chain.acceptance.next_float() < a) {
              std::swap(chain.current, chain.proposal);
              if (path_space_) {
                std::swap(chain.path, chain.path_proposal);
                ++chain.type_accepted[type];
              } else {
                chain.sampler.accept();
              }
              (large ? chain.large_accepted : chain.small_accepted) += 1;
            } else if (!path_space_) {
              chain.sampler.reject();  // path space: the state was never touched
            }
            if (mlt_.multiplexed && chain.current.depth >= 0)
              ++chain.strategy_counts[strategy_index(chain.current.depth, chain.current.s)];
          }
          made[c] += m;
          chain.rays += stats.rays;
        }
      });
    });
    // A cancelled render keeps the frame it has: applying up to a pass of splats could
    // take longer than the ~100 ms a cancel may.
    if (ctx.control.cancel_requested()) break;
    // b from the bootstrap and every large-step proposal so far (independent samples
    // both; the bootstrap counts as per_depth samples of the whole image's b).
    double large_sum = 0, large_sum2 = 0;
    uint64_t large_steps = 0, rays = 0, done_b = 0;
    done = 0;
    for (size_t c = 0; c < chains.size(); ++c) {  // in chain order: the same sums on any thread count
      large_sum += chains[c].large_sum;
      large_sum2 += chains[c].large_sum2;
      large_steps += chains[c].large_steps;
      done += made[c];
      if (c & 1) done_b += made[c];
    }
    const double n_b = double(per_depth) + double(large_steps);
    const double b_now = (b * double(per_depth) + large_sum) / n_b;
    double large_variance =
        large_steps > 1 ? std::max(0.0, large_sum2 / double(large_steps) - std::pow(large_sum / double(large_steps), 2)) : 0.0;
    const double b_error =
        std::sqrt(variance * double(per_depth) * double(per_depth) + large_variance * double(large_steps)) / n_b;
    {
      // The splats and the frame state they make (mutations per pixel, b / mutations):
      // a read sees both or neither.
      // The odd chains make half image B (film/noise_estimate.h) when the settings
      // ask for an estimate: chains are independent, their samples are not.
      Film::PassPublisher frame(ctx.film);
      const bool halves = n_chains > 1 && settings_.estimates_noise();
      ctx.arena.execute([&] {
        frame.add_splats(ctx.filter, [&](const auto &visit) {  // in chain order: the same sums on any thread count
          for (size_t c = 0; c < chains.size(); ++c) {
            const SlotShare *share = chains[c].shares.data();
            for (const Splat &sp : chains[c].splats) {
              visit(sp.raster, sp.L, halves && (c & 1), sp.strategy, sp.light_pass, share, sp.catcher);
              share += sp.light_pass.shares;
            }
          }
        });
      });
      for (Chain &chain : chains) {
        chain.splats.clear();
        chain.shares.clear();
      }
      if (done > 0)
        frame.publish(uint32_t(std::min<uint64_t>(done / region_pixels, UINT32_MAX)), {b_now, double(done)},
                      halves ? HalfSplit::Splats : HalfSplit::None, {b_now, double(done_b)},
                      b_now > 0 ? (b_error / b_now) * (b_error / b_now) : 0.0);
    }
    if (settings_.estimates_noise() && done > 0) {
      const double estimate = ctx.film.relative_mse_estimate();
      ctx.control.report_noise_estimate(estimate);
      // The estimate falls as 1 / mutations: the next pass makes at most the mutations
      // it takes to reach the target.
      if (settings_.noise_target > 0 && std::isfinite(estimate) && estimate > settings_.noise_target) {
        double needed = std::ceil(double(done) * (estimate / settings_.noise_target - 1.0) / double(n_chains));
        pass_limit = uint64_t(std::clamp(needed, 1.0, double(max_pass)));
      }
    }
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      stats_.mutations = done;
      stats_.b = b_now;
      stats_.b_standard_error = b_error;
      stats_.small_steps = stats_.small_accepted = stats_.large_steps = stats_.large_accepted = stats_.large_found = 0;
      if (mlt_.multiplexed) std::fill(stats_.strategy_counts.begin(), stats_.strategy_counts.end(), 0);
      // The chains' counts are totals since the start: summed afresh each pass.
      std::fill(std::begin(stats_.type_proposed), std::end(stats_.type_proposed), 0);
      std::fill(std::begin(stats_.type_accepted), std::end(stats_.type_accepted), 0);
      for (Chain &chain : chains) {
        stats_.small_steps += chain.small_steps;
        stats_.small_accepted += chain.small_accepted;
        stats_.large_steps += chain.large_steps;
        stats_.large_accepted += chain.large_accepted;
        stats_.large_found += chain.large_found;
        for (int t = 0; t < kMutationTypes; ++t) {
          stats_.type_proposed[t] += chain.type_proposed[t];
          stats_.type_accepted[t] += chain.type_accepted[t];
        }
        rays += chain.rays;
        chain.rays = 0;
        for (size_t k = 0; k < chain.strategy_counts.size(); ++k) stats_.strategy_counts[k] += chain.strategy_counts[k];
      }
    }
    ctx.control.add_rays(rays);
  }
}

std::string Metropolis::stats_json() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  nlohmann::json j;
  j["integrator"] = name();
  j["chains"] = mlt_.chains;
  j["bootstrap_samples"] = stats_.bootstrap_samples;
  j["b"] = stats_.b;
  j["b_standard_error"] = stats_.b_standard_error;
  j["target"] = mlt_.relative_target ? "relative" : "luminance";
  if (mlt_.relative_target) {
    j["pilot_samples"] = stats_.pilot_samples;
    j["relative_share"] = stats_.relative_share;
  }
  j["mutations"] = stats_.mutations;
  j["small_steps"] = stats_.small_steps;
  j["large_steps"] = stats_.large_steps;
  j["small_step_acceptance"] = stats_.small_steps ? double(stats_.small_accepted) / double(stats_.small_steps) : 0.0;
  j["large_step_acceptance"] = stats_.large_steps ? double(stats_.large_accepted) / double(stats_.large_steps) : 0.0;
  // The share of large steps (independent uniform proposals) that found a light-carrying
  // path at all: the ceiling of their acceptance.
  j["large_step_found"] = stats_.large_steps ? double(stats_.large_found) / double(stats_.large_steps) : 0.0;
  if (mlt_.path_space) {
    // Per mutation type: proposals and acceptance ("large": the whole path regenerated,
    // Veach's bidirectional mutation at its largest; small steps are all the others).
    nlohmann::json types = nlohmann::json::object();
    for (int t = 0; t < kMutationTypes; ++t) {
      const uint64_t n = stats_.type_proposed[t];
      const double acceptance = n ? double(stats_.type_accepted[t]) / double(n) : 0.0;
      const std::string name = mutation_name(MutationType(t));
      types[name] = {{"proposals", n}, {"acceptance", acceptance}};
      if (t != int(MutationType::Large)) j[name + "_acceptance"] = acceptance;
    }
    j["mutation_types"] = types;
  }
  if (mlt_.multiplexed) {
    j["depth_b"] = stats_.depth_b;
    j["strategy_counts"] = stats_.strategy_counts;
    j["strategy_b"] = stats_.strategy_b;
  }
  if (!stats_.warning.empty()) j["warning"] = stats_.warning;
  return j.dump();
}

}  // namespace rdv::mlt
