#include "media/medium.h"
#include "media/vdb_file.h"

namespace rdv {

Medium Medium::from_params(Params &p, const std::string &name, const GridBuffers *buffers) {
  Medium m;
  m.name = name;
  auto non_negative = [&](Color c, const char *key) {
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(p.what() + ": '" + key + "' must not be negative");
    return c;
  };
  if (p.has("sigma_a") || p.has("sigma_s")) {
    m.sigma_a = non_negative(p.get_vec3("sigma_a", Color(0.0f)), "sigma_a");
    m.sigma_s = non_negative(p.get_vec3("sigma_s", Color(0.0f)), "sigma_s");
    m.emission = non_negative(p.get_vec3("emission", Color(0.0f)), "emission");
  } else {
    // Cycles' Principled Volume: density scales scattering (colour) and absorption
    // (absorption colour: what is NOT absorbed); emission = colour x strength.
    float density = p.get_float("density", 1.0f);
    if (density < 0) fail(p.what() + ": 'density' must not be negative");
    Color color = non_negative(p.get_vec3("color", Color(0.5f)), "color");
    Color absorption = non_negative(p.get_vec3("absorption_color", Color(0.0f)), "absorption_color");
    m.sigma_s = color * density;
    m.sigma_a = vmax(Color(1.0f) - absorption, Color(0.0f)) * vmax(Color(1.0f) - color, Color(0.0f)) * density;
    Color ec = non_negative(p.get_vec3("emission_color", Color(1.0f)), "emission_color");
    float es = p.get_float("emission_strength", 0.0f);
    if (es < 0) fail(p.what() + ": 'emission_strength' must not be negative");
    m.emission = ec * es;
  }
  // Blackbody emission (Principled Volume): intensity, tint, temperature in kelvin.
  m.blackbody.intensity = p.get_float("blackbody_intensity", 0.0f);
  m.blackbody.tint = non_negative(p.get_vec3("blackbody_tint", Color(1.0f)), "blackbody_tint");
  m.temperature = p.get_float("temperature", 1000.0f);
  if (!(m.blackbody.intensity >= 0) || !(m.temperature >= 0) || !std::isfinite(m.temperature))
    fail(p.what() + ": 'blackbody_intensity' and 'temperature' must be finite and not negative");
  float g = p.get_float("anisotropy", 0.0f);
  m.phase.g = clampf(g, -0.999f, 0.999f);
  m.sigma_t = m.sigma_a + m.sigma_s;
  if (!is_finite(m.sigma_t)) fail(p.what() + ": coefficients must be finite");
  // Grids that vary the emission: its strength, and the blackbody temperature (Cycles'
  // Temperature Attribute). One that cannot be read turns its emission off.
  if (const nlohmann::json *eg = p.get_json("emission_grid")) {
    m.emission_grid = load_grid(m, *eg, p.what() + " emission_grid", "its emission", buffers);
    if (!m.emission_grid) m.emission = Color(0.0f);
  }
  if (const nlohmann::json *tg = p.get_json("temperature_grid")) {
    m.temperature_grid = load_grid(m, *tg, p.what() + " temperature_grid", "its blackbody emission", buffers);
    if (!m.temperature_grid) m.blackbody.intensity = 0;
  }
  if (const nlohmann::json *grid = p.get_json("grid")) {
    m.grid = load_grid(m, *grid, p.what() + " grid", "this medium", buffers);
    if (!m.grid) {  // a density grid that cannot be read: vacuum, as the warning says
      m.sigma_a = m.sigma_s = m.sigma_t = m.emission = Color(0.0f);
      m.blackbody.intensity = 0;
    }
    std::string method = p.get_string("method", "tracking");
    if (method != "tracking" && method != "ray_marching")
      fail(p.what() + ": 'method' must be \"tracking\" or \"ray_marching\", not \"" + method + "\"");
    if (m.grid) m.type = method == "tracking" ? MediumType::GridTracking : MediumType::GridRayMarching;  // else vacuum
    m.step_size = p.get_float("step_size", 0.0f);
    if (!(m.step_size >= 0)) fail(p.what() + ": 'step_size' must not be negative");
    if (m.step_size == 0 && m.grid) {  // default: one voxel (its shortest edge in the world)
      const Transform &g = m.grid->grid_to_world();
      m.step_size = std::min({length(g.column(0)), length(g.column(1)), length(g.column(2))});
    }
  } else if (p.has("method") || p.has("step_size")) {
    fail(p.what() + ": 'method' and 'step_size' need a 'grid'");
  }
  return m;
}

// "grid": dense {"resolution": [nx,ny,nz], "values": [...], "bounds": [[min],[max]]} (the
// values fill the box `bounds`, default the unit cube), dense {"buffer": name, "bounds"}
// (a grid added with rdv_scene_add_grid) or {"file": "x.vdb", "name": "density"} (the
// file's own voxel placement); all then placed by "transform".
std::shared_ptr<const DensityGrid> Medium::load_grid(Medium &m, const nlohmann::json &j, const std::string &what,
                                                     const std::string &without, const GridBuffers *buffers) {
  Params g(j.dump(), what);
  Transform to_world = g.get_transform("transform", Transform());
  if (!to_world.is_finite() || !(std::fabs(to_world.det3()) > 0)) fail(what + ": 'transform' must be finite and invertible");
  if (g.has("file")) {
    std::string file = g.get_string("file", ""), grid_name = g.get_string("name", "density");
    g.check_all_used();
    std::string error;
    std::shared_ptr<const DensityGrid> grid = load_vdb_density(file, grid_name, to_world, error);
    if (!grid) m.warnings.push_back("medium '" + m.name + "': " + error + "; rendering without " + without);
    return grid;
  }
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> values;
  const GridBuffer *buffer = nullptr;
  if (g.has("buffer")) {
    std::string buffer_name = g.get_string("buffer", "");
    buffer = buffers ? find_grid_buffer(*buffers, buffer_name) : nullptr;
    if (!buffer) {
      g.get_json("bounds");  // a missing buffer is a warning, not a malformed grid
      g.check_all_used();
      m.warnings.push_back("medium '" + m.name + "': no grid buffer '" + buffer_name +
                           "' (add it with rdv_scene_add_grid first); rendering without " + without);
      return nullptr;
    }
    nx = buffer->nx, ny = buffer->ny, nz = buffer->nz;
  } else {
    std::vector<float> res = g.get_floats("resolution", 3, {0, 0, 0});
    nx = int(res[0]), ny = int(res[1]), nz = int(res[2]);
    if (nx < 1 || ny < 1 || nz < 1 || res[0] != nx || res[1] != ny || res[2] != nz || double(nx) * ny * nz > 1e9)
      fail(what + ": 'resolution' must be three positive integers (or give a 'file' or a 'buffer')");
    values = g.get_floats("values", size_t(nx) * ny * nz, {});
    if (values.empty()) fail(what + ": needs 'values' (" + std::to_string(size_t(nx) * ny * nz) + " densities, x fastest)");
    for (float v : values)
      if (v < 0) fail(what + ": densities must not be negative");
  }
  Vec3 lo(0.0f), hi(1.0f);
  if (const nlohmann::json *b = g.get_json("bounds")) {
    if (!b->is_array() || b->size() != 2) fail(what + ": 'bounds' must be [[x0,y0,z0],[x1,y1,z1]]");
    Params bp(nlohmann::json{{"lo", (*b)[0]}, {"hi", (*b)[1]}}.dump(), what + " 'bounds'");
    lo = bp.get_vec3("lo", lo);
    hi = bp.get_vec3("hi", hi);
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) fail(what + ": 'bounds' must have max > min on every axis");
  }
  g.check_all_used();
  if (buffer) values = buffer->values;  // each medium owns its voxels (a buffer may be replaced later)
  // Grid coordinates [0, n] -> the box [lo, hi] -> the world.
  Transform box;
  Vec3 size = hi - lo;
  box.m[0][0] = size.x / nx; box.m[1][1] = size.y / ny; box.m[2][2] = size.z / nz;
  box.m[0][3] = lo.x; box.m[1][3] = lo.y; box.m[2][3] = lo.z;
  return std::make_shared<DensityGrid>(nx, ny, nz, std::move(values), to_world * box);
}

MediumSample Medium::sample_homogeneous(float tmax, SampleRun &rng) const {
  MediumSample s;
  if (max_component(sigma_s) == 0) {
    // Nothing scatters: attenuate exactly (zero variance).
    s.scattered = false;
    s.t = tmax;
    s.weight = transmittance(tmax);
    return s;
  }
  int c = std::min(int(rng.next_float() * 3.0f), 2);
  float st = sigma_t[c];
  float u_distance = rng.next_float();
  float t = st > 0 ? -std::log(1.0f - u_distance) / st : kInf;
  if (t < tmax) {
    Color tr = transmittance(t);
    Color density = sigma_t * tr;  // per-channel distance densities
    float pdf = average(density);
    if (!(pdf > 0)) return s;
    s.scattered = true;
    s.t = t;
    s.weight = sigma_s * tr / pdf;
    return s;
  }
  Color tr = transmittance(tmax);
  float p_surface = average(tr);
  s.scattered = false;
  s.t = tmax;
  s.weight = p_surface > 0 ? tr / p_surface : Color(0.0f);
  return s;
}

}  // namespace rdv
