// Render parts (farm tasks, docs/farm.md): sample ranges rendered apart and merged
// equal one render of all the samples; merging refuses parts that do not belong
// together, naming the part; Metropolis parts (independent chain sets) merge to the
// brightness BDPT gives.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_render_parts {

using namespace rdv::test;
using nlohmann::json;

namespace {

// Renders the scene with the settings through the C ABI and writes the EXR part.
void render_part(const json &scene, const json &settings, const std::string &path) {
  rdv_scene *s = nullptr;
  ASSERT_EQ(rdv_scene_create(&s), RDV_OK);
  auto loaded = rdv_tools::load_scene_json(scene.dump(), ".", s);
  json all = json::parse(loaded.settings_json);
  all.update(settings);
  rdv_session *session = nullptr;
  ASSERT_EQ(rdv_session_create(s, all.dump().c_str(), &session), RDV_OK) << rdv_last_error();
  rdv_session_start(session);
  rdv_session_wait(session);
  ASSERT_EQ(rdv_session_write_image(session, path.c_str(), nullptr), RDV_OK) << rdv_last_error();
  rdv_session_destroy(session);
  rdv_scene_destroy(s);
}

// Every channel of an EXR as 32-bit words, by channel name.
struct Channels {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<uint32_t> words;
  bool is_float(size_t c) const { return names[c].rfind("RdvMerge.", 0) != 0; }
  float value(size_t i, size_t c) const {
    float f;
    std::memcpy(&f, &words[i * names.size() + c], 4);
    return f;
  }
};
Channels read_channels(const std::string &path) {
  Channels out;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return out;
  const OIIO::ImageSpec &spec = in->spec();
  out.width = spec.width;
  out.height = spec.height;
  out.names = spec.channelnames;
  out.words.resize(size_t(spec.width) * spec.height * spec.nchannels);
  // Float channels as float, part channels as unsigned: both 32-bit, as stored.
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UNKNOWN, out.words.data())) << in->geterror();
  return out;
}

