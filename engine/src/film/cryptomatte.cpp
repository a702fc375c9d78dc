#include "film/cryptomatte.h"
#include <algorithm>
#include <cstdio>
#include <cstring>
#include "core/error.h"

namespace rdv {

namespace cryptomatte {

uint32_t murmur_hash3(std::string_view name, uint32_t seed) {
  auto rotl = [](uint32_t x, int r) { return (x << r) | (x >> (32 - r)); };
  constexpr uint32_t c1 = 0xcc9e2d51u, c2 = 0x1b873593u;
  const auto *bytes = reinterpret_cast<const uint8_t *>(name.data());
  const size_t len = name.size(), blocks = len / 4;
  uint32_t h = seed;
  for (size_t i = 0; i < blocks; ++i) {  // little-endian 4-byte blocks
    uint32_t k = uint32_t(bytes[4 * i]) | uint32_t(bytes[4 * i + 1]) << 8 | uint32_t(bytes[4 * i + 2]) << 16 |
                 uint32_t(bytes[4 * i + 3]) << 24;
    k = rotl(k * c1, 15) * c2;
    h = rotl(h ^ k, 13) * 5 + 0xe6546b64u;
  }
  uint32_t k = 0;
  const uint8_t *tail = bytes + 4 * blocks;
  switch (len & 3) {
    case 3: k ^= uint32_t(tail[2]) << 16; [[fallthrough]];
    case 2: k ^= uint32_t(tail[1]) << 8; [[fallthrough]];
    case 1: k ^= tail[0]; h ^= rotl(k * c1, 15) * c2;
  }
  h ^= uint32_t(len);  // the finaliser: every input bit reaches every output bit
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

float id_of(uint32_t hash) {
  const uint32_t exponent = std::clamp((hash >> 23) & 0xffu, 1u, 254u);
  const uint32_t bits = (hash & 0x807fffffu) | exponent << 23;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace cryptomatte

Cryptomatte Cryptomatte::parse(const nlohmann::json *j) {
  Cryptomatte out;
  if (!j || j->is_null()) return out;
  const char *usage = "render settings: 'cryptomatte' must be {\"object\", \"material\", \"asset\": true or false, "
                      "\"levels\": 1 to 16, \"view_layer\": a name}";
  if (!j->is_object()) fail(usage, RDV_ERROR_INVALID_ARGUMENT);
  static const char *kKeys[kKinds] = {"object", "material", "asset"};
  for (auto it = j->begin(); it != j->end(); ++it) {
    const std::string &key = it.key();
    const bool kind = std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char *k) { return key == k; }) !=
                      std::end(kKeys);
    if (kind ? !it->is_boolean()
             : key == "levels" ? !it->is_number_integer() || it->get<int64_t>() < 1 || it->get<int64_t>() > kMaxLevels
                               : key != "view_layer" || !it->is_string())
      fail(std::string(usage) + ", got '" + key + "': " + it->dump(), RDV_ERROR_INVALID_ARGUMENT);
  }
  for (int k = 0; k < kKinds; ++k) out.kinds[k] = j->value(kKeys[k], false);
  const int levels = j->value("levels", 6);  // Blender's default
  out.ranks = out.kind_count() ? 2 * ((levels + 1) / 2) : 0;  // Cycles: whole RGBA passes
  const std::string view_layer = j->value("view_layer", std::string());
  out.layer = view_layer.empty() ? "" : view_layer + ".";
  return out;
}

nlohmann::json Cryptomatte::to_json() const {
  if (empty()) return nullptr;
  nlohmann::json j = {{"object", kinds[Object]}, {"material", kinds[Material]}, {"asset", kinds[Asset]}, {"levels", ranks}};
  if (!layer.empty()) j["view_layer"] = layer.substr(0, layer.size() - 1);
  return j;
}

int Cryptomatte::slot_offset(Kind kind) const {
  if (!kinds[kind]) return -1;
  int offset = 0;
  for (int k = 0; k < kind; ++k) offset += kinds[k] ? ranks : 0;
  return offset;
}

const char *Cryptomatte::pass_prefix(Kind kind) {
  static const char *kNames[kKinds] = {"CryptoObject", "CryptoMaterial", "CryptoAsset"};
  return kNames[kind];
}

void CryptoSample::add(float object, float material, float asset, float weight) {
  if (!(weight > 0)) return;
  if (count == kMaxSurfaces) {
    surfaces[count - 1].weight += weight;
    return;
  }
  surfaces[count++] = {{object, material, asset}, weight};
}

// A weight for `id` into a kind's `ranks` slots: the id's slot, else the first free one,
// else the last (Cycles' rule).
static void add_to_slots(CryptoSlot *slots, int ranks, float id, float weight) {
  for (int i = 0; i < ranks; ++i) {
    if (slots[i].weight == 0 && slots[i].id == 0) slots[i].id = id;  // a free slot: the id's
    if (slots[i].id == id || i == ranks - 1) {
      slots[i].weight += weight;
      return;
    }
  }
}

void add_crypto_sample(const Cryptomatte &layout, CryptoSlot *pixel, const CryptoSample &sample) {
  for (int kind = 0; kind < Cryptomatte::kKinds; ++kind) {
    const int offset = layout.slot_offset(Cryptomatte::Kind(kind));
    if (offset < 0) continue;
    for (int s = 0; s < sample.count; ++s)
      add_to_slots(pixel + offset, layout.ranks, sample.surfaces[s].ids[kind], sample.surfaces[s].weight);
  }
}

void add_crypto_slots(const Cryptomatte &layout, CryptoSlot *pixel, const CryptoSlot *other) {
  for (int s = 0; s < layout.slots_per_pixel(); ++s) {
    if (!(other[s].weight > 0)) continue;
    const int kind_start = s - s % layout.ranks;  // the kinds' slots lie one after the other
    add_to_slots(pixel + kind_start, layout.ranks, other[s].id, other[s].weight);
  }
}

void read_crypto_pass(const Cryptomatte &layout, const CryptoSlot *pixel, Cryptomatte::Kind kind, int k, double n,
                      float *dst) {
  std::fill_n(dst, 4, 0.0f);
  const int offset = layout.slot_offset(kind);
  if (offset < 0 || k < 0 || k >= layout.passes_per_kind() || !(n > 0)) return;
  CryptoSlot ranked[2 * Cryptomatte::kMaxPassesPerKind];
  std::copy_n(pixel + offset, layout.ranks, ranked);
  // Heaviest first; equal weights by id, so the order does not depend on arrival.
  std::sort(ranked, ranked + layout.ranks, [](const CryptoSlot &a, const CryptoSlot &b) {
    return a.weight != b.weight ? a.weight > b.weight : a.id < b.id;
  });
  for (int r = 0; r < 2; ++r) {
    const CryptoSlot &s = ranked[2 * k + r];
    if (s.weight > 0) {
      dst[2 * r] = s.id;
      dst[2 * r + 1] = float(s.weight / n);
    }
  }
}

nlohmann::json crypto_metadata(const Cryptomatte &layout, const CryptoManifests &manifests) {
  nlohmann::json out = nlohmann::json::object();
  for (int kind = 0; kind < Cryptomatte::kKinds; ++kind) {
    if (!layout.kinds[kind]) continue;
    const std::string name = layout.layer + Cryptomatte::pass_prefix(Cryptomatte::Kind(kind));
    char key[32];  // the layer's key: the first 7 hex digits of its name's hash
    std::snprintf(key, sizeof key, "cryptomatte/%07x/", cryptomatte::murmur_hash3(name) >> 4);
    const std::string prefix = key;
    nlohmann::json manifest = nlohmann::json::object();
    for (const auto &[object, hash] : manifests.names[kind]) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "%08x", hash);
      manifest[object] = hex;
    }
    out[prefix + "name"] = name;
    out[prefix + "hash"] = "MurmurHash3_32";
    out[prefix + "conversion"] = "uint32_to_float32";
    out[prefix + "manifest"] = manifest.dump();
  }
  return out;
}

}  // namespace rdv
