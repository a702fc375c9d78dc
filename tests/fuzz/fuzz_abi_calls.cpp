// libFuzzer target: sequences of C ABI calls, as a host (Blender's viewport, a
// script) might make them: scene edits, commits, tiny renders started, cancelled,
// waited for and read while they run, in the order the input decodes to. The first
// byte picks a starting scene from scenes/ (the seed corpus); the rest are calls whose
// arguments (ids, counts, floats including NaN / Inf, parameter JSON) come from the
// input. Findings beyond ASan / UBSan: fuzz_checks.h.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>
#include "fuzz_checks.h"
#include "scene_file.h"

namespace {

using rdv_fuzz::checked;

// The input, read front to back; past its end every read gives zeros.
struct Reader {
  const uint8_t *data;
  size_t size, at = 0;
  bool done() const { return at >= size; }
  uint8_t byte() { return at < size ? data[at++] : 0; }
  uint32_t small(uint32_t n) { return n ? byte() % n : 0; }  // 0..n-1
  // Mostly values a scene holds, sometimes the extremes a hostile one holds.
  float number() {
    static const float kValues[] = {0.0f, 1.0f, 0.5f, 2.0f, -1.0f, 0.25f, 10.0f, 1e-4f, 1e5f, -0.0f, 1e-30f,
                                    1e30f, 3.0e38f, NAN, INFINITY, -INFINITY, 4.0f, 0.999f, 1000.0f, -1e5f};
    uint8_t b = byte();
    if (b < 200) return kValues[b % (sizeof kValues / sizeof kValues[0])];
    uint32_t bits = uint32_t(byte()) | uint32_t(byte()) << 8 | uint32_t(byte()) << 16 | uint32_t(byte()) << 24;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
  std::vector<float> numbers(size_t n) {
    std::vector<float> v(n);
    for (float &f : v) f = number();
    return v;
  }
  std::string text(size_t most) {
    size_t n = std::min<size_t>(small(uint32_t(most) + 1), size - std::min(at, size));
    std::string s(reinterpret_cast<const char *>(data + at), n);
    at += n;
    return s;
  }
  // A JSON number for a parameter template: JSON has no NaN / Inf, so those become null.
  std::string json_number() {
    float f = number();
    if (!std::isfinite(f)) return "null";
    char s[32];
    std::snprintf(s, sizeof s, "%.9g", f);
    return s;
  }
};

const char *kNames[] = {"A", "B", "C", ""};

// A parameter string, printed when tracing (RDV_FUZZ_TRACE); valid for the call it is passed to.
const char *traced(const std::string &params) {
  if (rdv_fuzz::tracing()) std::fprintf(stderr, "   params %s\n", params.c_str());
  return params.c_str();
}
const char *kColorSpaces[] = {"", "Non-Color", "sRGB", "Linear", "no such space"};

// A Light Falloff node (emission by the distance its light travels), its output and numbers
// from the input.
std::string light_falloff(Reader &in) {
  static const char *kOutputs[] = {"QUADRATIC", "LINEAR", "CONSTANT"};
  return std::string(R"({"node":"light_falloff","output":")") + kOutputs[in.small(3)] + R"(","strength":)" +
         in.json_number() + R"(,"smooth":)" + in.json_number() + "}";
}

// Parameter JSON for a material / light / world / camera / session: a template with
// numbers from the input, or (choice 0) raw input text.
std::string material_params(Reader &in) {
  auto x = [&] { return in.json_number(); };
  switch (in.small(24)) {  // 23: the default
    case 0: return in.text(64);
    case 21: return std::string(R"({"type":"mix","fac":)") + x() + R"(,"shader1":{"type":"transparent"},)" +
                    R"("shader2":{"type":"diffuse"},"aovs":{")" + kNames[in.small(4)] + R"(":{"color":{"node":"noise","scale":)" +
                    x() + R"(},"value":)" + x() + R"(},"B":{"value":{"node":"texture_coordinate","output":"position"}}}})";
    case 22: return std::string(R"({"type":"diffuse","color":{"node":"attribute","attribute_type":")") +
                    (in.small(2) ? "OBJECT" : "INSTANCER") + R"(","name":")" + kNames[in.small(3)] + R"(","output":")" +
                    (in.small(2) ? "fac" : "color") + R"("}})";
    case 1: return R"({"type":"diffuse","color":[)" + x() + "," + x() + "," + x() + R"(],"roughness":)" + x() + "}";
    case 2: return R"({"type":"glossy","roughness":)" + x() + R"(,"anisotropy":)" + x() + "}";
    case 3: return R"({"type":"glass","ior":)" + x() + R"(,"roughness":)" + x() + "}";
    case 4: return R"({"type":"principled","metallic":)" + x() + R"(,"transmission":)" + x() + R"(,"clearcoat":)" +
                   x() + R"(,"sheen":)" + x() + "}";
    case 5: return R"({"type":"emission","color":[1,0.5,0.2],"strength":)" + (in.small(2) ? light_falloff(in) : x()) + "}";
    case 6: return R"({"type":"mix","fac":)" + x() + R"(,"shader1":{"type":"diffuse"},"shader2":{"type":"glass"}})";
    case 7: return R"({"type":"volume","volume":{"density":)" + x() + R"(,"anisotropy":)" + x() + "}}";
    case 8: return R"({"type":"diffuse","volume":{"sigma_a":[)" + x() + ",0,0],\"sigma_s\":[1,1," + x() +
                   R"(],"emission_strength":)" + x() + "}}";
    case 9: return R"({"type":"diffuse","color":{"node":"image","buffer":")" + std::string(kNames[in.small(4)]) +
                   R"(","interpolation":")" + (in.small(2) ? "Closest" : "Cubic") + R"("}})";
    case 10: return R"({"type":"principled","normal":{"node":"bump","height":{"node":"checker","scale":)" + x() +
                    R"(},"strength":)" + x() + "}}";
    case 11: return R"({"type":"diffuse","color":{"node":"math","operation":"DIVIDE","value1":)" + x() +
                    R"(,"value2":)" + x() + "}}";
    case 12: return R"({"type":"transparent","color":[)" + x() + ",1,1]}";
    case 13: {  // Blender's procedural textures, each of its numeric inputs from the input
      struct Texture { const char *node; std::vector<const char *> keys; };
      static const Texture kTextures[] = {
          {"voronoi", {"scale", "w", "smoothness", "exponent", "randomness"}},
          {"musgrave", {"scale", "w", "detail", "dimension", "lacunarity", "offset", "gain"}},
          {"wave", {"scale", "distortion", "detail", "detail_scale", "detail_roughness", "phase"}},
          {"magic", {"scale", "distortion"}},
          {"brick", {"scale", "mortar_size", "mortar_smooth", "bias", "brick_width", "row_height", "squash"}},
          {"white_noise", {"w"}}};
      const Texture &t = kTextures[in.small(6)];
      std::string s = std::string(R"({"type":"diffuse","color":{"node":")") + t.node + R"(")";
      for (const char *key : t.keys) s += std::string(",\"") + key + "\":" + x();
      return s + "}}";
    }
    case 14: {  // a Mix Shader by the viewing direction, its parameter and table from the input
      static const char *kViews[] = {R"({"node":"fresnel","ior":)", R"({"node":"layer_weight","blend":)",
                                     R"({"node":"layer_weight","output":"facing","blend":)", R"({"node":"backfacing","table":[0,)"};
      const int v = in.small(4);
      std::string fac = std::string(kViews[v]) + x() + (v == 3 ? "]}" : R"(,"table":[)" + x() + "," + x() + "]}");
      return R"({"type":"mix","fac":)" + fac + R"(,"shader1":{"type":"transparent"},"shader2":{"type":"mix","fac":)" + fac +
             R"(,"shader1":{"type":"diffuse"},"shader2":{"type":"glossy","roughness":)" + x() + "}}}";
    }
    case 15: return R"({"type":"emission","color":{"node":"wavelength","wavelength":)" + x() +
                    R"(},"strength":{"node":"camera_data","output":")" + std::string(in.small(2) ? "view_z_depth" : "view_distance") +
                    R"("}})";
    case 17: return R"({"type":"diffuse","color":{"node":"ambient_occlusion","distance":)" + x() + R"(,"samples":)" + x() +
                    R"(,"only_local":)" + (in.small(2) ? "true" : "false") + R"(,"inside":)" +
                    (in.small(2) ? "true" : "false") + "}}";
    case 18: return R"({"type":"glossy","roughness":)" + x() + R"(,"normal":{"node":"bevel","radius":)" + x() +
                    R"(,"samples":)" + x() + R"(,"normal":{"node":"normal_map","strength":)" + x() + "}}}";
    case 19: {  // a displacement's bump as the surface normal (the add-on's Bump Only), a bump on top
      const std::string disp = std::string(R"({"node":"displacement","space":")") + (in.small(2) ? "OBJECT" : "WORLD") +
                               R"(","height":{"node":"noise","scale":)" + x() + R"(},"midlevel":)" + x() +
                               R"(,"scale":)" + x() + "}";
      return R"({"type":"principled","surface_normal":{"node":"bump","height":{"node":"vector_math","operation":)"
             R"("DOT_PRODUCT","output":"value","vector1":)" + disp +
             R"(,"vector2":{"node":"texture_coordinate","output":"normal"}}},"normal":{"node":"bump","strength":)" + x() +
             R"(,"height":{"node":"checker","scale":)" + x() + "}}}";
    }
    case 20:  // true displacement: the vertices moved by a noise, normals rebuilt or kept
      return R"({"type":"diffuse","displacement_method":")" + std::string(in.small(2) ? "true" : "both") +
             R"(","displacement":{"node":"displacement","space":"OBJECT","height":{"node":"noise","scale":)" + x() +
             R"(},"scale":)" + x() + "}}";
    case 16: return R"({"type":"emission","color":{"node":"texture_coordinate","output":"parametric"},"strength":)"
                    R"({"node":"wireframe","size":)" + x() + R"(,"pixel_size":)" + (in.small(2) ? "true" : "false") + "}}";
    default: return R"({"type":"volume","volume":{"grid":{"buffer":")" + std::string(kNames[in.small(4)]) +
                    R"(","bounds":[[-1,-1,-1],[1,1,1]]},"density":)" + x() + "}}";
  }
}