double word_double(const Channels &c, size_t i, size_t hi, size_t lo) {
  uint64_t bits = (uint64_t(c.words[i * c.names.size() + hi]) << 32) | c.words[i * c.names.size() + lo];
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

std::string merge(const std::vector<std::string> &parts, const std::string &out, const std::string &options,
                  rdv_status *status, std::string *report = nullptr) {
  std::vector<const char *> paths;
  for (const auto &p : parts) paths.push_back(p.c_str());
  const char *text = nullptr;
  *status = rdv_merge_parts(paths.data(), uint32_t(paths.size()), out.c_str(), options.c_str(), &text);
  if (report && text) *report = text;
  return *status == RDV_OK ? "" : rdv_last_error();
}

// `count` parts of `samples` each (sample offsets 0, samples, ...) rendered and merged.
struct MergedParts {
  std::vector<std::string> parts;
  std::string merged;
};
MergedParts render_and_merge(const json &scene, json settings, int count, int samples, const std::string &prefix) {
  MergedParts out;
  settings["samples"] = samples;
  for (int k = 0; k < count; ++k) {
    settings["sample_offset"] = k * samples;
    out.parts.push_back(temp_path(prefix + "_part" + std::to_string(k) + ".exr"));
    render_part(scene, settings, out.parts.back());
  }
  out.merged = temp_path(prefix + "_merged.exr");
  rdv_status status;
  std::string error = merge(out.parts, out.merged, "{}", &status);
  EXPECT_EQ(status, RDV_OK) << error;
  return out;
}

// 4 ranges of 4 samples merged (named out of order) vs one render of 16: the image
// channels bit for bit, the raw double sums within the rounding of re-associated sums.
// With the Noise pass (`halves`), the parts keep their half images and the merge has
// the whole render's Noise channel and half sums. With `passes`, Cycles' light passes,
// the data passes, the denoising data, shader AOVs, Cryptomatte (the box's surfaces are opaque:
// its weights are whole samples, whose float sums are exact in any order) and (bdpt) the
// strategy passes: the merge has them all.
// catcher: the box's first mesh is a shadow catcher, with the Shadow Catcher pass.
void expect_merge_equals_whole(const std::string &integrator, bool halves = false, bool passes = false,
                               bool catcher = false) {
  json scene = load_scene("cornell_box.json");
  json s = {{"width", 40}, {"height", 32}, {"integrator", integrator}, {"max_bounces", 6}, {"seed", 7}, {"threads", 2}};
  if (catcher) {
    scene["meshes"][0]["shadow_catcher"] = true;
    s["shadow_catcher_pass"] = true;
  }
  if (halves) s["noise_pass"] = true;
  if (passes) {
    s["light_passes"] = s["data_passes"] = s["denoising_passes"] = true;
    s["cryptomatte"] = {{"object", true}, {"material", true}, {"asset", true}, {"view_layer", "ViewLayer"}};
    s["aovs"] = json::array({{{"name", "tint"}, {"type", "color"}}, {{"name", "level"}, {"type", "value"}}});
    double k = 0.1;
    for (json &m : scene["materials"])  // values that are no sums of powers of 2
      m["aovs"] = {{"tint", {{"color", {k, 0.3, 0.7 - k}}}}, {"level", {{"value", k += 0.13}}}};
    if (integrator == "bdpt") s["strategy_passes"] = true;
  }
  s["samples"] = 16;
  const std::string whole = temp_path(integrator + "_whole.exr");
  render_part(scene, s, whole);
  std::vector<std::string> parts;
  for (int k : {2, 0, 3, 1}) {
    s["samples"] = 4;
    s["sample_offset"] = 4 * k;
    s["threads"] = 1 + k % 2;  // the thread count is not part of the image
    parts.push_back(temp_path(integrator + "_part" + std::to_string(k) + ".exr"));
    render_part(scene, s, parts.back());
  }
  const std::string merged = temp_path(integrator + "_merged.exr");
  rdv_status status;
  std::string report;
  std::string error = merge(parts, merged, "{\"samples\": 16}", &status, &report);
  ASSERT_EQ(status, RDV_OK) << error;
  EXPECT_EQ(json::parse(report)["ranges"], json::parse("[[0, 16]]"));

  Channels a = read_channels(whole), b = read_channels(merged);
  ASSERT_EQ(a.names, b.names);
  const bool has_noise = std::find(a.names.begin(), a.names.end(), "Noise.V") != a.names.end();
  EXPECT_EQ(has_noise, halves);
  EXPECT_EQ(std::find(a.names.begin(), a.names.end(), "RdvMerge.half_sample_count") != a.names.end(), halves);
  for (const char *pass :
       {"DiffDir.R", "Mist.Z", "IndexOB.X", "Denoising Albedo.G", "Denoising Depth.Z", "CryptoObject00.r",
        "CryptoAsset02.a", "RdvMerge.crypto17_weight", "tint.A", "level.X", "RdvMerge.aov4_v_lo", "Strategy_s2t1.R",
        "Strategy_rest.B"}) {
    const bool expected = passes && (integrator == "bdpt" || std::string(pass).rfind("Strategy", 0) != 0);
    EXPECT_EQ(std::find(a.names.begin(), a.names.end(), pass) != a.names.end(), expected) << pass;
  }
  EXPECT_EQ(std::find(a.names.begin(), a.names.end(), "Shadow Catcher.R") != a.names.end(), catcher);
  EXPECT_EQ(std::find(a.names.begin(), a.names.end(), "RdvMerge.catcher_splits_v_hi") != a.names.end(), catcher);
  ASSERT_EQ(a.words.size(), b.words.size());
  size_t image_differences = 0, raw_differences = 0;
  double worst_raw = 0;
  const size_t nc = a.names.size(), pixels = size_t(a.width) * a.height;
  for (size_t i = 0; i < pixels; ++i)
    for (size_t c = 0; c < nc; ++c) {
      if (a.words[i * nc + c] == b.words[i * nc + c]) continue;
      if (a.is_float(c)) {
        ++image_differences;
        ADD_FAILURE() << integrator << ": pixel " << i << " channel " << a.names[c] << ": " << a.value(i, c) << " vs "
                      << b.value(i, c);
      } else if (a.names[c].size() > 3 && a.names[c].compare(a.names[c].size() - 3, 3, "_lo") == 0) {
        ++raw_differences;
        size_t hi = c - 1;  // "<name>_hi" sorts just before "<name>_lo"
        double x = word_double(a, i, hi, c), y = word_double(b, i, hi, c);
        worst_raw = std::max(worst_raw, std::fabs(x - y) / std::max(std::fabs(x), 1e-300));
      } else {
        ADD_FAILURE() << integrator << ": pixel " << i << " channel " << a.names[c] << " differs";
      }
    }
  // Double sums of the same floats added in another order: a few units in the last
  // place of the sum (2^-52 relative each), far below float's 2^-24.
  EXPECT_LT(worst_raw, 1e-14);
  const size_t image_channels = size_t(std::count_if(a.names.begin(), a.names.end(),
                                                     [&](const std::string &n) { return n.rfind("RdvMerge.", 0) != 0; }));
  std::printf("[ merge %-4s ] image channels: %zu of %zu words differ; raw sums: %zu doubles differ, worst %.3g relative\n",
              integrator.c_str(), image_differences, pixels * image_channels, raw_differences, worst_raw);
}

}  // namespace

