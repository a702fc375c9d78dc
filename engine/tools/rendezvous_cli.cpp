// rendezvous: the command-line renderer. Renders a JSON scene (docs/scene-format.md)
// to PNG (through Blender's OpenColorIO view transform) or EXR (scene-linear float, a
// render part that `rendezvous merge` combines with others; docs/farm.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include "rendezvous.h"
#include "equal_time.h"
#include "scene_file.h"
#include "study.h"

namespace {

void usage() {
  std::fprintf(stderr,
               "usage: rendezvous SCENE.json [options]\n"
               "       rendezvous merge PART.exr... -o OUT.exr|OUT.png [--allow-missing] [--samples N] [--view NAME]\n"
               "       rendezvous study SCENE.json... [--integrators LIST] [--budgets LIST] [--reference SECONDS]\n"
               "                        [--out DIR] ... (rendezvous study --help)\n"
               "  -o, --output FILE      image to write (.png or .exr; default render.png)\n"
               "  --samples N            samples per pixel\n"
               "  --time SECONDS         time limit (0 = off)\n"
               "  --noise-target E       stop once the estimated relative MSE is below E (0 = off)\n"
               "  --adaptive T           adaptive sampling (path, bdpt): pixels stop below relative error T\n"
               "  --adaptive-min-samples N  samples before a pixel may stop (0 = automatic, 16)\n"
               "  --threads N            worker threads (0 = all cores)\n"
               "  --seed N               random seed\n"
               "  --sample-offset N      render samples [N, N + samples) of the sequence (a farm part)\n"
               "  --resolution WxH       image size\n"
               "  --integrator NAME      path, bdpt, pssmlt, mmlt or mlt (Metropolis: samples = mutations per pixel), or auto\n"
               "                         (with --time: pilots of each take 10%% of the time, the most efficient\n"
               "                         one, 1 / (estimated relMSE x time), renders the rest)\n"
               "  --mlt-large-step P     pssmlt / mmlt / mlt: probability of a large step\n"
               "  --mlt-bootstrap N      pssmlt / mmlt / mlt: bootstrap samples per pixel\n"
               "  --mlt-chains N         pssmlt / mmlt / mlt: number of Markov chains\n"
               "  --mlt-mutations B,L,P,S[,C[,M[,U]]]  mlt: weights of the bidirectional mutation, the lens\n"
               "                         perturbation, the propagation and scattering perturbations of medium\n"
               "                         vertices, the caustic and multi-chain perturbations and the lens subpath\n"
               "                         mutation (default 1 each; those a shorter list leaves out: 1)\n"
               "  --mlt-direct N         mlt: direct light (paths of one and two edges) by N path-traced samples\n"
               "                         per pixel, the chains take the rest (0: the chains take every path)\n"
               "  --mlt-equiangular P    mlt: probability that a camera-side distance in fog is drawn toward a point\n"
               "                         or spot lamp (equiangular) instead of by free flight (default 0: off)\n"
               "  --mlt-step-size S      pssmlt / mmlt: small-step size in primary sample space\n"
               "  --mlt-target T         pssmlt / mmlt / mlt: luminance or relative (even relative error)\n"
               "  --strategy S,T         bdpt: render only strategy (s, t), MIS-weighted\n"
               "  --unweighted           with --strategy: without its MIS weight\n"
               "  --mis NAME             bdpt weights: power (default), balance or lafortune_willems\n"
               "  --max-bounces N        maximum path length\n"
               "  --passes light         Cycles' light passes as EXR layers (Emit, Env, DiffDir, DiffInd, DiffCol,\n"
               "                         Gloss*, Trans*, VolumeDir, VolumeInd; path and bdpt);\n"
               "         data            Mist.Z, IndexOB.X, IndexMA.X (every integrator); e.g. --passes light,data\n"
               "         denoising       Denoising Normal / Albedo / Depth, Cycles' denoising data (every integrator)\n"
               "         shadowcatcher   path: a scene with a shadow catcher writes Combined as the matte and the\n"
               "                         layer 'Shadow Catcher' (else Combined holds the shadow, as Cycles)\n"
               "         cryptomatte     CryptoObject00.., CryptoMaterial00.., CryptoAsset00.. (6 levels) with the\n"
               "                         standard's metadata (every integrator; the instances' and materials' names)\n"
               "         strategies      bdpt: each strategy's MIS-weighted image, Strategy_s<S>t<T>, of paths up to\n"
               "                         --strategy-depth N bounces (default 3, at most 6), and Strategy_rest\n"
               "  --film-transparent     the world seen directly is transparent (alpha = coverage; PNG and EXR)\n"
               "  --motion-blur on|off   off: the shutter stays closed, objects render at their 'transform'\n"
               "  --transparent-glass    with it: also seen through smooth glass (Cycles' Transparent Glass)\n"
               "  --view NAME            PNG view transform: Standard (default) or Filmic\n"
               "  --summary              print what the engine modelled (JSON)\n"
               "  --quiet                no progress bar\n");
}

// The progress line's noise estimate (relative MSE), when the render makes one.
std::string noise_text(const rdv_progress &p) {
  if (p.noise_estimate < 0) return "";
  char text[96];
  if (!std::isfinite(p.noise_estimate)) std::snprintf(text, sizeof text, "  noise -");
  else std::snprintf(text, sizeof text, "  noise %.2e", p.noise_estimate);
  std::string out = text;
  if (p.noise_target > 0) {
    std::snprintf(text, sizeof text, " / %.2e", p.noise_target);
    out += text;
  }
  return out + "   ";
}

bool check(rdv_status s, const char *what) {
  if (s == RDV_OK) return true;
  std::fprintf(stderr, "rendezvous: %s: %s\n", what, rdv_last_error());
  return false;
}

// Identifies the scene in render parts: FNV-1a (64 bits) of the scene file's bytes.
// Files it refers to (textures, .vdb) are not part of it.
std::string scene_file_hash(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return rdv_tools::content_hash(bytes);
}

// rendezvous merge PART... -o OUT: adds render parts (rdv_merge_parts).
int merge_main(int argc, char **argv) {
  std::vector<std::string> parts;
  std::string output;
  nlohmann::json options = nlohmann::json::object();
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) { std::fprintf(stderr, "rendezvous merge: %s needs a value\n", a.c_str()); std::exit(2); }
      return argv[++i];
    };
    try {
      if (a == "-o" || a == "--output") output = next();
      else if (a == "--allow-missing") options["allow_missing"] = true;
      else if (a == "--samples") options["samples"] = std::stoi(next());
      else if (a == "--view") options["view"] = next();
      else if (!a.empty() && a[0] == '-') { std::fprintf(stderr, "rendezvous merge: unknown option %s\n", a.c_str()); return 2; }
      else parts.push_back(a);
    } catch (const std::exception &) {
      std::fprintf(stderr, "rendezvous merge: bad value for %s\n", a.c_str());
      return 2;
    }
  }
  if (parts.empty() || output.empty()) { usage(); return 2; }
  std::vector<const char *> paths;
  for (const std::string &p : parts) paths.push_back(p.c_str());
  const char *report = nullptr;
  if (!check(rdv_merge_parts(paths.data(), uint32_t(paths.size()), output.c_str(), options.dump().c_str(), &report),
             "merge"))
    return 1;
  nlohmann::json r = nlohmann::json::parse(report);
  for (const auto &w : r["warnings"]) std::fprintf(stderr, "rendezvous merge: warning: %s\n", w.get<std::string>().c_str());
  std::fprintf(stderr, "rendezvous merge: %zu parts, samples %s (%llu), wrote %s\n", parts.size(), r["ranges"].dump().c_str(),
               (unsigned long long)r["samples"].get<uint64_t>(), output.c_str());
  return 0;
}

}  // namespace

