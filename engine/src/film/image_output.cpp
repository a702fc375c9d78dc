#include "film/image_output.h"
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include "core/error.h"

namespace OCIO = OCIO_NAMESPACE;

namespace rdv {

std::string find_ocio_config() {
  if (const char *env = std::getenv("OCIO"); env && std::filesystem::exists(env)) return env;
  const char *candidates[] = {"/usr/share/blender/datafiles/colormanagement/config.ocio",
                              "/usr/share/blender/3.4/datafiles/colormanagement/config.ocio"};
  for (const char *c : candidates)
    if (std::filesystem::exists(c)) return c;
  return "";
}

static float srgb_oetf(float v) {
  v = clampf(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// Applies the display/view transform in place on RGBA pixels.
static std::string apply_view_transform(std::vector<float> &rgba, int w, int h, const std::string &view) {
  std::string config_path = find_ocio_config();
  if (!config_path.empty()) {
    try {
      OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(config_path.c_str());
      const char *display = config->getDefaultDisplay();
      auto t = OCIO::DisplayViewTransform::Create();
      t->setSrc(OCIO::ROLE_SCENE_LINEAR);
      t->setDisplay(display);
      t->setView(view.c_str());
      OCIO::ConstProcessorRcPtr processor = config->getProcessor(t);
      OCIO::PackedImageDesc desc(rgba.data(), w, h, 4);
      processor->getDefaultCPUProcessor()->apply(desc);
      return "";
    } catch (const OCIO::Exception &e) {
      std::string msg = std::string("OpenColorIO: ") + e.what() + "; wrote plain sRGB instead of view '" + view + "'";
      for (size_t i = 0; i < rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c) rgba[i + c] = srgb_oetf(rgba[i + c]);
      return msg;
    }
  }
  for (size_t i = 0; i < rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) rgba[i + c] = srgb_oetf(rgba[i + c]);
  return "no OpenColorIO config found (install blender or set $OCIO); wrote plain sRGB";
}

std::string write_image(const Film &film, const std::string &path, const std::string &view, const PartRecord *part) {
  int w = film.width(), h = film.height();
  std::string ext = std::filesystem::path(path).extension().string();
  for (char &c : ext) c = static_cast<char>(std::tolower(c));
  std::vector<float> rgba(size_t(w) * h * 4);
  film.read(RDV_PASS_COMBINED, 0, 0, w, h, true, rgba.data());
  std::string warning;
  auto out = OIIO::ImageOutput::create(path);
  if (!out) fail("cannot write '" + path + "': " + OIIO::geterror(), RDV_ERROR_IO);
  if (ext == ".exr") {
    // Combined RGBA plus the AOVs, as named channels.
    std::vector<float> depth(size_t(w) * h), normal(size_t(w) * h * 3), albedo(size_t(w) * h * 3);
    film.read(RDV_PASS_DEPTH, 0, 0, w, h, true, depth.data());
    film.read(RDV_PASS_NORMAL, 0, 0, w, h, true, normal.data());
    film.read(RDV_PASS_ALBEDO, 0, 0, w, h, true, albedo.data());
    // The estimated relative error of each pixel, when the frame has half images (a
    // merge of render parts too, when they kept theirs).
    std::vector<float> noise;
    if (film.frame_state().split != HalfSplit::None) {
      noise.resize(size_t(w) * h);
      film.read(RDV_PASS_NOISE, 0, 0, w, h, true, noise.data());
    }
    // The passes beyond those, as EXR layers (channel names as Blender's multilayer EXR has
    // them): Cycles' light passes when the film keeps them, its data passes when the
    // settings ask for them, BDPT's strategy passes when the film keeps them.
    struct Layer {
      rdv_pass pass;
      std::vector<std::string> channels;
    };
    std::vector<Layer> layers;
    static const std::pair<rdv_pass, const char *> kLightPasses[] = {
        {RDV_PASS_EMISSION, "Emit"},           {RDV_PASS_ENVIRONMENT, "Env"},
        {RDV_PASS_DIFFUSE_DIRECT, "DiffDir"},  {RDV_PASS_DIFFUSE_INDIRECT, "DiffInd"},
        {RDV_PASS_DIFFUSE_COLOR, "DiffCol"},   {RDV_PASS_GLOSSY_DIRECT, "GlossDir"},
        {RDV_PASS_GLOSSY_INDIRECT, "GlossInd"}, {RDV_PASS_GLOSSY_COLOR, "GlossCol"},
        {RDV_PASS_TRANSMISSION_DIRECT, "TransDir"}, {RDV_PASS_TRANSMISSION_INDIRECT, "TransInd"},
        {RDV_PASS_TRANSMISSION_COLOR, "TransCol"}, {RDV_PASS_VOLUME_DIRECT, "VolumeDir"},
        {RDV_PASS_VOLUME_INDIRECT, "VolumeInd"}};
    auto rgb = [](const std::string &name) { return std::vector<std::string>{name + ".R", name + ".G", name + ".B"}; };
    if (film.has_light_passes())
      for (const auto &[pass, name] : kLightPasses) layers.push_back({pass, rgb(name)});
    if (film.writes_data_passes())
      for (const auto &[pass, name] : {std::pair{RDV_PASS_MIST, "Mist.Z"}, std::pair{RDV_PASS_OBJECT_INDEX, "IndexOB.X"},
                                       std::pair{RDV_PASS_MATERIAL_INDEX, "IndexMA.X"}})
        layers.push_back({pass, {name}});
    if (film.has_denoising_passes()) {  // Blender's names: its Denoise node reads them
      layers.push_back({RDV_PASS_DENOISING_NORMAL, {"Denoising Normal.X", "Denoising Normal.Y", "Denoising Normal.Z"}});
      layers.push_back({RDV_PASS_DENOISING_ALBEDO, {"Denoising Albedo.R", "Denoising Albedo.G", "Denoising Albedo.B"}});
      layers.push_back({RDV_PASS_DENOISING_DEPTH, {"Denoising Depth.Z"}});
    }
    if (film.has_shadow_catcher() && film.catcher_display().pass)  // Combined is the matte: the shadow's here
      layers.push_back({RDV_PASS_SHADOW_CATCHER, rgb("Shadow Catcher")});
    const ShaderAovs &aovs = film.shader_aovs();  // Blender's layer names: the AOV's own
    for (size_t k = 0; k < aovs.passes.size(); ++k) {
      const ShaderAovs::Pass &a = aovs.passes[k];
      if (a.color) layers.push_back({rdv_pass(RDV_PASS_AOV_COLOR_FIRST + k), {a.name + ".R", a.name + ".G", a.name + ".B", a.name + ".A"}});
      else layers.push_back({rdv_pass(RDV_PASS_AOV_VALUE_FIRST + k), {a.name + ".X"}});
    }
    const Cryptomatte &crypto = film.cryptomatte();  // Blender's names: CryptoObject00.r, ...
    for (int kind = 0; kind < Cryptomatte::kKinds; ++kind) {
      if (!crypto.kinds[kind]) continue;
      for (int k = 0; k < crypto.passes_per_kind(); ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "%s%02d", Cryptomatte::pass_prefix(Cryptomatte::Kind(kind)), k);
        const std::string layer = name;
        layers.push_back({rdv_pass(RDV_PASS_CRYPTOMATTE_FIRST + kind * Cryptomatte::kMaxPassesPerKind + k),
                          {layer + ".r", layer + ".g", layer + ".b", layer + ".a"}});
      }
    }
    const StrategyPasses &strategies = film.strategy_passes();
    for (int k = 0; k < strategies.count(); ++k)
      layers.push_back({rdv_pass(RDV_PASS_STRATEGY_FIRST + k), rgb(strategies.name(k))});
    int layer_channels = 0;
    for (const Layer &layer : layers) layer_channels += int(layer.channels.size());
    std::vector<float> passes(size_t(w) * h * layer_channels);  // pixel-major, the layers' channels in order
    {
      std::vector<float> one;
      int first = 0;
      for (const Layer &layer : layers) {
        const int nc = int(layer.channels.size());
        one.resize(size_t(w) * h * nc);
        film.read(layer.pass, 0, 0, w, h, true, one.data());
        for (size_t i = 0; i < size_t(w) * h; ++i)
          for (int c = 0; c < nc; ++c) passes[i * layer_channels + first + c] = one[i * nc + c];
        first += nc;
      }
    }
    const int image_channels = (noise.empty() ? 11 : 12) + layer_channels;
    PartChannels extra;
    if (part) extra = part_channels(film, *part);
    const size_t extra_channels = extra.names.size();
    // One 32-bit word per channel: float bits for the image, unsigned for the part's sums.
    const size_t nc = image_channels + extra_channels;
    std::vector<uint32_t> all(size_t(w) * h * nc);
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      float d[12];
      for (int c = 0; c < 4; ++c) d[c] = rgba[i * 4 + c];
      d[4] = depth[i];
      for (int c = 0; c < 3; ++c) { d[5 + c] = normal[i * 3 + c]; d[8 + c] = albedo[i * 3 + c]; }
      if (!noise.empty()) d[11] = noise[i];
      const int base_channels = image_channels - layer_channels;
      std::memcpy(&all[i * nc], d, size_t(base_channels) * sizeof(float));
      if (layer_channels)
        std::memcpy(&all[i * nc + base_channels], &passes[i * layer_channels], size_t(layer_channels) * sizeof(float));
      if (extra_channels)
        std::memcpy(&all[i * nc + image_channels], &extra.words[i * extra_channels], extra_channels * 4);
    }
    OIIO::ImageSpec spec(w, h, int(nc), OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A", "Depth.Z", "Normal.X", "Normal.Y", "Normal.Z",
                         "Albedo.R", "Albedo.G", "Albedo.B"};
    if (!noise.empty()) spec.channelnames.push_back("Noise.V");
    for (const Layer &layer : layers)
      spec.channelnames.insert(spec.channelnames.end(), layer.channels.begin(), layer.channels.end());
    spec.channelformats.assign(image_channels, OIIO::TypeDesc::FLOAT);
    for (const std::string &name : extra.names) {
      spec.channelnames.push_back(name);
      spec.channelformats.push_back(OIIO::TypeDesc::UINT);
    }
    spec.alpha_channel = 3;
    spec.z_channel = 4;
    spec.attribute("compression", "zip");
    if (part) spec.attribute(part_attribute_name(), part->to_json());
    // Cryptomatte's metadata, as the standard has it (names, hash, conversion, manifest).
    for (auto it = film.crypto_metadata().begin(); it != film.crypto_metadata().end(); ++it)
      if (it->is_string()) spec.attribute(it.key(), it->get<std::string>());
    // TypeDesc::UNKNOWN: the buffer holds each channel in its own format.
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UNKNOWN, all.data()) || !out->close())
      fail("cannot write '" + path + "': " + out->geterror(), RDV_ERROR_IO);
    return warning;
  }
  // The film's colour is premultiplied by its alpha (a transparent film); PNG stores
  // straight alpha, as Blender writes it.
  for (size_t i = 0; i < rgba.size(); i += 4)
    if (rgba[i + 3] > 0 && rgba[i + 3] < 1)
      for (int c = 0; c < 3; ++c) rgba[i + c] /= rgba[i + 3];
  warning = apply_view_transform(rgba, w, h, view);
  std::vector<uint8_t> bytes(rgba.size());
  for (size_t i = 0; i < rgba.size(); ++i) {
    // Ordered dither of half a quantum hides banding in smooth gradients.
    float dither = ((i * 2654435761u >> 16) & 0xff) / 255.0f - 0.5f;
    bytes[i] = static_cast<uint8_t>(clampf(rgba[i] * 255.0f + 0.5f + dither * 0.5f, 0.0f, 255.0f));
  }
  OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) || !out->close())
    fail("cannot write '" + path + "': " + out->geterror(), RDV_ERROR_IO);
  return warning;
}

}  // namespace rdv