// An IES profile's text: a well-formed header with counts, type and angles from the input (so
// the mirroring and interpolation see odd tables), or printable bytes after a TILT line.
std::string ies_profile_text(Reader &in) {
  std::string s = "IESNA:LM-63-2002\nTILT=NONE\n";
  if (in.small(4) == 0) {
    for (char c : in.text(200)) s += (c >= 32 && c < 127) || c == '\n' ? c : ' ';
    return s;
  }
  const int nv = 1 + int(in.small(8)), nh = 1 + int(in.small(6));
  s += "1 -1 " + in.json_number() + " " + std::to_string(nv) + " " + std::to_string(nh) + " " + std::to_string(1 + in.small(3)) +
       " 2 0 0 0\n1 1 100\n";
  static const float kV[] = {0, 90, 180, -90}, kH[] = {0, 90, 180, 270, 360, -90};
  float v = kV[in.small(4)], h = kH[in.small(6)];
  for (int i = 0; i < nv; ++i, v += float(in.small(46))) s += std::to_string(v) + " ";
  for (int i = 0; i < nh; ++i, h += float(in.small(91))) s += std::to_string(h) + " ";
  for (int i = 0; i < nv * nh; ++i) s += in.json_number() + " ";
  return s + "\n";
}

std::string light_params(Reader &in) {
  auto x = [&] { return in.json_number(); };
  switch (in.small(7)) {
    case 0: return in.text(64);
    case 6: {  // a lamp shaped by an IES profile, turned by a Mapping of its normal
      const nlohmann::json ies = {{"node", "ies"}, {"profile", ies_profile_text(in)}, {"strength", in.number()},
                                  {"vector", {{"node", "mapping"}, {"rotation", {in.number(), 0.3, 0}},
                                              {"vector", {{"node", "texture_coordinate"}, {"output", "object_normal"}}}}}};
      return R"({"type":")" + std::string(in.small(2) ? "point" : "spot") + R"(","position":[0,0,1.5],"radius":)" + x() +
             R"(,"emission":{"strength":)" + ies.dump() + "}}";
    }
    case 1: return R"({"type":"point","position":[0,0,)" + x() + R"(],"power":)" + x() + R"(,"radius":)" + x() +
                   R"(,"emission":{"color":{"node":"blackbody","temperature":)" + x() + R"(},"strength":)" +
                   (in.small(2) ? light_falloff(in) : x()) + "}}";
    case 2: return R"({"type":"spot","position":[0,-2,1],"direction":[0,1,)" + x() + R"(],"power":)" + x() +
                   R"(,"spot_size":)" + x() + R"(,"spot_blend":)" + x() + R"(,"max_bounces":)" + x() + "}";
    case 3: return R"({"type":"sun","direction":[)" + x() + R"(,0,-1],"strength":)" + x() + R"(,"angle":)" + x() + "}";
    case 4: return R"({"type":"area","position":[0,0,1.9],"direction":[0,0,-1],"shape":"disk","power":)" + x() +
                   R"(,"size":)" + x() + "}";
    default: {  // with a tree that varies over the lamp: a checker of its Parametric, a noise of the position
      std::string emission;
      if (in.small(2))
        emission = R"(,"emission":{"color":{"node":"checker","scale":)" + x() +
                   R"(,"vector":{"node":"texture_coordinate","output":"parametric"}},"strength":{"node":"noise","scale":)" +
                   x() + R"(,"vector":{"node":"texture_coordinate","output":"position"}}})";
      return R"({"type":"area","position":[0,0,1.9],"shape":"rectangle","size":)" + x() + R"(,"size_y":)" + x() +
             R"(,"visible_camera":true)" + emission + "}";
    }
  }
}

