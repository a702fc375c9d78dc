#include "textures/image_texture.h"
#include <algorithm>
#include <cstdlib>
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>
#include <map>
#include <mutex>
#include <vector>
#include "film/image_output.h"

namespace rdv {

namespace OCIO = OCIO_NAMESPACE;
using OIIO::TextureOpt;
using OIIO::TextureSystem;
using OIIO::ustring;

// ---- colour spaces --------------------------------------------------------------
namespace {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c * (1.0f / 12.92f) : std::pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

struct ColorSpaces {
  std::mutex mutex;
  OCIO::ConstConfigRcPtr config;
  bool tried = false;
  std::map<std::string, OCIO::ConstCPUProcessorRcPtr> processors;  // null: identity

  // Returns false for an unknown space; *proc null means identity.
  bool processor(const std::string &name, OCIO::ConstCPUProcessorRcPtr *proc) {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = processors.find(name);
    if (it != processors.end()) { *proc = it->second; return true; }
    if (!tried) {
      tried = true;
      std::string path = find_ocio_config();
      try {
        if (!path.empty()) config = OCIO::Config::CreateFromFile(path.c_str());
      } catch (const OCIO::Exception &) {
        config.reset();
      }
    }
    OCIO::ConstCPUProcessorRcPtr p;
    if (name == "Non-Color" || name == "Raw" || name == "Linear" || name == "scene_linear" || name == "Linear Rec.709") {
      processors[name] = p;  // data or already scene-linear Rec.709
      *proc = p;
      return true;
    }
    if (!config) {
      if (name != "sRGB") return false;
      processors[name] = p;  // handled by the built-in sRGB curve in to_scene_linear
      *proc = p;
      return true;
    }
    try {
      if (!config->getColorSpace(name.c_str())) return false;
      p = config->getProcessor(name.c_str(), OCIO::ROLE_SCENE_LINEAR)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception &) {
      return false;
    }
    processors[name] = p;
    *proc = p;
    return true;
  }
};

ColorSpaces &color_spaces() {
  static ColorSpaces cs;
  return cs;
}

}  // namespace

bool to_scene_linear(const std::string &colorspace, Color &c) {
  OCIO::ConstCPUProcessorRcPtr p;
  if (!color_spaces().processor(colorspace, &p)) return false;
  if (p) {
    float rgb[3] = {c.x, c.y, c.z};
    p->applyRGB(rgb);
    c = {rgb[0], rgb[1], rgb[2]};
  } else if (colorspace == "sRGB" && !color_spaces().config) {
    c = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
  }
  return true;
}

// ---- images ---------------------------------------------------------------------
struct ImageTextures::Impl {
  struct Image {
    std::string path;
    TextureSystem::TextureHandle *handle = nullptr;
    int channels = 3;
    OCIO::ConstCPUProcessorRcPtr processor;  // null: identity
    bool builtin_srgb = false;               // no OCIO config: the sRGB curve by hand
  };
  TextureSystem *ts = nullptr;
  mutable std::mutex mutex;
  // Fixed capacity: lookups on render threads never race with a reallocation when
  // another scene registers images.
  static constexpr size_t kMaxImages = 1 << 16;
  std::vector<Image> images;
  std::map<std::pair<std::string, std::string>, int> by_key;
  float cache_mb = 256;
};

ImageTextures &ImageTextures::instance() {
  static ImageTextures t;
  return t;
}

ImageTextures::ImageTextures() : impl_(new Impl) {
  impl_->images.reserve(Impl::kMaxImages);
  impl_->ts = TextureSystem::create(false);  // our own cache, not the process-wide one
  if (const char *env = std::getenv("RDV_TEXTURE_CACHE_MB")) impl_->cache_mb = std::max(16.0f, float(std::atof(env)));
  impl_->ts->attribute("max_memory_MB", impl_->cache_mb);
  impl_->ts->attribute("autotile", 64);
  impl_->ts->attribute("automip", 1);
  impl_->ts->attribute("unassociatedalpha", 1);  // Blender's Image Texture gives straight colour
  impl_->ts->attribute("max_open_files", 100);
}

void ImageTextures::set_cache_megabytes(float mb) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->cache_mb = mb;
  impl_->ts->attribute("max_memory_MB", mb);
}
float ImageTextures::cache_megabytes() const { return impl_->cache_mb; }

