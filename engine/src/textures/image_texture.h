// Image textures through OpenImageIO's TextureSystem: tiled, MIP-mapped, filtered
// lookups behind a cache of bounded size (untiled files are tiled and MIP-mapped on
// demand by OIIO's autotile / automip), with Blender's interpolation (Linear, Closest,
// Cubic; Smart = Cubic) and extension (Repeat, Extend, Clip, Mirror) modes. Texel values
// are converted to scene-linear Rec.709 with OpenColorIO using Blender's own config
// (sRGB, Non-Color, Linear, Filmic Log, ...). One process-wide TextureSystem: images
// used by several scenes are cached once.
//
// Lookups filter over the ray's footprint (dx, dy: its axes in texture space, from the
// shading point): wider than a texel, they blend MIP levels so far and grazing surfaces
// show the texture's average. Small images are MIP-mapped here, in scene-linear
// colour; larger ones by OIIO (filtered in the file's colour space, then converted).
// Closest interpolation is never filtered (as in Blender).
//
// Images from memory (a Blender image without a file: generated, painted, made by a
// script; a movie's frame) are resident floats filtered the same way; Cubic filters them
// here with the cubic B-spline OIIO and Cycles use.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include "core/math.h"

namespace rdv {

enum class TexInterp : uint8_t { Linear, Closest, Cubic };
enum class TexExtension : uint8_t { Repeat, Extend, Clip, Mirror };

class ImageTextures {
 public:
  static ImageTextures &instance();
  // Registers an image. Returns an id, or -1 with `problem` set when the file is
  // missing or unreadable. colorspace "" = Blender's default: sRGB for 8/16-bit
  // integer files, Linear for float (half / float EXR, HDR).
  int load(const std::string &path, const std::string &colorspace, std::string &problem);
  // One frame of a movie (or one subimage of a multi-image file), read by OpenImageIO
  // (FFmpeg for movies) and kept resident like an image from memory; frame 0 is the
  // first. -1 with `problem` set if it cannot be read.
  int load_frame(const std::string &path, int frame, const std::string &colorspace, std::string &problem);
  // Registers an image from memory (copied): width x height texels of `channels` floats
  // (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), bottom row first (Blender's image.pixels),
  // values in `colorspace` ("" = Linear), converted to scene-linear as a file's are.
  // Non-finite values are set to 0 (counted in *non_finite). Returns the id; `problem`
  // is set (a warning) for an unknown colour space, whose values are used as they are.
  // Free it with release(id) once nothing looks it up (MemoryImage does).
  int add_pixels(const float *pixels, int width, int height, int channels, const std::string &colorspace,
                 std::string &problem, size_t *non_finite = nullptr);
  void release(int id);
  // (u, v) in Blender's convention (v = 0 at the bottom row). Returns scene-linear RGB
  // and the alpha (1 for files without alpha). dx, dy: the footprint's axes in (u, v)
  // (zero: the finest level, unfiltered beyond the interpolation).
  Color lookup(int id, float u, float v, TexInterp interp, TexExtension ext, float *alpha,
               Vec2 dx = Vec2(0.0f, 0.0f), Vec2 dy = Vec2(0.0f, 0.0f)) const;
  void set_cache_megabytes(float mb);
  float cache_megabytes() const;
  // Bytes the tile cache holds now (never above the limit plus one tile per thread).
  size_t cache_memory_bytes() const;
  int num_images() const;
  // Bytes of small images kept decoded outside the cache (bounded at 128 MB in all).
  size_t resident_bytes() const;
  std::string stats() const;
  struct Impl;  // defined in image_texture.cpp

 private:
  ImageTextures();
  Impl *impl_;

};

// An image from memory owned by whatever holds this (the scene's buffer of that name,
// the materials whose texture nodes use it): released with the last holder.
struct MemoryImage {
  int id;
  int width, height, channels;
  MemoryImage(int i, int w, int h, int c) : id(i), width(w), height(h), channels(c) {}
  MemoryImage(const MemoryImage &) = delete;
  MemoryImage &operator=(const MemoryImage &) = delete;
  ~MemoryImage() { ImageTextures::instance().release(id); }
};

// Converts one colour from a named colour space of Blender's config to scene-linear.
// Returns false (and leaves c unchanged) if the space is unknown.
bool to_scene_linear(const std::string &colorspace, Color &c);

}  // namespace rdv