std::string world_params(Reader &in) {
  auto x = [&] { return in.json_number(); };
  switch (in.small(6)) {
    case 0: return in.text(64);
    case 1:  // with the World's AOV Outputs (shader AOVs A and B): a texture of the direction, a number
      return R"({"color":[)" + x() + ",0.1,0.1],\"strength\":" + x() + R"(,"aovs":{")" + kNames[in.small(4)] +
             R"(":{"color":{"node":"noise","scale":)" + x() + R"(,"vector":{"node":"texture_coordinate"}},"value":)" +
             x() + "}}}";
    case 5: return R"({"color":[0.5,0.5,0.5],"camera":{"color":[)" + x() + R"(,0.2,0.9],"strength":)" + x() +
                   R"(},"visibility":{"camera":)" + (in.small(2) ? "true" : "false") + "}}";
    case 2: return R"({"color":[0,0,0],"volume":{"density":)" + x() + R"(,"anisotropy":)" + x() + "}}";
    case 3:
      if (in.small(2))
        return R"({"sky":{"type":"preetham","sun_direction":[)" + x() + "," + x() + R"(,1],"turbidity":)" + x() +
               R"(},"strength":)" + x() + "}";
      return R"({"sky":{"sun_elevation":)" + x() + R"(,"altitude":)" + x() + R"(,"air_density":)" + x() +
             R"(,"sun_size":)" + x() + R"(},"strength":)" + x() + "}";
    default: return R"({"environment":{"file":"textures/does_not_exist.exr"},"strength":)" + x() + "}";
  }
}