// Integrator auto's evidence: each candidate's pilots and the pick.
static void print_auto_choice(const nlohmann::json &choice, double time_limit) {
  const std::string pick = choice["integrator"].is_string() ? choice["integrator"].get<std::string>() : "";
  for (const nlohmann::json &p : choice["pilots"])
    std::fprintf(stderr,
                 "rendezvous: auto: %-6s pilot %.2f s, %u spp, estimated relMSE %.3g (own pilots %.3g, against "
                 "the others %.3g), efficiency %.3g /s%s\n",
                 p["integrator"].get<std::string>().c_str(), p["seconds"].get<double>(), p["spp"].get<unsigned>(),
                 p["rel_mse"].get<double>(), p.value("rel_mse_own", 0.0), p.value("rel_mse_cross", 0.0),
                 p["efficiency"].get<double>(),
                 p["integrator"] == pick ? "  <- chosen" : "");
  if (pick.empty())
    std::fprintf(stderr, "rendezvous: auto: cancelled during the pilots\n");
  else
    std::fprintf(stderr, "rendezvous: auto: chose %s; pilots took %.2f s of %.2f s%s\n", pick.c_str(),
                 choice["pilot_seconds"].get<double>(), time_limit,
                 choice.value("time_limit_extended", false) ? " (the time limit grew to give the pick 5% of it)" : "");
}

