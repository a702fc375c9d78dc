#include "film/render_part.h"
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "core/limits.h"

namespace rdv {

namespace {

using json = nlohmann::json;

// Channel layout of the layer "RdvMerge": each double as two words (high, low), so a
// part holds its sums bit for bit (EXR has no 64-bit channels).
constexpr const char *kLayer = "RdvMerge.";
constexpr int kWordsPerPixel = 6 + 1 + 6 + 6 + 6 + 1 + 2 + 4;
// The last channels (the transparency sum, the data passes) are newer than the format:
// a part without them has an opaque film and no data passes (0).
constexpr int kOptionalChannels = 6;

void put_double(uint32_t *&w, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  *w++ = uint32_t(bits >> 32);
  *w++ = uint32_t(bits);
}
double get_double(const uint32_t *&w) {
  uint64_t bits = (uint64_t(w[0]) << 32) | w[1];
  w += 2;
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

std::vector<std::string> channel_names() {
  std::vector<std::string> names;
  auto doubles = [&](const char *group, const char *axes) {
    for (const char *a = axes; *a; ++a)
      for (const char *half : {"_hi", "_lo"}) names.push_back(std::string(kLayer) + group + "_" + *a + half);
  };
  doubles("sample", "rgb");
  names.push_back(std::string(kLayer) + "sample_count");
  doubles("splat", "rgb");
  doubles("normal", "xyz");
  doubles("albedo", "rgb");
  names.push_back(std::string(kLayer) + "depth");  // float bits
  doubles("transparent", "v");
  // The data passes (film/data_passes.h): the mist cover's sum, and the pass indices (float
  // bits), which only the part holding sample 0 has (0 in the others: they add up).
  doubles("mist_cover", "v");
  for (const char *name : {"object_index", "material_index"}) names.push_back(std::string(kLayer) + name);
  return names;
}

// Half image B's sums (PartRecord::halves), after those of channel_names().
constexpr int kHalfWordsPerPixel = 6 + 1 + 6;
std::vector<std::string> half_channel_names() {
  std::vector<std::string> names;
  for (const char *group : {"half_sample", "half_splat"}) {
    for (const char *a = "rgb"; *a; ++a)
      for (const char *half : {"_hi", "_lo"}) names.push_back(std::string(kLayer) + group + "_" + *a + half);
    if (std::string(group) == "half_sample") names.push_back(std::string(kLayer) + "half_sample_count");
  }
  return names;
}

// The passes' sums (PartRecord::light_passes, strategy_max_depth, denoising_passes,
// shadow_catcher), after the halves'; then the shader AOVs' sums and Cryptomatte's slots (id
// and weight, float bits).
std::vector<std::string> pass_channel_names(bool light_passes, int strategy_max_depth, bool denoising_passes,
                                            bool shadow_catcher, int aov_channels, int crypto_slots) {
  std::vector<std::string> names;
  auto doubles = [&](const std::string &group, const char *axes) {
    for (const char *a = axes; *a; ++a)
      for (const char *half : {"_hi", "_lo"}) names.push_back(std::string(kLayer) + group + "_" + *a + half);
  };
  auto color = [&](const std::string &group) { doubles(group, "rgb"); };
  if (light_passes) {
    for (int k = 0; k < kLightPassSlots; ++k) color("light" + std::to_string(k));
    for (int k = 0; k < kColorKinds; ++k) color("light_color" + std::to_string(k));
    for (int k = 0; k < kLightPassSlots; ++k) color("light_splat" + std::to_string(k));
  }
  const StrategyPasses strategies{strategy_max_depth};
  for (int k = 0; k < strategies.count(); ++k) color("strategy" + std::to_string(k));
  for (int k = 0; k < strategies.splat_count(); ++k) color("strategy_splat" + std::to_string(k));
  if (denoising_passes) {
    doubles("denoising_normal", "xyz");
    doubles("denoising_albedo", "rgb");
    doubles("denoising_depth", "v");
  }
  if (shadow_catcher) {
    doubles("catcher_matte", "rgb");
    doubles("catcher_pass", "rgb");
    doubles("catcher_world", "rgb");
    doubles("catcher_matte_transparent", "v");
    doubles("catcher_splits", "v");
    doubles("catcher_matte_splat", "rgb");
    doubles("catcher_pass_splat", "rgb");
  }
  for (int k = 0; k < aov_channels; ++k) doubles("aov" + std::to_string(k), "v");
  for (int k = 0; k < crypto_slots; ++k)
    for (const char *word : {"_id", "_weight"}) names.push_back(std::string(kLayer) + "crypto" + std::to_string(k) + word);
  return names;
}
int crypto_slots_of(const PartRecord &record) { return Cryptomatte::parse(&record.cryptomatte).slots_per_pixel(); }
// A part's shader AOV sums per pixel (0 for a part of an engine that did not carry them).
int aov_channels_of(const PartRecord &record) {
  return record.shader_aovs.is_array() ? ShaderAovs::parse(&record.shader_aovs).channels : 0;
}
constexpr size_t kDenoisingDoubles = 7;  // normal, albedo, depth
// matte, catcher pass, world behind, matte transparency, splits, matte and catcher pass splats
constexpr size_t kCatcherDoubles = 17;

// One part file: its record and its raw sums as words.
struct LoadedPart {
  std::string path;
  PartRecord record;
  int width = 0, height = 0;
  // per pixel: kWordsPerPixel, kHalfWordsPerPixel with halves, then the passes' words
  std::vector<uint32_t> words;
};

LoadedPart load_part(const std::string &path) {
  LoadedPart part;
  part.path = path;
  auto in = OIIO::ImageInput::open(path);
  if (!in) fail("part '" + path + "': cannot read: " + OIIO::geterror(), RDV_ERROR_IO);
  const OIIO::ImageSpec &spec = in->spec();
  std::string text = spec.get_string_attribute(part_attribute_name());
  if (text.empty())
    fail("part '" + path + "': not a Rendezvous render part (no '" + std::string(part_attribute_name()) +
         "' attribute: an EXR written by the engine's command-line renderer or rdv_session_write_image is)");
  part.record = PartRecord::from_json(text, path);
  part.width = spec.width;
  part.height = spec.height;
  const std::vector<std::string> pass_names =
      pass_channel_names(part.record.light_passes, part.record.strategy_max_depth, part.record.denoising_passes,
                         part.record.shadow_catcher, aov_channels_of(part.record), crypto_slots_of(part.record));
  check_memory("part '" + path + "'", "its " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " sums",
               double(spec.width) * double(spec.height) *
                       double(spec.nchannels + kWordsPerPixel + (part.record.halves ? kHalfWordsPerPixel : 0) +
                              pass_names.size()) * 4.0 +
                   double(spec.width) * double(spec.height) *
                       double(Film::bytes_per_pixel(part.record.halves, part.record.light_passes,
                                                    part.record.strategy_max_depth, part.record.denoising_passes)));
  // EXR keeps channels sorted by name: find each of ours, read the span they lie in.
  std::vector<std::string> names = channel_names();
  const size_t base = names.size();
  if (part.record.halves)
    for (const std::string &name : half_channel_names()) names.push_back(name);
  names.insert(names.end(), pass_names.begin(), pass_names.end());
  std::vector<int> index(names.size(), -1);
  for (size_t k = 0; k < names.size(); ++k) {
    for (int c = 0; c < spec.nchannels; ++c)
      if (spec.channelnames[size_t(c)] == names[k]) index[k] = c;
    const bool optional = k < base && k + kOptionalChannels >= base;
    if (index[k] < 0 && !optional) fail("part '" + path + "': channel " + names[k] + " is missing");
  }
  int lo = spec.nchannels, hi = 0;
  for (int c : index)
    if (c >= 0) lo = std::min(lo, c), hi = std::max(hi, c + 1);
  const size_t pixels = size_t(part.width) * part.height, span = size_t(hi - lo);
  std::vector<uint32_t> words(pixels * span);
  if (!in->read_image(0, 0, lo, hi, OIIO::TypeDesc::UINT, words.data()))
    fail("part '" + path + "': cannot read its channels: " + in->geterror(), RDV_ERROR_IO);
  part.words.resize(pixels * names.size());
  for (size_t i = 0; i < pixels; ++i)
    for (size_t k = 0; k < names.size(); ++k)
      part.words[i * names.size() + k] = index[k] < 0 ? 0u : words[i * span + size_t(index[k] - lo)];
  return part;
}

std::string range_text(const SampleRange &r) {
  // Appended piece by piece: GCC 12's -Wrestrict misfires on "[" + std::to_string(...).
  std::string text = "[";
  text += std::to_string(r.begin);
  text += ", ";
  text += std::to_string(r.end);
  text += ")";
  return text;
}

// "key: a vs b" for every setting that differs.
std::string settings_difference(const std::string &a_text, const std::string &b_text) {
  json a = json::parse(a_text), b = json::parse(b_text);
  std::string out;
  for (auto &[key, value] : a.items()) {
    json other = b.contains(key) ? b[key] : json();
    if (value != other) out += (out.empty() ? "" : ", ") + key + " " + other.dump() + " vs " + value.dump();
  }
  for (auto &[key, value] : b.items())
    if (!a.contains(key)) out += (out.empty() ? "" : ", ") + key + " " + value.dump() + " vs (absent)";
  return out;
}

}  // namespace

const char *part_attribute_name() { return "rendezvous:part"; }

std::string PartRecord::to_json() const {
  json j;
  j["format"] = 1;
  j["scene_hash"] = scene_hash;
  j["settings"] = json::parse(settings_json);
  j["ranges"] = json::array();
  for (const SampleRange &r : ranges) j["ranges"].push_back({r.begin, r.end});
  j["splat_numerator"] = splats.numerator;  // printed to round-trip exactly
  j["splat_paths"] = splats.paths;
  if (halves) j["half_splats"] = {half_splats.numerator, half_splats.paths};
  // written only when carried: parts without them read as before
  if (light_passes) j["light_passes"] = true;
  if (data_passes) j["data_passes"] = true;
  if (denoising_passes) j["denoising_passes"] = true;
  if (!shader_aovs.is_null()) j["shader_aovs"] = shader_aovs;
  if (!cryptomatte.is_null()) j["cryptomatte"] = {{"settings", cryptomatte}, {"metadata", crypto_metadata}};
  if (shadow_catcher)
    j["shadow_catcher"] = {{"pass", catcher_display.pass}, {"film_transparent", catcher_display.film_transparent}};
  if (strategy_max_depth >= 0) j["strategy_max_depth"] = strategy_max_depth;
  return j.dump();
}

PartRecord PartRecord::from_json(const std::string &text, const std::string &part) {
  PartRecord r;
  try {
    json j = json::parse(text);
    if (j.value("format", 0) != 1)
      fail("part '" + part + "': part format " + j.value("format", json(0)).dump() + " (this engine reads format 1)");
    r.scene_hash = j.at("scene_hash").get<std::string>();
    r.settings_json = j.at("settings").dump();
    for (const json &range : j.at("ranges")) {
      SampleRange s{range.at(0).get<uint64_t>(), range.at(1).get<uint64_t>()};
      if (s.end < s.begin) fail("part '" + part + "': range " + range_text(s) + " ends before it begins");
      r.ranges.push_back(s);
    }
    r.splats.numerator = j.at("splat_numerator").get<double>();
    r.splats.paths = j.at("splat_paths").get<double>();
    if (j.contains("half_splats")) {  // optional: parts without halves, and older parts
      r.halves = true;
      r.half_splats.numerator = j["half_splats"].at(0).get<double>();
      r.half_splats.paths = j["half_splats"].at(1).get<double>();
    }
    r.light_passes = j.value("light_passes", false);
    r.data_passes = j.value("data_passes", false);
    r.denoising_passes = j.value("denoising_passes", false);
    if (j.contains("shader_aovs")) {
      r.shader_aovs = j["shader_aovs"];
      try {
        if (!r.shader_aovs.is_boolean()) ShaderAovs::parse(&r.shader_aovs);  // settings this engine reads
      } catch (const Error &e) {
        fail("part '" + part + "': " + e.what());
      }
    }
    if (j.contains("cryptomatte")) {
      r.cryptomatte = j["cryptomatte"].at("settings");
      r.crypto_metadata = j["cryptomatte"].at("metadata");
      try {
        Cryptomatte::parse(&r.cryptomatte);  // settings this engine reads
      } catch (const Error &e) {
        fail("part '" + part + "': " + e.what());
      }
    }
    if (j.contains("shadow_catcher")) {
      r.shadow_catcher = true;
      r.catcher_display.pass = j["shadow_catcher"].at("pass").get<bool>();
      r.catcher_display.film_transparent = j["shadow_catcher"].at("film_transparent").get<bool>();
    }
    r.strategy_max_depth = j.value("strategy_max_depth", -1);
    if (r.strategy_max_depth < -1 || r.strategy_max_depth > StrategyPasses::kMaxDepth)
      fail("part '" + part + "': strategy passes of depth " + std::to_string(r.strategy_max_depth) +
           " (at most " + std::to_string(StrategyPasses::kMaxDepth) + ")");
    json settings = j.at("settings");
    settings.at("width").get<int>();
    settings.at("height").get<int>();
    settings.at("border").at(3).get<int>();
  } catch (const json::exception &e) {
    fail("part '" + part + "': malformed '" + std::string(part_attribute_name()) + "' attribute: " + e.what());
  }
  if (!std::isfinite(r.splats.numerator) || !std::isfinite(r.splats.paths) || r.splats.paths < 0 ||
      !std::isfinite(r.half_splats.numerator) || !std::isfinite(r.half_splats.paths) || r.half_splats.paths < 0)
    fail("part '" + part + "': splat normalisation is not finite");
  return r;
}

PartChannels part_channels(const Film &film, const PartRecord &record) {
  PartChannels out;
  out.names = channel_names();
  const bool halves = record.halves && film.has_halves();
  if (halves)
    for (const std::string &name : half_channel_names()) out.names.push_back(name);
  // the passes the film keeps (the record says the same: Session::part_record)
  const bool light_passes = film.has_light_passes(), denoising = film.has_denoising_passes(),
             catcher = film.has_shadow_catcher();
  const int aov_channels = film.shader_aovs().channels, crypto_slots = film.cryptomatte().slots_per_pixel();
  const std::vector<std::string> pass_names = pass_channel_names(light_passes, film.strategy_passes().max_depth, denoising,
                                                                 catcher, aov_channels, crypto_slots);
  out.names.insert(out.names.end(), pass_names.begin(), pass_names.end());
  const size_t n = size_t(film.width()) * film.height();
  const size_t strategies = size_t(film.strategy_passes().count()),
               strategy_splats = size_t(film.strategy_passes().splat_count());
  out.words.resize(n * (kWordsPerPixel + (halves ? kHalfWordsPerPixel : 0) + pass_names.size()));
  uint32_t *w = out.words.data();
  for (size_t i = 0; i < n; ++i) {
    const PixelSum &p = film.pixel_sums()[i];
    const SplatSums &s = film.splat_sums()[i];
    const PixelAov &a = film.aov_sums()[i];
    for (double v : p.sample) put_double(w, v);
    *w++ = p.count;
    for (double v : s) put_double(w, v);
    for (double v : a.normal) put_double(w, v);
    for (double v : a.albedo) put_double(w, v);
    std::memcpy(w++, &a.depth, 4);
    put_double(w, p.transparent);
    put_double(w, a.mist_cover);
    for (float v : {a.object_index, a.material_index}) std::memcpy(w++, &v, 4);
    if (halves) {
      const HalfSum &h = film.half_pixel_sums()[i];
      for (double v : h.sample) put_double(w, v);
      *w++ = h.count;
      for (double v : film.half_splat_sums()[i]) put_double(w, v);
    }
    if (light_passes) {
      const LightPassSums &l = film.light_pass_sums()[i];
      for (const auto &c : l.light)
        for (double v : c) put_double(w, v);
      for (const auto &c : l.color)
        for (double v : c) put_double(w, v);
      for (const auto &c : film.light_splat_sums()[i])
        for (double v : c) put_double(w, v);
    }
    for (size_t k = 0; k < strategies; ++k)
      for (double v : film.strategy_sums()[i * strategies + k]) put_double(w, v);
    for (size_t k = 0; k < strategy_splats; ++k)
      for (double v : film.strategy_splat_sums()[i * strategy_splats + k]) put_double(w, v);
    if (denoising) {
      const DenoisingSums &d = film.denoising_sums()[i];
      for (double v : d.normal) put_double(w, v);
      for (double v : d.albedo) put_double(w, v);
      put_double(w, d.depth);
    }
    if (catcher) {
      const CatcherSums &c = film.shadow_catcher_sums()[i];
      for (const auto *sums : {&c.matte, &c.catcher, &c.background})
        for (double v : *sums) put_double(w, v);
      put_double(w, c.matte_transparent);
      put_double(w, c.splits);
      for (const auto *sums : {&c.matte_splats, &c.catcher_splats})
        for (double v : *sums) put_double(w, v);
    }
    for (int k = 0; k < aov_channels; ++k) put_double(w, film.shader_aov_sums()[i * size_t(aov_channels) + size_t(k)]);
    for (int k = 0; k < crypto_slots; ++k) {
      const CryptoSlot &slot = film.crypto_slots()[i * size_t(crypto_slots) + size_t(k)];
      std::memcpy(w++, &slot.id, 4);
      std::memcpy(w++, &slot.weight, 4);
    }
  }
  return out;
}

std::string MergeResult::report_json() const {
  json j;
  j["ranges"] = json::array();
  uint64_t samples = 0;
  for (const SampleRange &r : record.ranges) {
    j["ranges"].push_back({r.begin, r.end});
    samples += r.end - r.begin;
  }
  j["samples"] = samples;
  j["missing"] = json::array();
  for (const SampleRange &r : missing) j["missing"].push_back({r.begin, r.end});
  j["warnings"] = warnings;
  return j.dump();
}

MergeResult merge_parts(const std::vector<std::string> &paths, const MergeOptions &options) {
  if (paths.empty()) fail("merge: no parts given");
  std::vector<LoadedPart> parts;
  parts.reserve(paths.size());
  for (const std::string &path : paths) parts.push_back(load_part(path));

  // The same scene and settings, and an image of the size they say.
  const LoadedPart &first = parts[0];
  for (const LoadedPart &p : parts) {
    if (p.record.scene_hash != first.record.scene_hash)
      fail("part '" + p.path + "' is of another scene (scene hash " + p.record.scene_hash + ") than '" + first.path +
           "' (" + first.record.scene_hash + ")");
    if (p.record.settings_json != first.record.settings_json)
      fail("part '" + p.path + "' was rendered with other settings than '" + first.path +
           "': " + settings_difference(first.record.settings_json, p.record.settings_json));
  }
  const json settings = json::parse(first.record.settings_json);
  const int width = settings["width"].get<int>(), height = settings["height"].get<int>();
  for (const LoadedPart &p : parts)
    if (p.width != width || p.height != height)
      fail("part '" + p.path + "': image is " + std::to_string(p.width) + "x" + std::to_string(p.height) +
           ", its settings say " + std::to_string(width) + "x" + std::to_string(height));

  // Ranges: no sample twice; gaps reported.
  MergeResult result;
  struct Owned { SampleRange range; size_t part; };
  std::vector<Owned> owned;
  for (size_t k = 0; k < parts.size(); ++k) {
    bool any = false;
    for (const SampleRange &r : parts[k].record.ranges)
      if (r.end > r.begin) {
        owned.push_back({r, k});
        any = true;
      }
    if (!any) result.warnings.push_back("part '" + parts[k].path + "' holds no samples");
  }
  std::sort(owned.begin(), owned.end(), [](const Owned &a, const Owned &b) { return a.range.begin < b.range.begin; });
  uint64_t covered = 0;
  for (size_t i = 0; i < owned.size(); ++i) {
    const SampleRange &r = owned[i].range;
    if (i > 0 && r.begin < owned[i - 1].range.end)
      fail("parts '" + parts[owned[i - 1].part].path + "' " + range_text(owned[i - 1].range) + " and '" +
           parts[owned[i].part].path + "' " + range_text(r) + " overlap: samples " + std::to_string(r.begin) + ".." +
           std::to_string(std::min(r.end, owned[i - 1].range.end) - 1) + " would count twice");
    if (r.begin > covered) result.missing.push_back({covered, r.begin});
    if (!result.record.ranges.empty() && result.record.ranges.back().end == r.begin) result.record.ranges.back().end = r.end;
    else result.record.ranges.push_back(r);
    covered = r.end;
  }
  if (options.expected_samples > covered) result.missing.push_back({covered, options.expected_samples});
  if (!result.missing.empty()) {
    std::string list;
    for (const SampleRange &r : result.missing) list += (list.empty() ? "" : ", ") + range_text(r);
    if (!options.allow_missing) fail("merge: missing sample ranges " + list + " (no part holds them)");
    result.warnings.push_back("missing sample ranges " + list + ": the image holds the other samples only");
  }

  // Add in the order of the parts' first samples (the same sums whatever order the
  // parts are named in). Splat sums of parts with another numerator (MLT: each part's
  // own b) are rescaled to the first one's, so that numerator / paths stays right.
  std::vector<size_t> order(parts.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  auto first_sample = [&](size_t k) { return parts[k].record.ranges.empty() ? 0 : parts[k].record.ranges[0].begin; };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return first_sample(a) < first_sample(b); });
  double numerator = 0, paths_total = 0, half_numerator = 0, half_paths_total = 0;
  for (size_t k : order)
    if (parts[k].record.splats.paths > 0 && numerator == 0) numerator = parts[k].record.splats.numerator;
  // Half images only when every part kept its own (the same settings make them all do,
  // unless a part published no pass).
  const bool halves = std::all_of(parts.begin(), parts.end(), [](const LoadedPart &p) { return p.record.halves; });
  if (!halves && std::any_of(parts.begin(), parts.end(), [](const LoadedPart &p) { return p.record.halves; }))
    result.warnings.push_back("some parts carry no half images: the merged image has no noise estimate (no Noise pass)");
  for (size_t k : order)
    if (halves && parts[k].record.half_splats.paths > 0 && half_numerator == 0)
      half_numerator = parts[k].record.half_splats.numerator;

