// Cryptomatte (View Layer > Passes > Cryptomatte: Object, Material, Asset and Levels), as
// Cycles 3.4 writes it (kernel/film/cryptomatte_passes.h) and the Cryptomatte standard reads
// it (Friedman & Jones 2015): per pixel, the objects (materials, assets) the camera sees
// there, ranked by the share of the pixel each covers, so a compositor can cut any of them
// out with anti-aliased, motion-blurred and see-through edges.
//
// - An object's (material's, asset's) id is the MurmurHash3_32 of its name (seed 0) as a
//   float, its exponent kept within the finite normal numbers (Cycles' util_hash_to_float).
//   The asset is the object's topmost parent.
// - A camera sample writes at each surface of its see-through chain (film/data_passes.h)
//   the weight average(throughput) x (1 - average(transparency)), as Cycles: an opaque
//   surface seen straight takes the sample whole; a half-transparent card shares it with
//   what lies behind. The world writes nothing (its share is the pixel's 1 - alpha).
// - The pixel adds weights by id into 2 x ceil(levels / 2) slots per kind, in the order ids
//   arrive; once every slot is taken, a new id's weight goes to the last slot (Cycles' rule:
//   the coverages still sum to the pixel's). A read ranks the slots by weight and divides
//   by the pixel's samples: pass k of a kind holds ranks 2k and 2k + 1 as (id, coverage,
//   id, coverage), the layout of Blender's CryptoObject00, CryptoObject01, ...
#pragma once
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace rdv {

namespace cryptomatte {
// MurmurHash3's 32-bit hash (Austin Appleby's, public domain) of the name's bytes.
uint32_t murmur_hash3(std::string_view name, uint32_t seed = 0);
// The hash as the float a Cryptomatte pass stores: sign and mantissa kept, the exponent
// clamped to 1..254 (never 0, a denormal, infinity or NaN; 0 means "no id").
float id_of(uint32_t hash);
inline float id_of(std::string_view name) { return id_of(murmur_hash3(name)); }
}  // namespace cryptomatte

struct Cryptomatte {
  enum Kind : uint8_t { Object, Material, Asset };
  static constexpr int kKinds = 3, kMaxLevels = 16, kMaxPassesPerKind = kMaxLevels / 2;
  bool kinds[kKinds] = {false, false, false};
  int ranks = 0;      // slots per kind: 2 x its passes (0: no Cryptomatte)
  std::string layer;  // the layer names' prefix: "<view layer>." or "" (image_output.cpp, metadata)

  // From the render setting "cryptomatte": {"object": bool, "material": bool, "asset": bool,
  // "levels": 1..16 (default 6), "view_layer": name} (null: none). Malformed input throws.
  static Cryptomatte parse(const nlohmann::json *j);
  nlohmann::json to_json() const;  // parse's input again (render parts)
  bool empty() const { return ranks == 0; }
  int passes_per_kind() const { return ranks / 2; }
  int kind_count() const { return int(kinds[0]) + int(kinds[1]) + int(kinds[2]); }
  int slots_per_pixel() const { return empty() ? 0 : ranks * kind_count(); }
  // The kind's first slot in a pixel's slots (the enabled kinds in order), -1 if off.
  int slot_offset(Kind kind) const;
  // Blender's pass names: "CryptoObject", "CryptoMaterial", "CryptoAsset" (pass k: + "%02d").
  static const char *pass_prefix(Kind kind);
};

// One slot of a pixel: an id and the weight of the samples that saw it.
struct CryptoSlot {
  float id = 0, weight = 0;
};

// One camera sample's writes (DataPassSample::crypto): the see-through chain's surfaces.
struct CryptoSample {
  static constexpr int kMaxSurfaces = 16;  // beyond: added to the last (a chain that long is rare)
  struct Surface {
    float ids[Cryptomatte::kKinds];
    float weight;
  };
  const Cryptomatte *layout = nullptr;
  Surface surfaces[kMaxSurfaces];
  int count = 0;
  void start(const Cryptomatte *c) {
    layout = c && !c->empty() ? c : nullptr;
    count = 0;
  }
  bool active() const { return layout != nullptr; }
  void add(float object, float material, float asset, float weight);
};

// Adds a sample's writes to a pixel's slots (layout.slots_per_pixel() of them).
void add_crypto_sample(const Cryptomatte &layout, CryptoSlot *pixel, const CryptoSample &sample);
// Adds another pixel's slots (a render part's, film/render_part.h) to a pixel's, by id.
void add_crypto_slots(const Cryptomatte &layout, CryptoSlot *pixel, const CryptoSlot *other);
// Pass k of `kind` at a pixel into dst (4 floats): ranks 2k and 2k + 1 as (id, weight / n);
// zeros where the kind is off, the rank is empty or n is 0.
void read_crypto_pass(const Cryptomatte &layout, const CryptoSlot *pixel, Cryptomatte::Kind kind, int k, double n,
                      float *dst);

// The manifests (name -> 8 hex digits of its hash) of the names a scene gave each kind.
struct CryptoManifests {
  std::map<std::string, uint32_t> names[Cryptomatte::kKinds];
  void add(Cryptomatte::Kind kind, const std::string &name) { names[kind].emplace(name, cryptomatte::murmur_hash3(name)); }
};
// The Cryptomatte standard's metadata of the layers `layout` keeps, as Cycles writes it:
// "cryptomatte/<7 hex digits of the layer name's hash>/name" (the layer: layout.layer +
// pass_prefix), "/hash" MurmurHash3_32, "/conversion" uint32_to_float32, "/manifest" (JSON).
nlohmann::json crypto_metadata(const Cryptomatte &layout, const CryptoManifests &manifests);

}  // namespace rdv