size_t ImageTextures::cache_memory_bytes() const {
  long long used = 0;
  impl_->ts->imagecache()->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &used);
  return size_t(used);
}

int ImageTextures::num_images() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return int(impl_->images.size());
}

std::string ImageTextures::stats() const { return impl_->ts->getstats(1); }

int ImageTextures::load(const std::string &path, const std::string &colorspace, std::string &problem) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  auto key = std::make_pair(path, colorspace);
  if (auto it = impl_->by_key.find(key); it != impl_->by_key.end()) return it->second;
  TextureSystem *ts = impl_->ts;
  Impl::Image img;
  img.path = path;
  img.handle = ts->get_texture_handle(ustring(path));
  OIIO::ImageSpec spec;
  if (!img.handle || !ts->good(img.handle) || !ts->get_imagespec(img.handle, nullptr, 0, spec)) {
    std::string err = ts->geterror();
    problem = "cannot read '" + path + "'" + (err.empty() ? "" : ": " + err);
    return -1;
  }
  if (impl_->images.size() >= Impl::kMaxImages) {
    problem = "too many images (" + std::to_string(Impl::kMaxImages) + ")";
    return -1;
  }
  img.channels = std::clamp(spec.nchannels, 1, 4);
  std::string cs = colorspace;
  if (cs.empty()) cs = spec.format.is_floating_point() ? "Linear" : "sRGB";
  OCIO::ConstCPUProcessorRcPtr proc;
  if (!color_spaces().processor(cs, &proc)) {
    problem = "unknown colour space '" + cs + "' for '" + path + "' (not in Blender's config); using its values as they are";
  }
  img.processor = proc;
  img.builtin_srgb = cs == "sRGB" && !proc && !color_spaces().config;
  impl_->images.push_back(img);
  int id = int(impl_->images.size() - 1);
  impl_->by_key[key] = id;
  return id;
}

Color ImageTextures::lookup(int id, float u, float v, TexInterp interp, TexExtension ext, float *alpha) const {
  const Impl::Image &img = impl_->images[size_t(id)];
  TextureOpt opt;
  switch (ext) {
    case TexExtension::Repeat: opt.swrap = opt.twrap = TextureOpt::WrapPeriodic; break;
    case TexExtension::Extend: opt.swrap = opt.twrap = TextureOpt::WrapClamp; break;
    case TexExtension::Clip: opt.swrap = opt.twrap = TextureOpt::WrapBlack; break;
    case TexExtension::Mirror: opt.swrap = opt.twrap = TextureOpt::WrapMirror; break;
  }
  switch (interp) {
    case TexInterp::Linear: opt.interpmode = TextureOpt::InterpBilinear; break;
    case TexInterp::Closest: opt.interpmode = TextureOpt::InterpClosest; break;
    case TexInterp::Cubic: opt.interpmode = TextureOpt::InterpBicubic; break;
  }
  opt.mipmode = TextureOpt::MipModeNoMIP;  // no ray differentials yet: finest level
  float r[4] = {0, 0, 0, 1};
  TextureSystem *ts = impl_->ts;
  // OIIO's t runs down from the top row; Blender's v runs up from the bottom.
  if (!ts->texture(img.handle, ts->get_perthread_info(), opt, u, 1.0f - v, 0, 0, 0, 0, img.channels, r)) {
    (void)ts->geterror();
    if (alpha) *alpha = 1;
    return Color(1, 0, 1);
  }
  Color c;
  float a = 1;
  switch (img.channels) {
    case 1: c = Color(r[0]); break;
    case 2: c = Color(r[0]); a = r[1]; break;
    case 3: c = {r[0], r[1], r[2]}; break;
    default: c = {r[0], r[1], r[2]}; a = r[3]; break;
  }
  if (ext == TexExtension::Clip && (u < 0 || u > 1 || v < 0 || v > 1)) a = 0;
  if (img.processor) {
    float rgb[3] = {c.x, c.y, c.z};
    img.processor->applyRGB(rgb);
    c = {rgb[0], rgb[1], rgb[2]};
  } else if (img.builtin_srgb) {
    c = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
  }
  if (alpha) *alpha = a;
  return c;
}

}  // namespace rdv
