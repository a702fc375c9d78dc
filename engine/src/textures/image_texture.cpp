#include "textures/image_texture.h"
#include <algorithm>
#include <cstdlib>
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>
#include <tbb/parallel_for.h>
#include <map>
#include <mutex>
#include <vector>
#include "core/error.h"
#include "core/limits.h"
#include "film/image_output.h"
#include "textures/image_mips.h"

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
    // Small images stay resident (decoded once) and are filtered here for Closest and
    // Linear: a lookup costs ~30 ns instead of ~250 ns through the tile cache.
    bool resident = false;
    int w = 0, h = 0;
    std::vector<uint8_t> bytes;  // 8-bit files
    std::vector<float> floats;   // everything else
    // MIP levels first_mip, first_mip + 1, ... in scene-linear floats (image_mips.h): a
    // resident image's from level 1, a cached one's from the first of at most
    // kCoarseTexels texels where its colour space is not linear (OpenImageIO's own levels
    // average the file's values, which a nonlinear conversion makes darker than the mean of
    // unfiltered lookups); empty: OpenImageIO's levels.
    std::vector<MipLevel> mips;
    int first_mip = 1;
    // The colour-space conversion as a per-channel table over [0, 1] when it is one
    // (sRGB, most of Blender's spaces), else null (OCIO per lookup).
    std::vector<float> lut;
    bool from_memory = false;  // add_pixels (released by MemoryImage); like movie frames, no
                               // cache handle: Cubic is filtered here
  };
  static constexpr size_t kResidentTexels = size_t(1) << 22;      // up to 2048 x 2048
  static constexpr size_t kResidentBudget = size_t(128) << 20;    // bytes over all images
  // Cached images' own coarse levels (build_coarse_mips): the finest kept has at most
  // kCoarseTexels texels (RGB: 12 MB, 16 MB with the rest), for files up to kCoarseSourceTexels.
  static constexpr size_t kCoarseTexels = size_t(1) << 20;        // 1024 x 1024
  static constexpr size_t kCoarseSourceTexels = size_t(1) << 26;  // 8192 x 8192
  static constexpr int kLutSize = 4096;
  size_t resident_bytes = 0;
  TextureSystem *ts = nullptr;
  mutable std::mutex mutex;
  // Fixed capacity: lookups on render threads never race with a reallocation when
  // another scene registers images.
  static constexpr size_t kMaxImages = 1 << 16;
  std::vector<Image> images;
  std::map<std::pair<std::string, std::string>, int> by_key;
  std::vector<int> free_slots;  // released memory images' ids, reused first
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

namespace {

// True if the conversion acts on each channel alone (then a 1D table represents it).
bool per_channel(const OCIO::ConstCPUProcessorRcPtr &p) {
  const float probes[4][3] = {{0.2f, 0.7f, 0.45f}, {0.9f, 0.1f, 0.3f}, {0.05f, 0.5f, 0.95f}, {0.6f, 0.6f, 0.0f}};
  for (auto &q : probes) {
    float all[3] = {q[0], q[1], q[2]};
    p->applyRGB(all);
    for (int c = 0; c < 3; ++c) {
      float one[3] = {q[c], q[c], q[c]};
      p->applyRGB(one);
      if (std::fabs(one[c] - all[c]) > 1e-5f * std::max(1.0f, std::fabs(all[c]))) return false;
    }
  }
  return true;
}

}  // namespace

using Image = ImageTextures::Impl::Image;

static void make_lut(Image &img) {
  using Impl = ImageTextures::Impl;
  if (!per_channel(img.processor)) return;
  img.lut.resize(Impl::kLutSize * 3);
  for (int i = 0; i < Impl::kLutSize; ++i) {
    float v = float(i) / (Impl::kLutSize - 1);
    float rgb[3] = {v, v, v};
    img.processor->applyRGB(rgb);
    for (int c = 0; c < 3; ++c) img.lut[size_t(i) * 3 + c] = rgb[c];
  }
}