std::string camera_params(Reader &in) {
  auto x = [&] { return in.json_number(); };
  switch (in.small(4)) {
    case 0: return in.text(64);
    case 1: return R"({"type":"perspective","focal_length":)" + x() + R"(,"clip_start":)" + x() +
                   R"(,"transform":{"look_at":{"from":[0,-3.9,1],"to":[0,0,)" + x() + "]}}}";
    case 2: return R"({"type":"orthographic","ortho_scale":)" + x() + R"(,"shift_x":)" + x() +
                   R"(,"transform":{"look_at":{"from":[0,-3.9,1],"to":[0,0,1]}}})";
    default: return R"({"type":"perspective","fstop":)" + x() + R"(,"focus_distance":)" + x() + R"(,"blades":)" +
                    std::to_string(in.small(9)) + R"(,"transform":{"look_at":{"from":[0,-3.9,1],"to":[0,0,1]}}})";
  }
}

// from_text: the settings are raw input text (any size and sample count).
std::string session_settings(Reader &in, bool &from_text) {
  from_text = in.small(16) == 0;
  if (from_text) return in.text(64);
  static const char *kIntegrators[] = {"path", "bdpt", "pssmlt", "mmlt", "mlt", "auto"};
  std::string s = "{\"width\":" + std::to_string(1 + in.small(12)) + ",\"height\":" + std::to_string(1 + in.small(12)) +
                  ",\"integrator\":\"" + kIntegrators[in.small(6)] + "\",\"samples\":" + std::to_string(1 + in.small(3)) +
                  ",\"max_bounces\":" + std::to_string(in.small(9)) + ",\"seed\":" + std::to_string(in.byte()) +
                  ",\"threads\":" + std::to_string(1 + in.small(2)) + ",\"mlt_bootstrap\":" +
                  std::to_string(1 + in.small(64)) + ",\"mlt_chains\":" + std::to_string(1 + in.small(4));
  switch (in.small(9)) {
    case 1: s += ",\"noise_target\":" + in.json_number(); break;
    case 2: s += ",\"adaptive_sampling\":true,\"adaptive_threshold\":" + in.json_number(); break;
    case 3: s += ",\"border\":[" + in.json_number() + "," + in.json_number() + ",1,1]"; break;
    case 4: s += ",\"sample_offset\":" + std::to_string(in.small(5)); break;
    case 5: s += ",\"clamp\":" + in.json_number() + ",\"diffuse_bounces\":" + std::to_string(in.small(3)); break;
    case 6: s += ",\"noise_pass\":true"; break;
    case 7:  // shader AOVs: names the materials' "aovs" write (A, B) and one none writes
      s += std::string(",\"aovs\":[{\"name\":\"A\",\"type\":\"") + (in.small(2) ? "color" : "value") +
           "\"},{\"name\":\"C\"},{\"name\":\"B\",\"type\":\"" + (in.small(2) ? "color" : "value") + "\"}]";
      break;
    case 8:  // Cryptomatte: some kinds, any levels (out of range: refused)
      s += std::string(",\"cryptomatte\":{\"object\":") + (in.small(2) ? "true" : "false") +
           ",\"material\":" + (in.small(2) ? "true" : "false") + ",\"asset\":true,\"levels\":" +
           std::to_string(int(in.small(18)) - 1) + "}";
      break;
    default: break;
  }
  return s + "}";
}