int main(int argc, char **argv) {
  if (argc > 1 && std::strcmp(argv[1], "merge") == 0) return merge_main(argc, argv);
  if (argc > 1 && std::strcmp(argv[1], "study") == 0) return rdv_tools::study_main(argc, argv);
  std::string scene_path, output = "render.png", view = "Standard";
  nlohmann::json overrides = nlohmann::json::object();
  rdv_tools::LoadOptions load_options;
  bool quiet = false, summary = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) { std::fprintf(stderr, "rendezvous: %s needs a value\n", a.c_str()); std::exit(2); }
      return argv[++i];
    };
    try {
      if (a == "-h" || a == "--help") { usage(); return 0; }
      else if (a == "-o" || a == "--output") output = next();
      else if (a == "--samples") overrides["samples"] = std::stoi(next());
      else if (a == "--time") overrides["time_limit"] = std::stod(next());
      else if (a == "--adaptive") {
        overrides["adaptive_sampling"] = true;
        overrides["adaptive_threshold"] = std::stod(next());
      } else if (a == "--adaptive-min-samples") overrides["adaptive_min_samples"] = std::stoi(next());
      else if (a == "--noise-target") {
        std::string v = next();
        double e = std::stod(v);
        if (!std::isfinite(e) || e < 0) {
          std::fprintf(stderr, "rendezvous: --noise-target must be a finite number >= 0 (relative MSE; 0 = off), got %s\n",
                       v.c_str());
          return 2;
        }
        overrides["noise_target"] = e;
      }
      else if (a == "--passes") {
        // Render passes beyond Combined / Depth / Normal / Albedo, as EXR layers: "light"
        // (Cycles' light passes, path and bdpt), "data" (Mist, Object and Material Index),
        // "denoising" (Cycles' Denoising Normal / Albedo / Depth), "strategies" (BDPT's
        // per-strategy images, docs/bdpt.md).
        std::stringstream list(next());
        std::string item;
        while (std::getline(list, item, ',')) {
          if (item == "light") overrides["light_passes"] = true;
          else if (item == "data") overrides["data_passes"] = true;
          else if (item == "denoising") overrides["denoising_passes"] = true;
          else if (item == "shadowcatcher") overrides["shadow_catcher_pass"] = true;
          else if (item == "strategies") overrides["strategy_passes"] = true;
          else if (item == "cryptomatte") overrides["cryptomatte"] = {{"object", true}, {"material", true}, {"asset", true}};
          else {
            std::fprintf(stderr, "rendezvous: --passes: unknown pass set '%s' (available: light, data, denoising, shadowcatcher, cryptomatte, strategies)\n",
                         item.c_str());
            return 2;
          }
        }
      }
      else if (a == "--film-transparent") overrides["film_transparent"] = true;
      else if (a == "--motion-blur") {
        std::string v = next();
        if (v != "on" && v != "off") {
          std::fprintf(stderr, "rendezvous: --motion-blur: expected on or off, got '%s'\n", v.c_str());
          return 2;
        }
        load_options.motion_blur = v == "on";
      }
      else if (a == "--transparent-glass") overrides["film_transparent_glass"] = true;
      else if (a == "--threads") overrides["threads"] = std::stoi(next());
      else if (a == "--seed") overrides["seed"] = std::stoi(next());
      else if (a == "--sample-offset") overrides["sample_offset"] = std::stoi(next());
      else if (a == "--integrator") overrides["integrator"] = next();
      else if (a == "--mis") overrides["mis"] = next();
      else if (a == "--mlt-large-step") overrides["mlt_large_step"] = std::stod(next());
      else if (a == "--mlt-bootstrap") overrides["mlt_bootstrap"] = std::stoi(next());
      else if (a == "--mlt-chains") overrides["mlt_chains"] = std::stoi(next());
      else if (a == "--mlt-mutations") {
        // B,L,P,S[,C[,M[,U]]]: the weights of mlt's bidirectional mutation, lens / propagation / scattering /
        // caustic / multi-chain perturbations and lens subpath mutation (the ones a shorter list leaves out
        // keep their defaults, as before they existed).
        std::stringstream list(next());
        std::string item;
        nlohmann::json w = nlohmann::json::object();
        for (const char *name :
             {"bidirectional", "lens", "propagation", "scattering", "caustic", "multi_chain", "lens_subpath"})
          w[name] = std::getline(list, item, ',') ? std::stof(item) : 1.0f;
        overrides["mlt_mutations"] = w;
      }
      else if (a == "--mlt-direct") overrides["mlt_direct_samples"] = std::stoi(next());
      else if (a == "--mlt-step-size") overrides["mlt_step_size"] = std::stod(next());
      else if (a == "--mlt-equiangular") overrides["mlt_equiangular"] = std::stod(next());
      else if (a == "--mlt-target") overrides["mlt_target"] = next();
      else if (a == "--strategy") {
        std::string v = next();
        size_t c = v.find(',');
        if (c == std::string::npos) throw std::invalid_argument(v);
        overrides["strategy"] = {std::stoi(v.substr(0, c)), std::stoi(v.substr(c + 1))};
      } else if (a == "--unweighted") overrides["strategy_unweighted"] = true;
      else if (a == "--strategy-depth") overrides["strategy_passes_max_depth"] = std::stoi(next());
      else if (a == "--max-bounces") overrides["max_bounces"] = std::stoi(next());
      else if (a == "--view") view = next();
      else if (a == "--quiet") quiet = true;
      else if (a == "--summary") summary = true;
      else if (a == "--resolution") {
        std::string v = next();
        size_t x = v.find('x');
        if (x == std::string::npos) throw std::invalid_argument(v);
        overrides["width"] = std::stoi(v.substr(0, x));
        overrides["height"] = std::stoi(v.substr(x + 1));
      } else if (!a.empty() && a[0] == '-') { std::fprintf(stderr, "rendezvous: unknown option %s\n", a.c_str()); usage(); return 2; }
      else scene_path = a;
    } catch (const std::exception &) {
      std::fprintf(stderr, "rendezvous: bad value for %s\n", a.c_str());
      return 2;
    }
  }
  if (scene_path.empty()) { usage(); return 2; }

  rdv_scene *scene = nullptr;
  if (!check(rdv_scene_create(&scene), "scene")) return 1;
  rdv_tools::LoadedScene loaded;
  try {
    loaded = rdv_tools::load_scene_file(scene_path, scene, load_options);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "rendezvous: %s\n", e.what());
    rdv_scene_destroy(scene);
    return 1;
  }
  for (const auto &p : loaded.problems) std::fprintf(stderr, "rendezvous: warning: %s\n", p.c_str());
  nlohmann::json settings = nlohmann::json::parse(loaded.settings_json);
  if ((overrides.contains("time_limit") || overrides.contains("noise_target")) && !overrides.contains("samples") &&
      !settings.contains("samples"))
    overrides["samples"] = 0;  // a time limit or noise target alone renders until it halts
  settings.update(overrides);
  if (!settings.contains("scene_hash")) settings["scene_hash"] = scene_file_hash(scene_path);

  rdv_session *session = nullptr;
  if (!check(rdv_session_create(scene, settings.dump().c_str(), &session), "session")) {
    rdv_scene_destroy(scene);
    return 1;
  }
  const char *text = nullptr;
  if (rdv_scene_messages(scene, &text) == RDV_OK && text && *text)
    std::fprintf(stderr, "rendezvous: warnings:\n%s", text);
  if (summary && rdv_scene_summary(scene, &text) == RDV_OK) std::printf("%s\n", text);

  check(rdv_session_start(session), "start");
  rdv_progress p{};
  while (true) {
    rdv_session_progress(session, &p);
    if (!quiet) {
      int bar = int(p.fraction_done * 40);
      std::fprintf(stderr, "\r[%-40s] %3d%%  %u spp  %.1f s  %.2f Mrays/s%s", std::string(bar, '#').c_str(),
                   int(p.fraction_done * 100), p.samples_done, p.elapsed_seconds, p.rays_per_second * 1e-6,
                   noise_text(p).c_str());
    }
    if (p.finished) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (!quiet) std::fprintf(stderr, "\n");
  if (!check(rdv_session_wait(session), "render")) {
    rdv_session_destroy(session);
    rdv_scene_destroy(scene);
    return 1;
  }
  rdv_session_progress(session, &p);
  std::fprintf(stderr, "rendezvous: %u samples/pixel in %.2f s, %.2f Mrays/s, %llu dropped samples\n",
               p.samples_done, p.elapsed_seconds, p.rays_per_second * 1e-6, (unsigned long long)p.samples_dropped);
  if (p.noise_target > 0)
    std::fprintf(stderr, "rendezvous: %s: estimated relative MSE %.3g, target %.3g\n",
                 p.noise_reached ? "noise target reached" : "noise target NOT reached", p.noise_estimate, p.noise_target);
  // The integrator's own figures (Metropolis: b, acceptance, chains) and its warnings.
  if (rdv_session_stats(session, &text) == RDV_OK && text && std::strcmp(text, "{}") != 0) {
    nlohmann::json stats = nlohmann::json::parse(text);
    if (stats.contains("warning")) std::fprintf(stderr, "rendezvous: warning: %s\n", stats["warning"].get<std::string>().c_str());
    if (stats.contains("auto")) print_auto_choice(stats["auto"], p.time_limit_seconds);
    if (stats.contains("b"))
      std::fprintf(stderr,
                   "rendezvous: %s: %s target, %u chains, b = %.6g +- %.2g (%llu bootstrap samples), acceptance: %s "
                   "%.3f, large steps %.3f (%.3f found light), %.3g mutations/s\n",
                   stats["integrator"].get<std::string>().c_str(), stats.value("target", "luminance").c_str(),
                   stats["chains"].get<unsigned>(), stats["b"].get<double>(),
                   stats["b_standard_error"].get<double>(), (unsigned long long)stats["bootstrap_samples"].get<uint64_t>(),
                   "small steps", stats["small_step_acceptance"].get<double>(), stats["large_step_acceptance"].get<double>(),
                   stats.value("large_step_found", 0.0), p.elapsed_seconds > 0 ? stats["mutations"].get<double>() / p.elapsed_seconds : 0.0);
    if (stats.contains("mutation_types")) {  // mlt: acceptance per mutation type
      std::string line = "rendezvous: mutations (acceptance, proposals):";
      for (auto it = stats["mutation_types"].begin(); it != stats["mutation_types"].end(); ++it) {
        char part[96];
        std::snprintf(part, sizeof part, " %s %.3f (%llu)", it.key().c_str(), it.value()["acceptance"].get<double>(),
                      (unsigned long long)it.value()["proposals"].get<uint64_t>());
        line += part;
      }
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    if (summary) std::printf("%s\n", text);
  }
  int rc = check(rdv_session_write_image(session, output.c_str(), view.c_str()), "write image") ? 0 : 1;
  if (rc == 0) std::fprintf(stderr, "rendezvous: wrote %s\n", output.c_str());
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
  return rc;
}