// A colour in the file's space to scene-linear.
static Color to_linear(const Image &img, Color c) {
  using Impl = ImageTextures::Impl;
  if (!img.lut.empty()) {
    for (int k = 0; k < 3; ++k) {
      float x = c[k];
      if (x >= 0 && x <= 1) {
        float f = x * (Impl::kLutSize - 1);
        int i = std::min(int(f), Impl::kLutSize - 2);
        float w = f - i;
        c[k] = img.lut[size_t(i) * 3 + k] * (1 - w) + img.lut[size_t(i + 1) * 3 + k] * w;
      } else {
        float rgb[3] = {x, x, x};
        img.processor->applyRGB(rgb);
        c[k] = rgb[k];
      }
    }
  } else if (img.processor) {
    float rgb[3] = {c.x, c.y, c.z};
    img.processor->applyRGB(rgb);
    c = {rgb[0], rgb[1], rgb[2]};
  } else if (img.builtin_srgb) {
    c = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
  }
  return c;
}

// Channels as filtered (grey, grey + alpha, RGB, RGBA) to linear colour and alpha.
static Color finish(const Image &img, const float r[4], float *alpha, bool linear) {
  Color c;
  float a = 1;
  switch (img.channels) {
    case 1: c = Color(r[0]); break;
    case 2: c = Color(r[0]); a = r[1]; break;
    case 3: c = {r[0], r[1], r[2]}; break;
    default: c = {r[0], r[1], r[2]}; a = r[3]; break;
  }
  if (alpha) *alpha = a;
  return linear ? c : to_linear(img, c);
}

// Whether the conversion to scene-linear is not linear: MIP levels are then built here
// (image_mips.h), so that a filtered lookup sees the mean of unfiltered ones.
static bool nonlinear(const Image &img) { return img.builtin_srgb || img.processor || !img.lut.empty(); }

static MipSource mip_source(const Image &img) {
  MipSource s;
  s.w = img.w;
  s.h = img.h;
  s.channels = img.channels;
  s.nonlinear = nonlinear(img);
  // Through the lookups' own conversion (a table for most spaces), so the means are of
  // exactly what they return.
  s.to_scene_linear = [&img](const float r[4]) { return finish(img, r, nullptr, false); };
  return s;
}

// Levels 1, 2, ... of a resident image (image_mips.h): a filtered lookup (a camera path's ray
// cone) sees the mean of what an unfiltered one (light paths, mlt) sees. Cost: 0.55 s more for
// a 2048 x 2048 sRGB image of noise on 2 cores than with the texels' converted values.
static void build_mips(Image &img) {
  MipSource s = mip_source(img);
  const size_t row = size_t(img.w) * size_t(img.channels);
  s.read = [&img, row](int y0, int y1, float *dst) {
    const size_t n = size_t(y1 - y0) * row, o = size_t(y0) * row;
    if (img.bytes.empty()) std::copy_n(&img.floats[o], n, dst);
    else
      for (size_t i = 0; i < n; ++i) dst[i] = img.bytes[o + i] * (1.0f / 255.0f);
    return true;
  };
  build_mip_levels(s, 1, img.mips);
  img.first_mip = 1;
}

// An image read whole (untiled files: OpenImageIO's automip builds the MIP levels in memory;
// movie and sequence frames: decoded here), in float with its MIP levels, must fit the
// memory budget: a header claiming 100000 x 100000 texels is a problem naming the file,
// not a 149 GB allocation. Tiled files stream through the bounded tile cache.
static bool fits_in_memory(const OIIO::ImageSpec &spec, const std::string &path, std::string &problem) {
  double bytes = double(spec.width) * spec.height * std::max(spec.depth, 1) * std::clamp(spec.nchannels, 1, 4) *
                 sizeof(float) * 4 / 3;
  if (bytes <= memory_budget_bytes()) return true;
  problem = "'" + path + "' is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
            " texels: reading it needs about " + format_bytes(bytes) + ", more than the " +
            format_bytes(memory_budget_bytes()) + " of memory available to the engine";
  return false;
}