TEST(RenderParts, FourRangesEqualOneRenderPath) { expect_merge_equals_whole("path"); }
// A shadow catcher's sums (film/shadow_catcher_passes.h): Combined (the matte) and the
// Shadow Catcher pass of the merge as one render's.
TEST(RenderParts, FourRangesWithShadowCatcherEqualOneRenderPath) { expect_merge_equals_whole("path", false, true, true); }
// BDPT's too: its matte and catcher-pass splat sums.
TEST(RenderParts, FourRangesWithShadowCatcherEqualOneRenderBdpt) { expect_merge_equals_whole("bdpt", false, true, true); }
TEST(RenderParts, FourRangesEqualOneRenderBdpt) { expect_merge_equals_whole("bdpt"); }
TEST(RenderParts, FourRangesWithNoiseEqualOneRenderPath) { expect_merge_equals_whole("path", true); }
TEST(RenderParts, FourRangesWithNoiseEqualOneRenderBdpt) { expect_merge_equals_whole("bdpt", true); }
TEST(RenderParts, FourRangesWithPassesEqualOneRenderPath) { expect_merge_equals_whole("path", false, true); }
TEST(RenderParts, FourRangesWithPassesEqualOneRenderBdpt) { expect_merge_equals_whole("bdpt", false, true); }