// Starting scenes: the small files of scenes/ (a few KB, so each input loads one fast).
const std::vector<std::string> &start_scenes() {
  static const std::vector<std::string> texts = [] {
    std::vector<std::string> t;
    for (const char *name : {"cornell_box", "light_types", "caustic", "fog_spot", "furnace_sphere", "glass_sphere",
                             "volume_caustic", "mirror_caustic", "materials", "door_gap"}) {
      std::ifstream f(std::string(RDV_SOURCE_DIR "/scenes/") + name + ".json");
      std::stringstream ss;
      ss << f.rdbuf();
      t.push_back(ss.str());
    }
    return t;
  }();
  return texts;
}

struct State {
  rdv_scene *scene = nullptr;
  rdv_session *session = nullptr;
  uint32_t materials = 0, meshes = 0, lights = 0, instances = 0;
  uint32_t film_width = 0, film_height = 0;
  bool open_ended = false;  // settings from raw input text: may render for long, so cancelled before a wait
  bool session_on_scene = false;  // the session renders `scene` (not one destroyed since)

  uint32_t some(Reader &in, uint32_t count) { return in.small(count + 2); }  // sometimes past the end

  void end_session() {
    if (!session) return;
    checked(rdv_session_cancel(session), "rdv_session_cancel");
    rdv_session_wait(session);  // a render that failed reports it here; any status but internal
    checked(rdv_session_destroy(session), "rdv_session_destroy");
    session = nullptr;
  }