static void make_resident(ImageTextures::Impl &impl, Image &img, const OIIO::ImageSpec &spec) {
  using Impl = ImageTextures::Impl;
  size_t texels = size_t(spec.width) * spec.height;
  bool is_byte = spec.format == OIIO::TypeDesc::UINT8;
  size_t bytes = texels * img.channels * (is_byte ? 1 : 4);
  bytes += (texels / 3 + 1) * img.channels * sizeof(float);  // the MIP levels (a third of the texels)
  if (texels > Impl::kResidentTexels || impl.resident_bytes + bytes > Impl::kResidentBudget) return;
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // straight colour, as the cache gives it
  auto in = OIIO::ImageInput::open(img.path, &config);
  if (!in) { (void)OIIO::geterror(); return; }
  bool ok;
  if (is_byte) {
    img.bytes.resize(texels * img.channels);
    ok = in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::UINT8, img.bytes.data());
  } else {
    img.floats.resize(texels * img.channels);
    ok = in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.floats.data());
  }
  if (!ok) {
    (void)in->geterror();
    img.bytes.clear();
    img.floats.clear();
    return;
  }
  img.w = spec.width;
  img.h = spec.height;
  build_mips(img);
  img.resident = true;
  impl.resident_bytes += bytes;
}

// A cached image in a nonlinear colour space: its own levels from the first of at most
// kCoarseTexels texels down (the finer ones: OpenImageIO's finest level and a blend toward the
// first, between_levels), its rows read once through the cache at load. A far view of a
// 4096 x 4096 sRGB PNG of noise rendered in 3.3 s where OIIO's own levels took 4.7 s (its
// automip of an untiled file). Files larger than kCoarseSourceTexels keep OIIO's levels.
static void build_coarse_mips(ImageTextures::Impl &impl, Image &img, const OIIO::ImageSpec &spec) {
  using Impl = ImageTextures::Impl;
  if (!nonlinear(img) || spec.depth > 1 || size_t(spec.width) * size_t(spec.height) > Impl::kCoarseSourceTexels) return;
  int first = 1;  // the first level of at most kCoarseTexels texels
  for (int w = std::max(spec.width / 2, 1), h = std::max(spec.height / 2, 1); size_t(w) * size_t(h) > Impl::kCoarseTexels;
       ++first) {
    w = std::max(w / 2, 1);
    h = std::max(h / 2, 1);
  }
  img.w = spec.width;
  img.h = spec.height;
  MipSource s = mip_source(img);
  OIIO::ImageCache *cache = impl.ts->imagecache();
  const ustring file(img.path);
  s.read = [&](int y0, int y1, float *dst) {
    return cache->get_pixels(file, 0, 0, spec.x, spec.x + spec.width, spec.y + y0, spec.y + y1, 0, 1, 0, img.channels,
                             OIIO::TypeDesc::FLOAT, dst);
  };
  std::vector<MipLevel> levels;
  if (!build_mip_levels(s, first, levels)) {
    (void)cache->geterror();
    return;  // OpenImageIO's levels, as before
  }
  img.mips = std::move(levels);
  img.first_mip = first;
}

size_t ImageTextures::resident_bytes() const { return impl_->resident_bytes; }

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
  OIIO::ImageSpec native;  // the file's own tiling (the cache's spec shows autotile's)
  if (ts->imagecache()->get_imagespec(ustring(path), native, 0, 0, true) && native.tile_width == 0 &&
      !fits_in_memory(native, path, problem))
    return -1;
  img.channels = std::clamp(spec.nchannels, 1, 4);
  std::string cs = colorspace;
  if (cs.empty()) cs = spec.format.is_floating_point() ? "Linear" : "sRGB";
  OCIO::ConstCPUProcessorRcPtr proc;
  if (!color_spaces().processor(cs, &proc)) {
    problem = "unknown colour space '" + cs + "' for '" + path + "' (not in Blender's config); using its values as they are";
  }
  img.processor = proc;
  img.builtin_srgb = cs == "sRGB" && !proc && !color_spaces().config;
  if (img.processor) make_lut(img);
  make_resident(*impl_, img, spec);
  if (!img.resident) build_coarse_mips(*impl_, img, spec);
  impl_->images.push_back(img);
  int id = int(impl_->images.size() - 1);
  impl_->by_key[key] = id;
  return id;
}

