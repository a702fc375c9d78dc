// Cryptomatte's pieces (film/cryptomatte.h): the name hashes and layer keys against the
// ones Cycles 3.4 wrote into a multilayer EXR of a small scene (objects Floor, Ball, Cube;
// material Red; Cycles' default_surface; view layer ViewLayer), ids that are always finite
// normal floats, a pixel's slots (adding by id, the overflow into the last slot, ranks read
// heaviest first over the sample count) and the settings' checks. Deterministic.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "film/cryptomatte.h"

namespace test_cryptomatte {

using namespace rdv;

namespace {
Cryptomatte layout_of(const nlohmann::json &j) { return Cryptomatte::parse(&j); }
}  // namespace

TEST(Cryptomatte, NameHashesMatchCyclesManifest) {
  // Cycles' manifests of that render: {"Floor":"6a2fb16e","Ball":"74d3ebe9","Cube":"a8fce865"},
  // {"default_surface":"78d05529", ..., "Red":"6e1a9181"}.
  EXPECT_EQ(cryptomatte::murmur_hash3("Floor"), 0x6a2fb16eu);
  EXPECT_EQ(cryptomatte::murmur_hash3("Ball"), 0x74d3ebe9u);
  EXPECT_EQ(cryptomatte::murmur_hash3("Cube"), 0xa8fce865u);
  EXPECT_EQ(cryptomatte::murmur_hash3("Red"), 0x6e1a9181u);
  EXPECT_EQ(cryptomatte::murmur_hash3("default_surface"), 0x78d05529u);
  EXPECT_EQ(cryptomatte::murmur_hash3("default_background"), 0xdba7ec85u);
  // Every tail length (0..3 bytes past the 4-byte blocks) and a name past ASCII (UTF-8 bytes).
  EXPECT_EQ(cryptomatte::murmur_hash3(""), 0u);
  EXPECT_NE(cryptomatte::murmur_hash3("Würfel"), cryptomatte::murmur_hash3("Wurfel"));
}

TEST(Cryptomatte, LayerKeysAndManifestsAsCyclesWritesThem) {
  const Cryptomatte c = layout_of({{"object", true}, {"material", true}, {"asset", true}, {"view_layer", "ViewLayer"}});
  CryptoManifests m;
  for (const char *name : {"Floor", "Ball", "Cube"}) m.add(Cryptomatte::Object, name);
  m.add(Cryptomatte::Material, "Red");
  const nlohmann::json meta = crypto_metadata(c, m);
  // Cycles: cryptomatte/542cafa (ViewLayer.CryptoObject), c7dbf5e (Material), aa21542 (Asset).
  EXPECT_EQ(meta.value("cryptomatte/542cafa/name", ""), "ViewLayer.CryptoObject");
  EXPECT_EQ(meta.value("cryptomatte/c7dbf5e/name", ""), "ViewLayer.CryptoMaterial");
  EXPECT_EQ(meta.value("cryptomatte/aa21542/name", ""), "ViewLayer.CryptoAsset");
  EXPECT_EQ(meta.value("cryptomatte/542cafa/hash", ""), "MurmurHash3_32");
  EXPECT_EQ(meta.value("cryptomatte/542cafa/conversion", ""), "uint32_to_float32");
  EXPECT_EQ(nlohmann::json::parse(meta.value("cryptomatte/542cafa/manifest", "{}")),
            (nlohmann::json{{"Floor", "6a2fb16e"}, {"Ball", "74d3ebe9"}, {"Cube", "a8fce865"}}));
  EXPECT_EQ(nlohmann::json::parse(meta.value("cryptomatte/c7dbf5e/manifest", "{}")), (nlohmann::json{{"Red", "6e1a9181"}}));
  EXPECT_EQ(meta.size(), 12u);  // 4 keys for each of the 3 layers
}

TEST(Cryptomatte, IdsAreFiniteNormalFloatsKeepingSignAndMantissa) {
  for (uint32_t hash : {0u, 0x007fffffu, 0x7f800000u, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0x6a2fb16eu}) {
    const float id = cryptomatte::id_of(hash);
    EXPECT_TRUE(std::isnormal(id)) << std::hex << hash;
    uint32_t bits;
    std::memcpy(&bits, &id, sizeof bits);
    EXPECT_EQ(bits & 0x807fffffu, hash & 0x807fffffu) << std::hex << hash;
    const uint32_t exponent = (hash >> 23) & 0xffu;
    if (exponent >= 1 && exponent <= 254) EXPECT_EQ(bits, hash);  // most hashes: the bits themselves
  }
}

TEST(Cryptomatte, LevelsRoundUpToWholePassesAndKindsTakeTheirSlots) {
  Cryptomatte c = layout_of({{"object", true}, {"asset", true}, {"levels", 5}});
  EXPECT_EQ(c.ranks, 6);  // Cycles: ceil(5 / 2) RGBA passes of two ranks
  EXPECT_EQ(c.passes_per_kind(), 3);
  EXPECT_EQ(c.slots_per_pixel(), 12);
  EXPECT_EQ(c.slot_offset(Cryptomatte::Object), 0);
  EXPECT_EQ(c.slot_offset(Cryptomatte::Material), -1);
  EXPECT_EQ(c.slot_offset(Cryptomatte::Asset), 6);
  EXPECT_EQ(layout_of({{"material", true}, {"levels", 1}}).ranks, 2);
  EXPECT_EQ(layout_of({{"material", true}}).ranks, 6);  // Blender's default of 6 levels
  EXPECT_TRUE(layout_of({{"levels", 6}}).empty());       // no kind: nothing kept
  EXPECT_TRUE(Cryptomatte::parse(nullptr).empty());
}

TEST(Cryptomatte, SlotsAddByIdOverflowIntoTheLastAndReadHeaviestFirst) {
  const Cryptomatte c = layout_of({{"object", true}, {"material", true}, {"levels", 2}});  // 2 slots per kind
  std::vector<CryptoSlot> pixel(size_t(c.slots_per_pixel()));
  auto add = [&](float object, float material, float weight) {
    CryptoSample s;
    s.start(&c);
    s.add(object, material, 9.0f, weight);
    add_crypto_sample(c, pixel.data(), s);
  };
  add(1.0f, 10.0f, 0.25f);
  add(2.0f, 10.0f, 1.0f);
  add(1.0f, 10.0f, 0.25f);
  add(3.0f, 20.0f, 0.5f);  // a third object: both object slots are taken, its weight goes to the last (2)
  add(4.0f, 20.0f, 0.0f);  // no weight: nothing written
  float out[4];
  read_crypto_pass(c, pixel.data(), Cryptomatte::Object, 0, 4.0, out);
  EXPECT_EQ(out[0], 2.0f);
  EXPECT_FLOAT_EQ(out[1], 1.5f / 4);  // its own 1 and the overflow's 0.5
  EXPECT_EQ(out[2], 1.0f);
  EXPECT_FLOAT_EQ(out[3], 0.5f / 4);
  read_crypto_pass(c, pixel.data(), Cryptomatte::Material, 0, 4.0, out);
  EXPECT_EQ(out[0], 10.0f);
  EXPECT_FLOAT_EQ(out[1], 1.5f / 4);
  EXPECT_EQ(out[2], 20.0f);
  EXPECT_FLOAT_EQ(out[3], 0.5f / 4);
  // The asset kind is not kept, a pass beyond the levels is empty, and so is a pixel without samples.
  for (auto [kind, k, n] : {std::tuple{Cryptomatte::Asset, 0, 4.0}, std::tuple{Cryptomatte::Object, 1, 4.0},
                            std::tuple{Cryptomatte::Object, 0, 0.0}}) {
    read_crypto_pass(c, pixel.data(), kind, k, n, out);
    for (float v : out) EXPECT_EQ(v, 0.0f);
  }
}

TEST(Cryptomatte, ASampleKeepsEachSurfaceOfALongChain) {
  const Cryptomatte c = layout_of({{"object", true}, {"levels", 16}});
  CryptoSample s;
  s.start(&c);
  for (int i = 0; i < CryptoSample::kMaxSurfaces + 4; ++i) s.add(float(i + 1), 1.0f, 1.0f, 0.5f);
  EXPECT_EQ(s.count, CryptoSample::kMaxSurfaces);
  double total = 0;
  for (int i = 0; i < s.count; ++i) total += s.surfaces[i].weight;
  EXPECT_DOUBLE_EQ(total, 0.5 * (CryptoSample::kMaxSurfaces + 4));  // the surfaces past the last share its entry
}

TEST(Cryptomatte, BadSettingsAreRefusedWithTheReason) {
  for (const nlohmann::json &j : {nlohmann::json(true), nlohmann::json{{"object", 1}}, nlohmann::json{{"levels", 0}},
                                  nlohmann::json{{"levels", 17}}, nlohmann::json{{"levels", 2.5}},
                                  nlohmann::json{{"objects", true}}, nlohmann::json{{"view_layer", 3}}}) {
    try {
      Cryptomatte::parse(&j);
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const Error &e) {
      EXPECT_NE(std::string(e.what()).find("'cryptomatte'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace test_cryptomatte