  void mesh_call(Reader &in, bool replace) {
    uint32_t nv = in.small(10), nt = in.small(7);
    std::vector<float> positions = in.numbers(size_t(nv) * 3);
    std::vector<float> normals = in.small(2) ? in.numbers(size_t(nv) * 3) : std::vector<float>();
    std::vector<float> uvs = in.small(2) ? in.numbers(size_t(nv) * 2) : std::vector<float>();
    std::vector<uint32_t> indices(size_t(nt) * 3), ids;
    for (uint32_t &i : indices) i = in.small(nv + 1);
    if (in.small(2)) {
      ids.resize(nt);
      for (uint32_t &i : ids) i = some(in, materials);
    }
    const float *n = normals.empty() ? nullptr : normals.data(), *uv = uvs.empty() ? nullptr : uvs.data();
    const uint32_t *m = ids.empty() ? nullptr : ids.data();
    if (replace) {
      checked(rdv_scene_set_mesh(scene, some(in, meshes), positions.data(), nv, n, uv, indices.data(), nt, m,
                                 some(in, materials)),
              "rdv_scene_set_mesh");
    } else {
      uint32_t id;
      if (checked(rdv_scene_add_mesh(scene, kNames[in.small(4)], positions.data(), nv, n, uv, indices.data(), nt, m,
                                     some(in, materials), &id),
                  "rdv_scene_add_mesh") == RDV_OK)
        meshes = std::max(meshes, id + 1);
    }
  }

