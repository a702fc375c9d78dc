#include "film/shader_aovs.h"
#include "core/error.h"
#include "textures/shading_point.h"

namespace rdv {

static_assert(ShaderAovs::kMaxPasses == 16, "the message below names it");

ShaderAovs ShaderAovs::parse(const nlohmann::json *j) {
  ShaderAovs out;
  if (!j || j->is_null()) return out;
  if (!j->is_array()) fail("render settings: 'aovs' must be a list of {\"name\", \"type\"}", RDV_ERROR_INVALID_ARGUMENT);
  if (j->size() > size_t(kMaxPasses)) {
    std::string message = "render settings: at most 16 shader AOVs, got ";  // kMaxPasses
    message += std::to_string(j->size());
    fail(message, RDV_ERROR_INVALID_ARGUMENT);
  }
  for (const nlohmann::json &a : *j) {
    if (!a.is_object() || !a.contains("name") || !a["name"].is_string() || a["name"].get<std::string>().empty())
      fail("render settings: each of 'aovs' needs a \"name\"", RDV_ERROR_INVALID_ARGUMENT);
    Pass p;
    p.name = a["name"].get<std::string>();
    const std::string type = a.value("type", std::string("color"));
    if (type != "color" && type != "value")
      fail("render settings: shader AOV '" + p.name + "': 'type' must be color or value, got '" + type + "'",
           RDV_ERROR_INVALID_ARGUMENT);
    p.color = type == "color";
    p.id = attribute_id(p.name);
    if (out.find(p.id)) fail("render settings: shader AOV '" + p.name + "' is given twice", RDV_ERROR_INVALID_ARGUMENT);
    p.offset = out.channels;
    out.channels += p.color ? 4 : 1;
    out.passes.push_back(p);
  }
  return out;
}

nlohmann::json ShaderAovs::to_json() const {
  if (empty()) return nullptr;
  nlohmann::json j = nlohmann::json::array();
  for (const Pass &p : passes) j.push_back({{"name", p.name}, {"type", p.color ? "color" : "value"}});
  return j;
}

}  // namespace rdv