namespace {

// A resident image of w x h texels from `pixels` (rows bottom first if bottom_up, else top
// first), non-finite values set to 0 (counted); the colour space's processor set.
Image memory_image(const float *pixels, int width, int height, int channels, bool bottom_up,
                   const std::string &colorspace, std::string &problem, size_t *non_finite);

}  // namespace

int ImageTextures::add_pixels(const float *pixels, int width, int height, int channels,
                              const std::string &colorspace, std::string &problem, size_t *non_finite) {
  Image img = memory_image(pixels, width, height, channels, true, colorspace, problem, non_finite);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (!impl_->free_slots.empty()) {
    int id = impl_->free_slots.back();
    impl_->free_slots.pop_back();
    impl_->images[size_t(id)] = std::move(img);
    return id;
  }
  if (impl_->images.size() >= Impl::kMaxImages) fail("too many images (" + std::to_string(Impl::kMaxImages) + ")");
  impl_->images.push_back(std::move(img));
  return int(impl_->images.size() - 1);
}

int ImageTextures::load_frame(const std::string &path, int frame, const std::string &colorspace,
                              std::string &problem) {
  auto key = std::make_pair(path + "#frame " + std::to_string(frame), colorspace);
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (auto it = impl_->by_key.find(key); it != impl_->by_key.end()) return it->second;
  }
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    problem = "cannot read '" + path + "': " + OIIO::geterror();
    return -1;
  }
  if (frame < 0 || !in->seek_subimage(frame, 0)) {
    int frames = in->spec().get_int_attribute("oiio:subimages", 1);
    (void)in->geterror();
    problem = "'" + path + "' has no frame " + std::to_string(frame + 1) + " (" + std::to_string(frames) + " frames)";
    return -1;
  }
  const OIIO::ImageSpec &spec = in->spec();
  if (!fits_in_memory(spec, path, problem)) return -1;
  int channels = std::clamp(spec.nchannels, 1, 4);
  std::vector<float> pixels(size_t(spec.width) * spec.height * channels);
  if (!in->read_image(frame, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    problem = "cannot read frame " + std::to_string(frame + 1) + " of '" + path + "': " + in->geterror();
    return -1;
  }
  std::string cs = colorspace.empty() ? (spec.format.is_floating_point() ? "Linear" : "sRGB") : colorspace;
  Image img = memory_image(pixels.data(), spec.width, spec.height, channels, false, cs, problem, nullptr);
  img.path = path;
  img.from_memory = false;  // kept with the files: never released
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (auto it = impl_->by_key.find(key); it != impl_->by_key.end()) return it->second;
  if (impl_->images.size() >= Impl::kMaxImages) {
    problem = "too many images (" + std::to_string(Impl::kMaxImages) + ")";
    return -1;
  }
  impl_->images.push_back(std::move(img));
  int id = int(impl_->images.size() - 1);
  impl_->by_key[key] = id;
  return id;
}

namespace {

Image memory_image(const float *pixels, int width, int height, int channels, bool bottom_up,
                   const std::string &colorspace, std::string &problem, size_t *non_finite) {
  Image img;
  img.from_memory = true;
  img.resident = true;
  img.w = width;
  img.h = height;
  img.channels = channels;
  std::string cs = colorspace.empty() ? "Linear" : colorspace;
  OCIO::ConstCPUProcessorRcPtr proc;
  if (!color_spaces().processor(cs, &proc))
    problem = "unknown colour space '" + cs + "' (not in Blender's config); using its values as they are";
  img.processor = proc;
  img.builtin_srgb = cs == "sRGB" && !proc && !color_spaces().config;
  if (img.processor) make_lut(img);
  // Rows top first, as files are read (lookups count t down from the top row).
  const size_t row = size_t(width) * channels;
  img.floats.resize(row * height);
  size_t bad = 0;
  for (int y = 0; y < height; ++y) {
    const float *src = pixels + size_t(bottom_up ? height - 1 - y : y) * row;
    float *dst = &img.floats[size_t(y) * row];
    for (size_t i = 0; i < row; ++i) {
      float v = src[i];
      if (!std::isfinite(v)) { v = 0; ++bad; }
      dst[i] = v;
    }
  }
  if (non_finite) *non_finite = bad;
  build_mips(img);
  return img;
}

}  // namespace