  // The passes every part carries (the others' are left out, with a warning).
  auto all_parts = [&](auto has) { return std::all_of(parts.begin(), parts.end(), has); };
  auto some_part = [&](auto has) { return std::any_of(parts.begin(), parts.end(), has); };
  const bool light_passes = all_parts([](const LoadedPart &p) { return p.record.light_passes; });
  const bool data_passes = all_parts([](const LoadedPart &p) { return p.record.data_passes; });
  const bool denoising = all_parts([](const LoadedPart &p) { return p.record.denoising_passes; });
  const int depth = first.record.strategy_max_depth;
  const int strategy_depth =
      all_parts([&](const LoadedPart &p) { return p.record.strategy_max_depth == depth; }) ? depth : -1;
  if (!light_passes && some_part([](const LoadedPart &p) { return p.record.light_passes; }))
    result.warnings.push_back("some parts carry no light passes: the merged image has none");
  if (!data_passes && some_part([](const LoadedPart &p) { return p.record.data_passes; }))
    result.warnings.push_back("some parts carry no data passes (Mist, IndexOB, IndexMA): the merged image has none");
  if (!denoising && some_part([](const LoadedPart &p) { return p.record.denoising_passes; }))
    result.warnings.push_back("some parts carry no denoising data (Denoising Normal, Albedo, Depth): the merged image has none");
  // Shader AOVs: kept when every part has the same ones, with their sums.
  const bool aovs = all_parts([&](const LoadedPart &p) {
    return p.record.shader_aovs.is_array() && p.record.shader_aovs == first.record.shader_aovs;
  });
  if (!aovs && some_part([](const LoadedPart &p) { return !p.record.shader_aovs.is_null(); }))
    result.warnings.push_back("some parts carry no shader AOVs, or other ones (or were written by an engine that did not "
                              "carry them): the merged image has none");
  const ShaderAovs aov_layout = aovs ? ShaderAovs::parse(&first.record.shader_aovs) : ShaderAovs();
  // Cryptomatte: kept when every part has it alike (the slots of each pixel combine by id).
  const bool crypto = all_parts([&](const LoadedPart &p) {
    return !p.record.cryptomatte.is_null() && p.record.cryptomatte == first.record.cryptomatte;
  });
  if (!crypto && some_part([](const LoadedPart &p) { return !p.record.cryptomatte.is_null(); }))
    result.warnings.push_back("some parts carry no Cryptomatte, or other Cryptomatte settings: the merged image has none");
  const Cryptomatte crypto_layout = crypto ? Cryptomatte::parse(&first.record.cryptomatte) : Cryptomatte();
  const bool catcher = all_parts([&](const LoadedPart &p) {
    return p.record.shadow_catcher && p.record.catcher_display.pass == first.record.catcher_display.pass &&
           p.record.catcher_display.film_transparent == first.record.catcher_display.film_transparent;
  });
  if (!catcher && some_part([](const LoadedPart &p) { return p.record.shadow_catcher; }))
    result.warnings.push_back("some parts carry no shadow catcher sums, or other display settings: the merged image "
                              "shows the catcher as an ordinary object (no Shadow Catcher pass)");
  if (strategy_depth < 0 && some_part([](const LoadedPart &p) { return p.record.strategy_max_depth >= 0; }))
    result.warnings.push_back("the parts carry strategy passes of different depths, or some none: the merged image has none");

