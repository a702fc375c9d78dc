// Render parts: what a farm task writes so that `rendezvous merge` can add parts into
// the image one render of all their samples gives (docs/farm.md).
//
// Every EXR the engine writes is a part: besides the image it carries the film's raw
// sums (per-pixel sample sums and counts, splat sums, AOV sums; doubles stored bit for
// bit as pairs of 32-bit unsigned channels in the layer "RdvMerge") and a header
// attribute "rendezvous:part" (JSON: scene hash, the settings that shape the image,
// the sample ranges held, the splat normalisation). Merging adds the sums and writes
// them through the same Film::read as a render, so the merged image is the whole
// render's up to the rounding of double sums added in another order.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include "film/film.h"

namespace rdv {

struct SampleRange {
  uint64_t begin = 0, end = 0;  // samples [begin, end) of the render's sequence
};

struct PartRecord {
  std::string scene_hash;
  std::string settings_json;         // RenderSettings::image_settings_json
  std::vector<SampleRange> ranges;   // sorted, disjoint
  SplatNormalisation splats;
  // The part keeps half image B of its camera samples (path, bdpt estimating their noise:
  // the odd samples of the whole render's sequence), so merged parts have the halves, the
  // Noise pass and the estimate one render of all the samples would. Metropolis parts'
  // halves (odd chains, each part its own b) are not merged.
  bool halves = false;
  SplatNormalisation half_splats;  // half B's splats: numerator / its paths
  // The passes the part carries beyond the image's (a merge keeps those every part has):
  // Cycles' light passes' sums, the data passes as EXR layers (their sums are always
  // there), BDPT's strategy passes' sums of paths up to this depth (-1: none),
  // Cycles' denoising data's sums (denoising_passes).
  bool light_passes = false, data_passes = false, denoising_passes = false;
  // Shader AOVs (film/shader_aovs.h): their settings (ShaderAovs::to_json; null: none), with
  // their sums carried. Parts of engines before 2026-11-30 wrote `true` here and no sums.
  nlohmann::json shader_aovs;
  // Cryptomatte (film/cryptomatte.h): its settings (Cryptomatte::to_json; null: none) and
  // metadata (names, manifests); its slots are carried, and a merge combines them by id.
  nlohmann::json cryptomatte, crypto_metadata;
  int strategy_max_depth = -1;
  // A shadow catcher's sums (film/shadow_catcher_passes.h) and how Combined reads with them.
  bool shadow_catcher = false;
  CatcherDisplay catcher_display;

  std::string to_json() const;
  // Throws an Error naming `part` (a file name) when the text is not a part record.
  static PartRecord from_json(const std::string &text, const std::string &part);
};

// The extra channels of a part, appended to an image's channels: names and, per
// pixel (row-major from the top), that many 32-bit words.
struct PartChannels {
  std::vector<std::string> names;
  std::vector<uint32_t> words;  // width * height * names.size()
};
PartChannels part_channels(const Film &film, const PartRecord &record);
const char *part_attribute_name();  // the EXR header attribute holding PartRecord::to_json

struct MergeOptions {
  bool allow_missing = false;  // write the merge of the ranges present when some are missing
  uint64_t expected_samples = 0;  // > 0: the ranges must cover [0, expected_samples)
};

struct MergeResult {
  std::unique_ptr<Film> film;
  PartRecord record;
  std::vector<SampleRange> missing;
  std::vector<std::string> warnings;
  std::string report_json() const;
};

// Reads the parts and adds them. Refuses (an Error naming the part and the problem)
// parts of different scenes or settings, overlapping ranges, unreadable or foreign
// files, and missing ranges unless options.allow_missing.
MergeResult merge_parts(const std::vector<std::string> &paths, const MergeOptions &options);

}  // namespace rdv