void ImageTextures::release(int id) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (id < 0 || size_t(id) >= impl_->images.size() || !impl_->images[size_t(id)].from_memory) return;
  impl_->images[size_t(id)] = Impl::Image();  // frees the texels; nothing looks this id up any more
  impl_->free_slots.push_back(id);
}

namespace {

// Texel index under Blender's extension modes; -1 = outside (Clip).
inline int wrap_index(int i, int n, TexExtension ext) {
  switch (ext) {
    case TexExtension::Repeat: i %= n; return i < 0 ? i + n : i;
    case TexExtension::Extend: return std::clamp(i, 0, n - 1);
    case TexExtension::Clip: return (i < 0 || i >= n) ? -1 : i;
    case TexExtension::Mirror: {
      int p = i % (2 * n);
      if (p < 0) p += 2 * n;
      return p < n ? p : 2 * n - 1 - p;
    }
  }
  return 0;
}

// The two texels bilinear filtering blends along one axis, i and i + 1, wrapped. Repeat
// (the common case) needs no integer division inside the image.
inline void wrap_pair(int i, int n, TexExtension ext, int &i0, int &i1) {
  if (ext == TexExtension::Repeat) {
    i0 = i >= 0 && i < n ? i : wrap_index(i, n, ext);
    i1 = i0 + 1 == n ? 0 : i0 + 1;
    return;
  }
  i0 = wrap_index(i, n, ext);
  i1 = wrap_index(i + 1, n, ext);
}

// Closest or bilinear filtering of a w x h level at (u, v); fetch(x, y, weight, r)
// adds a texel (already wrapped) into r.
template <class Fetch>
void filter_level(int w, int h, float u, float v, bool closest, TexExtension ext, const Fetch &fetch, float r[4]) {
  auto add = [&](int x, int y, float weight) {
    if (x >= 0 && y >= 0) fetch(x, y, weight, r);  // Clip: transparent black outside
  };
  // OIIO's t runs down from the top row; Blender's v runs up from the bottom.
  float s = u * w, t = (1.0f - v) * h;
  // Texel indices are ints: a coordinate beyond their range (or NaN) reads texel 0.
  if (!(std::fabs(s) < 1e9f && std::fabs(t) < 1e9f)) s = t = 0;
  if (closest) {
    add(wrap_index(int(std::floor(s)), w, ext), wrap_index(int(std::floor(t)), h, ext), 1.0f);
    return;
  }
  s -= 0.5f;
  t -= 0.5f;
  float fs = std::floor(s), ft = std::floor(t);
  int x0, x1, y0, y1;
  wrap_pair(int(fs), w, ext, x0, x1);
  wrap_pair(int(ft), h, ext, y0, y1);
  float ws = s - fs, wt = t - ft;
  add(x0, y0, (1 - ws) * (1 - wt));
  add(x1, y0, ws * (1 - wt));
  add(x0, y1, (1 - ws) * wt);
  add(x1, y1, ws * wt);
}

// Filters w x h texels of NC channels (scaled by `scale`: 1/255 for bytes) into r;
// the channel count is a template argument so the per-texel loops unroll.
template <int NC, class T>
void filter_texels(const T *texels, float scale, int w, int h, float u, float v, bool closest, TexExtension ext,
                   float r[4]) {
  filter_level(w, h, u, v, closest, ext, [&](int x, int y, float weight, float *acc) {
    const T *t = &texels[(size_t(y) * w + x) * NC];
    for (int c = 0; c < NC; ++c) acc[c] += weight * float(t[c]) * scale;
  }, r);
}

template <class T>
void filter_texels(int nc, const T *texels, float scale, int w, int h, float u, float v, bool closest,
                   TexExtension ext, float r[4]) {
  switch (nc) {
    case 1: return filter_texels<1>(texels, scale, w, h, u, v, closest, ext, r);
    case 2: return filter_texels<2>(texels, scale, w, h, u, v, closest, ext, r);
    case 3: return filter_texels<3>(texels, scale, w, h, u, v, closest, ext, r);
    default: return filter_texels<4>(texels, scale, w, h, u, v, closest, ext, r);
  }
}

// Level l of a resident image (0: the file's texels) or a coarse level of a cached one
// (l >= first_mip), filtered, in scene-linear colour.
Color lookup_level(const Image &img, int l, float u, float v, bool closest, TexExtension ext, float *alpha) {
  const int nc = img.channels;
  float r[4] = {0, 0, 0, 0};
  if (l > 0) {
    const MipLevel &level = img.mips[size_t(l - img.first_mip)];
    filter_texels(nc, level.texels.data(), 1.0f, level.w, level.h, u, v, closest, ext, r);
    return finish(img, r, alpha, true);
  }
  if (!img.bytes.empty()) filter_texels(nc, img.bytes.data(), 1.0f / 255.0f, img.w, img.h, u, v, closest, ext, r);
  else filter_texels(nc, img.floats.data(), 1.0f, img.w, img.h, u, v, closest, ext, r);
  return finish(img, r, alpha, false);
}

// Cubic B-spline filtering of level 0 (the weights of OIIO's and Cycles' bicubic), in the
// image's colour space, then converted: images from memory, which have no OIIO handle.
template <int NC>
Color bicubic_level0(const Image &img, float u, float v, TexExtension ext, float *alpha) {
  float s = u * img.w - 0.5f, t = (1.0f - v) * img.h - 0.5f;
  // Texel indices are ints: a coordinate beyond their range (or NaN) reads texel 0.
  if (!(std::fabs(s) < 1e9f && std::fabs(t) < 1e9f)) s = t = 0;
  float fs = std::floor(s), ft = std::floor(t);
  auto weights = [](float f, float w[4]) {
    float f2 = f * f, f3 = f2 * f;
    w[0] = (1 - f) * (1 - f) * (1 - f) * (1.0f / 6.0f);
    w[1] = (3 * f3 - 6 * f2 + 4) * (1.0f / 6.0f);
    w[2] = (-3 * f3 + 3 * f2 + 3 * f + 1) * (1.0f / 6.0f);
    w[3] = f3 * (1.0f / 6.0f);
  };
  float ws[4], wt[4];
  weights(s - fs, ws);
  weights(t - ft, wt);
  int xs[4], ys[4];
  for (int k = 0; k < 4; ++k) {
    xs[k] = wrap_index(int(fs) - 1 + k, img.w, ext);
    ys[k] = wrap_index(int(ft) - 1 + k, img.h, ext);
  }
  float r[4] = {0, 0, 0, 0};
  for (int j = 0; j < 4; ++j) {
    if (ys[j] < 0) continue;  // Clip: transparent black outside
    for (int i = 0; i < 4; ++i) {
      if (xs[i] < 0) continue;
      const float *texel = &img.floats[(size_t(ys[j]) * img.w + xs[i]) * NC];
      float w = ws[i] * wt[j];
      for (int c = 0; c < NC; ++c) r[c] += w * texel[c];
    }
  }
  return finish(img, r, alpha, false);
}

Color bicubic_level0(const Image &img, float u, float v, TexExtension ext, float *alpha) {
  switch (img.channels) {
    case 1: return bicubic_level0<1>(img, u, v, ext, alpha);
    case 2: return bicubic_level0<2>(img, u, v, ext, alpha);
    case 3: return bicubic_level0<3>(img, u, v, ext, alpha);
    default: return bicubic_level0<4>(img, u, v, ext, alpha);
  }
}

// The MIP level of a footprint whose longer axis is sqrt(w2) texels wide (> 1): log2 of that,
// at most the coarsest level's.
float mip_level(const Image &img, float w2) {
  return std::min(0.5f * std::log2(w2), float(img.first_mip + int(img.mips.size()) - 1));
}

// Trilinear between the MIP levels around `level` (> 0); level 0 from finest(&alpha), which
// interpolates as asked. Where levels 1 .. first_mip - 1 are not kept (cached images), a
// blend of level 0 and first_mip by the level.
template <class Finest>
Color between_levels(const Image &img, float level, float u, float v, TexExtension ext, float *alpha, Finest finest) {
  const int l0 = level < float(img.first_mip) ? 0 : int(level);
  const int l1 = l0 == 0 ? img.first_mip : l0 + 1;
  const float t = l0 == 0 ? level / float(img.first_mip) : level - float(l0);
  Color c = l0 == 0 ? finest(alpha) : lookup_level(img, l0, u, v, false, ext, alpha);
  if (t > 0 && l1 < img.first_mip + int(img.mips.size())) {
    float a1;
    Color c1 = lookup_level(img, l1, u, v, false, ext, &a1);
    c = c * (1 - t) + c1 * t;
    *alpha = *alpha * (1 - t) + a1 * t;
  }
  return c;
}

// Trilinear MIP filtering over the footprint's longer axis (wider than a texel), else
// level 0 with the requested interpolation.
Color lookup_resident(const Image &img, float u, float v, TexInterp interp, TexExtension ext, float *alpha, Vec2 dx,
                      Vec2 dy) {
  bool closest = interp == TexInterp::Closest;
  float w2 = std::max(sqr(dx.x * img.w) + sqr(dx.y * img.h), sqr(dy.x * img.w) + sqr(dy.y * img.h));
  float a = 1;
  Color c;
  if (interp == TexInterp::Cubic && !(w2 > 1.0f)) {
    c = bicubic_level0(img, u, v, ext, &a);
  } else if (closest || !(w2 > 1.0f)) {
    c = lookup_level(img, 0, u, v, closest, ext, &a);
  } else {
    // Cubic (images without an OIIO handle) keeps its B-spline on the finest level.
    c = between_levels(img, mip_level(img, w2), u, v, ext, &a, [&](float *a0) {
      return interp == TexInterp::Cubic ? bicubic_level0(img, u, v, ext, a0) : lookup_level(img, 0, u, v, false, ext, a0);
    });
  }
  if (ext == TexExtension::Clip && (u < 0 || u > 1 || v < 0 || v > 1)) a = 0;
  if (alpha) *alpha = a;
  return c;
}

}  // namespace