// Parts that carry different passes merge to the passes they all carry, with a warning
// naming what was left out.
TEST(RenderParts, MergeKeepsThePassesEveryPartCarries) {
  json scene = load_scene("cornell_box.json");
  json s = {{"width", 16}, {"height", 12}, {"integrator", "bdpt"}, {"samples", 2}, {"light_passes", true},
            {"data_passes", true}, {"strategy_passes", true}, {"denoising_passes", true},
            {"cryptomatte", {{"object", true}}}, {"aovs", json::array({{{"name", "tint"}}})}};
  const std::string p0 = temp_path("passes0.exr"), p1 = temp_path("passes1.exr"), out = temp_path("passes.exr");
  render_part(scene, s, p0);
  s["sample_offset"] = 2;
  s["light_passes"] = s["denoising_passes"] = false;
  s["strategy_passes_max_depth"] = 2;
  s["cryptomatte"] = {{"object", true}, {"levels", 2}};
  s.erase("aovs");
  render_part(scene, s, p1);
  rdv_status status;
  std::string report;
  ASSERT_EQ(merge({p0, p1}, out, "{}", &status, &report), "");
  const std::string warnings = json::parse(report)["warnings"].dump();
  EXPECT_NE(warnings.find("no light passes"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("strategy passes of different depths"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("no denoising data"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("other Cryptomatte settings"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("no shader AOVs"), std::string::npos) << warnings;
  const Channels merged = read_channels(out);
  auto has = [&](const char *name) { return std::find(merged.names.begin(), merged.names.end(), name) != merged.names.end(); };
  EXPECT_TRUE(has("Mist.Z"));
  EXPECT_FALSE(has("DiffDir.R"));
  EXPECT_FALSE(has("Strategy_s2t1.R"));
  EXPECT_FALSE(has("Denoising Normal.X"));
  EXPECT_FALSE(has("CryptoObject00.r"));
}

// Every refusal names the part and the problem; missing ranges are listed.
TEST(RenderParts, MergeRefusesPartsThatDoNotBelongTogether) {
  json scene = load_scene("cornell_box.json");
  json s = {{"width", 16}, {"height", 12}, {"integrator", "bdpt"}, {"samples", 2}, {"scene_hash", "scene-a"}};
  auto part = [&](const std::string &name, json changes) {
    json t = s;
    t.update(changes);
    std::string path = temp_path(name);
    render_part(scene, t, path);
    return path;
  };
  const std::string p0 = part("r0.exr", {{"sample_offset", 0}});
  const std::string p1 = part("r1.exr", {{"sample_offset", 2}});
  const std::string p3 = part("r3.exr", {{"sample_offset", 6}});
  const std::string overlapping = part("overlap.exr", {{"sample_offset", 1}});
  const std::string other_scene = part("other_scene.exr", {{"sample_offset", 2}, {"scene_hash", "scene-b"}});
  const std::string other_settings = part("other_settings.exr", {{"sample_offset", 2}, {"max_bounces", 3}});
  const std::string out = temp_path("refused.exr");
  rdv_status status;
  auto expect_refused = [&](const std::vector<std::string> &parts, const std::vector<std::string> &words) {
    std::string error = merge(parts, out, "{}", &status);
    EXPECT_NE(status, RDV_OK);
    for (const std::string &w : words) EXPECT_NE(error.find(w), std::string::npos) << "'" << w << "' not in: " << error;
  };
  expect_refused({p0, other_scene}, {other_scene, "another scene", "scene-b"});
  expect_refused({p0, other_settings}, {other_settings, "other settings", "max_bounces 3 vs 12"});
  expect_refused({p0, p1, overlapping}, {overlapping, "overlap", "[1, 3)"});
  expect_refused({p0, p0}, {p0, "overlap"});
  expect_refused({p0, p1, p3}, {"missing sample ranges [4, 6)"});
  EXPECT_EQ(merge({p0, p1}, out, "{}", &status), "");  // [0, 4) complete without an expected count
  std::string error = merge({p0, p1}, out, "{\"samples\": 8}", &status);
  EXPECT_NE(error.find("missing sample ranges [4, 8)"), std::string::npos) << error;
  // Allowed: the merge of what is there, the gap reported.
  std::string report;
  EXPECT_EQ(merge({p0, p1, p3}, out, "{\"allow_missing\": true}", &status, &report), "");
  EXPECT_EQ(json::parse(report)["missing"], json::parse("[[4, 6]]")) << report;

  // Files that are not parts: a PNG, a file that does not exist.
  const std::string png = temp_path("image.png");
  {
    rdv_scene *sc = nullptr;
    rdv_scene_create(&sc);
    rdv_tools::load_scene_json(scene.dump(), ".", sc);
    rdv_session *session = nullptr;
    ASSERT_EQ(rdv_session_create(sc, s.dump().c_str(), &session), RDV_OK);
    rdv_session_start(session);
    rdv_session_wait(session);
    rdv_session_write_image(session, png.c_str(), nullptr);
    rdv_session_destroy(session);
    rdv_scene_destroy(sc);
  }
  expect_refused({p0, png}, {png, "not a Rendezvous render part"});
  expect_refused({p0, temp_path("absent.exr")}, {"absent.exr", "cannot read"});
  EXPECT_EQ(merge({}, out, "{}", &status), "merge: no parts given");
}

// Metropolis parts are independent chain sets (seeded by (seed, sample_offset)); merged
// by their mutation counts and each part's b, 8 parts give BDPT's brightness. The
// parts' spread gives the merged image's standard error; BDPT's reference is 8 merged
// ranges, its error from their spread. |t| < 4.8 (7 degrees of freedom): false alarm 0.2%
// per integrator.
TEST(RenderParts, MetropolisPartsMergeToBdptBrightness) {
  json scene = load_scene("cornell_box.json");
  constexpr int kParts = 8;
  auto luminance_mean = [](const std::string &path) {
    Channels c = read_channels(path);
    double sum = 0;
    for (size_t i = 0; i < size_t(c.width) * c.height; ++i)
      sum += 0.2126 * c.value(i, 0) + 0.7152 * c.value(i, 1) + 0.0722 * c.value(i, 2);
    return sum / double(c.width * c.height);
  };
  struct Estimate { double merged, part_mean, error; };
  auto run = [&](const std::string &integrator, int samples) {
    json s = {{"width", 32}, {"height", 32}, {"integrator", integrator}, {"max_bounces", 6},
              {"seed", 3}, {"mlt_chains", 32}, {"mlt_bootstrap", 16}};
    const MergedParts run = render_and_merge(scene, s, kParts, samples, integrator + "_m");
    std::vector<double> means;
    for (const std::string &part : run.parts) means.push_back(luminance_mean(part));
    const std::string &merged = run.merged;
    double m = 0, m2 = 0;
    for (double v : means) { m += v; m2 += v * v; }
    m /= kParts;
    double sd = std::sqrt(std::max(0.0, m2 / kParts - m * m) * kParts / (kParts - 1));
    return Estimate{luminance_mean(merged), m, sd / std::sqrt(double(kParts))};
  };
  Estimate bdpt = run("bdpt", 32);
  for (const char *integrator : {"pssmlt", "mmlt"}) {
    // 128 mutations per pixel: at 32, mmlt's parts read ~5% dark on this scene (all of
    // them alike, a part of offset 0 too: a property of short mmlt runs, not of merging).
    Estimate mlt = run(integrator, 128);
    // Equal mutations per part: the merge is the parts' average (b rescaled per part).
    EXPECT_NEAR(mlt.merged, mlt.part_mean, 1e-5 * mlt.part_mean) << integrator;
    double t = (mlt.merged - bdpt.merged) / std::sqrt(mlt.error * mlt.error + bdpt.error * bdpt.error);
    EXPECT_LT(std::fabs(t), 4.8) << integrator << ": merged " << mlt.merged << " +- " << mlt.error << " vs bdpt "
                                 << bdpt.merged << " +- " << bdpt.error;
    std::printf("[ merge %-6s ] 8 parts: mean %.5f +- %.5f, bdpt %.5f +- %.5f, ratio %.4f\n", integrator, mlt.merged,
                mlt.error, bdpt.merged, bdpt.error, mlt.merged / bdpt.merged);
  }
}

// Metropolis parts of a scene with a shadow catcher (a black ball over a floor that is a
// catcher, a sun, a black world; Shadow Catcher pass on): each part has its own b, and the
// merge rescales the catcher's splat sums as Combined's. Exact where the design says so:
// the merged matte (Combined, RGBA) is the parts' average (equal mutations each, 4
// first-hit rays a pixel each) to float rounding, and where every part's pass is exactly 1
// (sun-lit floor: each state's Combined past the split equals its copy's) the merged pass
// is 1 too. Without the rescale the merged pass there was off by the parts' spread of b
// and the matte by its ratio to the first part's. Deterministic (fixed seeds).
TEST(RenderParts, MetropolisPartsWithShadowCatcherMergeTheirSums) {
  const json floor = {{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"floor"}},
                      {"shadow_catcher", true}};
  const json ball = {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.5}, {"segments", 24}}},
                     {"materials", {"ball"}}, {"transform", {{"translate", {-0.3, 0.2, 0.8}}}}};
  json scene = {
      {"camera", {{"focal_length", 30}, {"transform", {{"look_at", {{"from", {0, -4.0, 3.2}}, {"to", {0, 0, 0.3}}}}}}}},
      {"world", {{"color", {0, 0, 0}}}},
      {"materials",
       {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.65, 0.6}}},
        {{"name", "ball"}, {"type", "diffuse"}, {"color", {0, 0, 0}}}}},
      {"meshes", {floor, ball}},
      {"lights", {{{"type", "sun"}, {"strength", 3}, {"angle", 0}, {"direction", {0.7, -0.5, -1}}}}}};
  constexpr int kParts = 4;
  // The black ball for the lit floor's pass, a red one for the matte's colour.
  for (const std::string integrator : {"pssmlt", "mmlt"})
  for (const bool red : {false, true}) {
    scene["materials"][1]["color"] = red ? json{0.8, 0.3, 0.2} : json{0, 0, 0};
    const std::string name = integrator + (red ? "_red" : "");
    const json s = {{"width", 32},      {"height", 32},          {"integrator", integrator},
                    {"max_bounces", 4}, {"seed", 5},             {"mlt_chains", 32},
                    {"mlt_bootstrap", 4}, {"film_transparent", true}, {"shadow_catcher_pass", true}};
    const MergedParts run = render_and_merge(scene, s, kParts, 16, name + "_c");
    std::vector<Channels> images;
    for (const std::string &part : run.parts) images.push_back(read_channels(part));
    const Channels m = read_channels(run.merged);
    auto channel = [](const Channels &c, const std::string &name) {
      const auto it = std::find(c.names.begin(), c.names.end(), name);
      EXPECT_NE(it, c.names.end()) << name;
      return size_t(it - c.names.begin());
    };
    size_t lit = 0, matte_values = 0;
    double worst_matte = 0, worst_lit = 0;
    const size_t pass_r = channel(m, "Shadow Catcher.R");
    for (size_t i = 0; i < size_t(m.width) * m.height; ++i) {
      for (const char *name : {"R", "G", "B", "A"}) {  // the matte: the parts' average
        const size_t c = channel(m, name);
        double mean = 0;
        for (const Channels &part : images) mean += part.value(i, channel(part, name)) / kParts;
        worst_matte = std::max(worst_matte, std::fabs(m.value(i, c) - mean) / std::max(std::fabs(mean), 1e-3));
        matte_values += mean > 0;
      }
      bool every_part_lit = true;  // the pass exactly 1 in every part (and no ball seen)
      for (const Channels &part : images)
        for (int c = 0; c < 3; ++c)
          every_part_lit = every_part_lit && part.value(i, channel(part, "Shadow Catcher.R") + size_t(c)) == 1.0f &&
                           part.value(i, channel(part, "A")) == 0.0f;
      if (!every_part_lit) continue;
      ++lit;
      for (int c = 0; c < 3; ++c)
        worst_lit = std::max(worst_lit, std::fabs(double(m.value(i, pass_r + size_t(c))) - 1.0));
    }
    EXPECT_LT(worst_matte, 1e-5) << name;
    EXPECT_LT(worst_lit, 1e-4) << name;
    if (red) EXPECT_GT(matte_values, 100u) << name << ": the matte compares nothing";
    else EXPECT_GT(lit, 100u) << name << ": no sun-lit floor";
    std::printf("[ merge %-6s ] shadow catcher, 4 parts: matte values %zu, worst relative difference from the parts' "
                "average %.2g; lit floor pixels %zu, worst |pass - 1| %.2g\n",
                name.c_str(), matte_values, worst_matte, lit, worst_lit);
  }
}

}  // namespace test_render_parts