  void transform_call(Reader &in, bool replace) {
    float t[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (uint32_t k = in.small(4); k > 0; --k) t[in.small(16)] = in.number();
    if (rdv_fuzz::tracing())
      for (int r = 0; r < 4; ++r) std::fprintf(stderr, "   transform %g %g %g %g\n", t[4 * r], t[4 * r + 1], t[4 * r + 2], t[4 * r + 3]);
    if (replace) {
      checked(rdv_scene_set_instance_transform(scene, some(in, instances), t), "rdv_scene_set_instance_transform");
    } else {
      uint32_t id;
      if (checked(rdv_scene_add_instance(scene, some(in, meshes), t, &id), "rdv_scene_add_instance") == RDV_OK)
        instances = std::max(instances, id + 1);
    }
  }

  void read_film(Reader &in) {
    static const int kMorePasses[] = {RDV_PASS_AOV_COLOR_FIRST,       RDV_PASS_AOV_COLOR_FIRST + 2, RDV_PASS_AOV_VALUE_FIRST,
                                      RDV_PASS_AOV_VALUE_FIRST + 2,   RDV_PASS_CRYPTOMATTE_FIRST,   RDV_PASS_CRYPTOMATTE_FIRST + 9,
                                      RDV_PASS_CRYPTOMATTE_LAST};
    const uint32_t pick = in.small(13);  // 5: not a pass; 6..9 shader AOVs; 10..12 Cryptomatte
    rdv_pass pass = rdv_pass(pick < 6 ? int(pick) : kMorePasses[pick - 6]);
    uint32_t x = in.small(film_width + 2), y = in.small(film_height + 2);
    uint32_t w = in.small(film_width + 2), h = in.small(film_height + 2);
    int channels = std::max(rdv_pass_channels(pass), 1);
    std::vector<float> out(size_t(w) * h * channels + 1);
    if (checked(rdv_session_read_film(session, pass, x, y, w, h, in.small(2), out.data()), "rdv_session_read_film") ==
        RDV_OK)
      rdv_fuzz::check_finite(out.data(), size_t(w) * h * channels, "rdv_session_read_film");
  }

  void step(Reader &in) {
    uint32_t id;
    if (rdv_fuzz::tracing()) std::fprintf(stderr, "-- byte %zu\n", in.at);
    switch (in.small(27)) {
      case 0:
        if (checked(rdv_scene_add_material(scene, kNames[in.small(4)], traced(material_params(in)), &id),
                    "rdv_scene_add_material") == RDV_OK)
          materials = std::max(materials, id + 1);
        break;
      case 1:
        checked(rdv_scene_set_material(scene, some(in, materials), traced(material_params(in))),
                "rdv_scene_set_material");
        break;
      case 2: mesh_call(in, false); break;
      case 3: mesh_call(in, true); break;
      case 4: {
        static const char *kKinds[] = {"uv", "color", "normal"};
        uint32_t components = in.small(5), vertices = in.small(10);
        std::vector<float> data = in.numbers(size_t(components) * vertices);
        checked(rdv_scene_add_mesh_attribute(scene, some(in, meshes), kNames[in.small(4)], kKinds[in.small(3)],
                                             data.data(), components, vertices),
                "rdv_scene_add_mesh_attribute");
        break;
      }
      case 5: transform_call(in, false); break;
      case 6: transform_call(in, true); break;
      case 7:
        if (checked(rdv_scene_add_light(scene, kNames[in.small(4)], traced(light_params(in)), &id),
                    "rdv_scene_add_light") == RDV_OK)
          lights = std::max(lights, id + 1);
        break;
      case 8: checked(rdv_scene_set_light(scene, some(in, lights), traced(light_params(in))), "rdv_scene_set_light"); break;
      case 9: checked(rdv_scene_set_world(scene, traced(world_params(in))), "rdv_scene_set_world"); break;
      case 10: checked(rdv_scene_set_camera(scene, traced(camera_params(in))), "rdv_scene_set_camera"); break;
      case 11: {
        uint32_t nx = in.small(5), ny = in.small(5), nz = in.small(5);
        std::vector<float> values = in.numbers(size_t(nx) * ny * nz);
        checked(rdv_scene_add_grid(scene, kNames[in.small(4)], values.data(), nx, ny, nz, nullptr), "rdv_scene_add_grid");
        break;
      }
      case 12: {
        uint32_t w = in.small(5), h = in.small(5), c = in.small(6);
        std::vector<float> pixels = in.numbers(size_t(w) * h * c);
        checked(rdv_scene_add_image(scene, kNames[in.small(4)], pixels.data(), w, h, c, kColorSpaces[in.small(5)],
                                    nullptr),
                "rdv_scene_add_image");
        break;
      }
      case 13: checked(rdv_scene_commit(scene), "rdv_scene_commit"); break;
      case 14: {
        const char *text = nullptr;
        checked(rdv_scene_messages(scene, &text), "rdv_scene_messages");
        checked(rdv_scene_summary(scene, &text), "rdv_scene_summary");
        break;
      }
      case 15: case 16: {  // a second session on the scene that has one is refused (RDV_ERROR_STATE)
        rdv_session *created = nullptr;
        bool from_text = false;
        std::string settings = session_settings(in, from_text);
        if (checked(rdv_session_create(scene, traced(settings), &created), "rdv_session_create") != RDV_OK) break;
        if (session && session_on_scene) rdv_fuzz::finding("a second session was created on a scene that has one");
        end_session();  // the one on a scene destroyed since
        session = created;
        session_on_scene = true;
        open_ended = from_text;
        rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, 0, 0, 1, nullptr);  // NULL out: refused
        film_width = 0;
        film_height = 0;
        // The film's size: the largest rectangle a read accepts, found by reading 1 pixel.
        float pixel[4];
        while (film_width < 64 &&
               rdv_session_read_film(session, RDV_PASS_COMBINED, film_width, 0, 1, 1, 1, pixel) == RDV_OK)
          ++film_width;
        while (film_height < 64 &&
               rdv_session_read_film(session, RDV_PASS_COMBINED, 0, film_height, 1, 1, 1, pixel) == RDV_OK)
          ++film_height;
        break;
      }
      case 17: if (session) checked(rdv_session_start(session), "rdv_session_start"); break;
      case 18:
        if (!session) break;
        if (open_ended) checked(rdv_session_cancel(session), "rdv_session_cancel");
        rdv_session_wait(session);  // reports the render's own failure
        break;
      case 19: if (session) checked(rdv_session_cancel(session), "rdv_session_cancel"); break;
      case 20: end_session(); break;
      case 21:
        if (session) {
          rdv_progress p;
          checked(rdv_session_progress(session, &p), "rdv_session_progress");
          if (!(p.fraction_done >= 0 && p.fraction_done <= 1)) rdv_fuzz::finding("progress fraction out of [0, 1]");
          const char *stats = nullptr;
          checked(rdv_session_stats(session, &stats), "rdv_session_stats");
        }
        break;
      case 22: case 23: if (session) read_film(in); break;
      case 26: {  // object settings: ray visibility per kind, look copies, holdout, catcher
        static const char *kKinds[] = {"camera", "diffuse", "glossy", "transmission", "shadow", "volume_scatter"};
        std::string params = "{\"visibility\":{";
        for (int k = 0; k < 6; ++k) params += std::string(k ? "," : "") + "\"" + kKinds[k] + "\":" + (in.small(2) ? "true" : "false");
        params += std::string("},\"look_copy\":") + (in.small(2) ? "true" : "false") +
                  ",\"holdout\":" + (in.small(4) == 0 ? "true" : "false") +
                  ",\"shadow_catcher\":" + (in.small(4) == 0 ? "true" : "false");
        if (in.small(2)) {  // what Attribute nodes of type Object / Instancer read
          params += std::string(",\"") + (in.small(2) ? "object" : "instancer") + "_attributes\":{\"" + kNames[in.small(4)] + "\":";
          const uint32_t n = in.small(6);
          if (n == 0) params += in.json_number();
          else {
            params += "[";
            for (uint32_t i = 0; i < n; ++i) params += (i ? "," : "") + in.json_number();
            params += "]";
          }
          params += "}";
        }
        if (in.small(2))  // Cryptomatte's names (a name of any bytes; not a string: refused)
          params += ",\"cryptomatte\":{\"object\":" + (in.small(4) ? "\"" + std::string(kNames[in.small(4)]) + "\"" : in.json_number()) +
                    ",\"asset\":\"" + kNames[in.small(4)] + "\"}";
        params += "}";
        checked(rdv_scene_set_instance_params(scene, some(in, instances), traced(params)), "rdv_scene_set_instance_params");
        break;
      }
      case 24:
        if (session) {
          static const char *kFiles[] = {"fuzz.exr", "fuzz.png", "fuzz.nosuchformat"};
          std::string path = (std::filesystem::temp_directory_path() / kFiles[in.small(3)]).string();
          checked(rdv_session_write_image(session, path.c_str(), in.small(2) ? "Filmic" : "Standard"),
                  "rdv_session_write_image");
        }
        break;
      default: {  // a new scene; a session keeps rendering the old one (it holds its own reference)
        checked(rdv_scene_destroy(scene), "rdv_scene_destroy");
        checked(rdv_scene_create(&scene), "rdv_scene_create");
        materials = meshes = lights = instances = 0;
        session_on_scene = false;
        break;
      }
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  Reader in{data, size};
  State state;
  checked(rdv_scene_create(&state.scene), "rdv_scene_create");
  const std::vector<std::string> &scenes = start_scenes();
  const std::string &start = scenes[in.small(uint32_t(scenes.size()))];
  try {
    rdv_tools::load_scene_json(start, RDV_SOURCE_DIR "/scenes", state.scene);
    state.materials = state.meshes = state.instances = state.lights = 8;  // ids near the loaded ones
  } catch (const std::exception &e) {
    rdv_fuzz::finding(std::string("a shipped scene did not load: ") + e.what());
  }
  for (int calls = 0; !in.done() && calls < 64; ++calls) state.step(in);
  state.end_session();
  checked(rdv_scene_destroy(state.scene), "rdv_scene_destroy");
  rdv_fuzz::check_no_live_objects();
  return 0;
}