  const auto &border = settings["border"];
  result.film = std::make_unique<Film>(width, height, Rect{border[0].get<int>(), border[1].get<int>(), border[2].get<int>(), border[3].get<int>()}, halves,
                                       light_passes, data_passes, strategy_depth, denoising, aov_layout, crypto_layout);
  Film &film = *result.film;
  if (crypto) film.set_crypto_metadata(first.record.crypto_metadata);
  if (catcher) film.keep_shadow_catcher(first.record.catcher_display);
  const size_t n = size_t(width) * height;
  for (size_t k : order) {
    const LoadedPart &part = parts[k];
    const int part_aovs = aov_channels_of(part.record), part_slots = crypto_slots_of(part.record);  // once a part
    const SplatNormalisation &sn = part.record.splats;
    const bool splats = sn.paths > 0;
    const bool same_numerator = sn.numerator == numerator;
    const double rescale = splats && numerator != 0 ? sn.numerator / numerator : 0.0;
    if (splats) paths_total += sn.paths;
    const SplatNormalisation &hn = part.record.half_splats;
    const bool half_splats = halves && hn.paths > 0;
    const double half_rescale = half_splats && half_numerator != 0 ? hn.numerator / half_numerator : 0.0;
    if (half_splats) half_paths_total += hn.paths;
    const uint32_t *w = part.words.data();
    auto check_finite = [&](double value, size_t i, const char *sum) {
      if (!std::isfinite(value))
        fail("part '" + part.path + "': pixel (" + std::to_string(i % width) + ", " + std::to_string(i / width) +
             ") holds a non-finite " + sum + " (a damaged file?)");
    };
    for (size_t i = 0; i < n; ++i) {
      PixelSum &p = film.pixel_sums()[i];
      SplatSums &s = film.splat_sums()[i];
      PixelAov &a = film.aov_sums()[i];
      double v[18];
      for (int c = 0; c < 3; ++c) v[c] = get_double(w);
      uint32_t count = *w++;
      for (int c = 3; c < 12; ++c) v[c] = get_double(w);
      float depth;
      std::memcpy(&depth, w++, 4);
      v[12] = get_double(w);
      v[13] = get_double(w);  // mist cover
      float index[2];         // object, material
      for (float &d : index) std::memcpy(&d, w++, 4);
      v[14] = index[0];
      v[15] = index[1];
      for (int c = 0; c < 16; ++c) check_finite(v[c], i, "sum");
      if (uint64_t(p.count) + count > UINT32_MAX)
        fail("part '" + part.path + "': pixel sample counts overflow 2^32 when merged");
      for (int c = 0; c < 3; ++c) p.sample[c] += v[c];
      p.count += count;
      p.transparent += v[12];
      if (splats)
        for (int c = 0; c < 3; ++c) s[c] += same_numerator ? v[3 + c] : v[3 + c] * rescale;
      for (int c = 0; c < 3; ++c) {
        a.normal[c] += v[6 + c];
        a.albedo[c] += v[9 + c];
      }
      if (!std::isnan(depth)) a.depth = std::min(a.depth, depth);
      a.mist_cover += v[13];
      a.object_index += index[0];
      a.material_index += index[1];
      if (halves) {
        double h[6];
        for (int c = 0; c < 3; ++c) h[c] = get_double(w);
        const uint32_t half_count = *w++;
        for (int c = 3; c < 6; ++c) h[c] = get_double(w);
        for (double value : h) check_finite(value, i, "half-image sum");
        HalfSum &hp = film.half_pixel_sums()[i];
        for (int c = 0; c < 3; ++c) hp.sample[c] += h[c];
        hp.count += half_count;
        if (half_splats)
          for (int c = 0; c < 3; ++c)
            film.half_splat_sums()[i][c] += hn.numerator == half_numerator ? h[3 + c] : h[3 + c] * half_rescale;
      }
      // The passes' sums: camera samples' added, splats' rescaled as the image's; those
      // of a pass the merge leaves out are skipped.
      auto add_sums = [&](std::array<double, 3> *sum, size_t count, bool splat) {
        for (size_t k = 0; k < count; ++k) {
          std::array<double, 3> v;
          for (double &c : v) c = get_double(w);
          for (double c : v) check_finite(c, i, "pass sum");
          if (!sum || (splat && !splats)) continue;
          for (int c = 0; c < 3; ++c) sum[k][c] += splat && !same_numerator ? v[c] * rescale : v[c];
        }
      };
      if (part.record.light_passes) {
        LightPassSums *l = light_passes ? &film.light_pass_sums()[i] : nullptr;
        add_sums(l ? l->light.data() : nullptr, kLightPassSlots, false);
        add_sums(l ? l->color.data() : nullptr, kColorKinds, false);
        add_sums(light_passes ? film.light_splat_sums()[i].data() : nullptr, kLightPassSlots, true);
      }
      const StrategyPasses strategies{part.record.strategy_max_depth};
      const bool keep = part.record.strategy_max_depth == strategy_depth;
      const size_t ns = size_t(strategies.count()), nsplat = size_t(strategies.splat_count());
      add_sums(keep ? &film.strategy_sums()[i * ns] : nullptr, ns, false);
      add_sums(keep ? &film.strategy_splat_sums()[i * nsplat] : nullptr, nsplat, true);
      // A pass's doubles, checked (those of a pass the merge leaves out are read past).
      auto read_sums = [&](double *d, size_t count, const char *sum) {
        for (size_t k = 0; k < count; ++k) check_finite(d[k] = get_double(w), i, sum);
      };
      if (part.record.denoising_passes) {
        double d[kDenoisingDoubles];
        read_sums(d, kDenoisingDoubles, "denoising sum");
        if (denoising) {
          DenoisingSums &sum = film.denoising_sums()[i];
          for (int c = 0; c < 3; ++c) {
            sum.normal[c] += d[c];
            sum.albedo[c] += d[3 + c];
          }
          sum.depth += d[6];
        }
      }
      if (part.record.shadow_catcher) {
        double d[kCatcherDoubles];
        read_sums(d, kCatcherDoubles, "shadow catcher sum");
        if (catcher) {
          CatcherSums &sum = film.shadow_catcher_sums()[i];
          for (int c = 0; c < 3; ++c) {
            sum.matte[c] += d[c];
            sum.catcher[c] += d[3 + c];
            sum.background[c] += d[6 + c];
          }
          sum.matte_transparent += float(d[9]);
          if (d[10] < 0 || d[10] > UINT32_MAX || uint64_t(sum.splits) + uint64_t(d[10]) > UINT32_MAX)
            fail("part '" + part.path + "': shadow catcher split counts out of range");
          sum.splits += uint32_t(d[10]);
          // Splat sums rescaled as the image's (Metropolis parts: each its own b); without
          // that a merge of pssmlt parts read the matte and the pass off by the parts' b.
          if (splats)
            for (int c = 0; c < 3; ++c) {
              sum.matte_splats[c] += same_numerator ? d[11 + c] : d[11 + c] * rescale;
              sum.catcher_splats[c] += same_numerator ? d[14 + c] : d[14 + c] * rescale;
            }
        }
      }
      if (part_aovs) {
        double d[4 * ShaderAovs::kMaxPasses];
        read_sums(d, size_t(part_aovs), "shader AOV sum");
        if (aovs)
          for (int c = 0; c < part_aovs; ++c) film.shader_aov_sums()[i * size_t(part_aovs) + size_t(c)] += d[c];
      }
      // Cryptomatte: the part's slots added by id to the merged pixel's, kind by kind.
      if (part_slots) {
        CryptoSlot slots[Cryptomatte::kKinds * 2 * Cryptomatte::kMaxPassesPerKind];
        for (int k = 0; k < part_slots; ++k) {
          CryptoSlot &slot = slots[k];
          std::memcpy(&slot.id, w++, 4);
          std::memcpy(&slot.weight, w++, 4);
          check_finite(slot.id, i, "Cryptomatte id");
          check_finite(slot.weight, i, "Cryptomatte weight");
        }
        if (crypto) add_crypto_slots(crypto_layout, &film.crypto_slots()[i * size_t(part_slots)], slots);
      }
    }
  }
  {
    uint64_t samples = 0;
    for (const SampleRange &r : result.record.ranges) samples += r.end - r.begin;
    Film::PassPublisher frame(film);
    if (halves)
      frame.publish(uint32_t(std::min<uint64_t>(samples, UINT32_MAX)), {numerator, paths_total},
                    HalfSplit::CameraSamples, {half_numerator, half_paths_total});
    else
      frame.publish(uint32_t(std::min<uint64_t>(samples, UINT32_MAX)), {numerator, paths_total});
  }
  result.record.scene_hash = first.record.scene_hash;
  result.record.settings_json = first.record.settings_json;
  result.record.splats = {numerator, paths_total};
  result.record.halves = halves;
  result.record.half_splats = {half_numerator, half_paths_total};
  result.record.light_passes = light_passes;
  result.record.data_passes = data_passes;
  result.record.denoising_passes = denoising;
  result.record.shadow_catcher = catcher;
  if (aovs) result.record.shader_aovs = first.record.shader_aovs;
  if (crypto) {
    result.record.cryptomatte = first.record.cryptomatte;
    result.record.crypto_metadata = first.record.crypto_metadata;
  }
  result.record.catcher_display = first.record.catcher_display;
  result.record.strategy_max_depth = strategy_depth;
  return result;
}

}  // namespace rdv