Color ImageTextures::lookup(int id, float u, float v, TexInterp interp, TexExtension ext, float *alpha, Vec2 dx,
                            Vec2 dy) const {
  const Impl::Image &img = impl_->images[size_t(id)];
  if (img.resident && (interp != TexInterp::Cubic || !img.handle)) return lookup_resident(img, u, v, interp, ext, alpha, dx, dy);
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
  bool footprint = interp != TexInterp::Closest && (dx.x != 0 || dx.y != 0 || dy.x != 0 || dy.y != 0);
  // Without a footprint (or Closest): the finest level. With one: our own levels where the
  // image has them (a nonlinear colour space: resident images with Cubic, cached ones;
  // between_levels), else OIIO's anisotropic MIP filtering. OIIO's t runs down from the top
  // row; Blender's v runs up.
  float w2 = 0;  // the footprint's longer axis, squared, in texels (images with own levels)
  if (footprint && !img.mips.empty()) {
    w2 = std::max(sqr(dx.x * img.w) + sqr(dx.y * img.h), sqr(dy.x * img.w) + sqr(dy.y * img.h));
    footprint = false;
  }
  opt.mipmode = footprint ? TextureOpt::MipModeDefault : TextureOpt::MipModeNoMIP;
  if (!footprint) dx = dy = Vec2(0.0f, 0.0f);
  bool failed = false;
  auto finest = [&](float *a) {
    float r[4] = {0, 0, 0, 1};
    TextureSystem *ts = impl_->ts;
    if (!ts->texture(img.handle, ts->get_perthread_info(), opt, u, 1.0f - v, dx.x, -dx.y, dy.x, -dy.y, img.channels, r)) {
      (void)ts->geterror();
      failed = true;
      return Color(1, 0, 1);
    }
    return finish(img, r, a, false);
  };
  float a = 1;
  const Color c = w2 > 1 ? between_levels(img, mip_level(img, w2), u, v, ext, &a, finest) : finest(&a);
  if (failed) {
    if (alpha) *alpha = 1;
    return Color(1, 0, 1);
  }
  if (ext == TexExtension::Clip && (u < 0 || u > 1 || v < 0 || v > 1)) a = 0;
  if (alpha) *alpha = a;
  return c;
}

}  // namespace rdv
