// The BSDF at a surface point: a small fixed set of lobes, each a plain struct,
// dispatched with a switch (no allocation, no virtual calls in the hot loop).
// Each lobe has eval / sample / pdf in the local shading frame; the Bsdf adds the
// frame change, lobe selection and the transport-mode rules BDPT needs:
//  - Radiance mode (camera paths) and Importance mode (light paths) differ by the
//    shading-normal correction (Veach 1997, eq. 5.17) and, for refraction (later
//    lobes), by the eta^2 radiance scaling.
#pragma once
#include <array>
#include "bsdfs/fresnel.h"
#include "bsdfs/microfacet.h"
#include "core/math.h"

namespace rdv {

enum class TransportMode { Radiance, Importance };

enum class LobeType : uint8_t {
  Lambert,           // f = color / pi
  GgxConductor,      // GGX reflection, Fresnel none (tint) or complex IOR
  SpecularConductor  // perfect mirror (GGX below Cycles' smoothness limit)
};

struct Lobe {
  LobeType type = LobeType::Lambert;
  Color color{1.0f};          // tint / albedo
  GgxDistribution ggx{1, 1};
  bool use_conductor_fresnel = false;
  Color eta{1.0f}, k{0.0f};

  Color fresnel(float cos_i) const {
    return use_conductor_fresnel ? color * fresnel_conductor(cos_i, eta, k) : color;
  }
  bool is_delta() const { return type == LobeType::SpecularConductor; }
};

struct BsdfSample {
  Vec3 wi;            // world space
  Color weight;       // f * |cos| / pdf, including the transport-mode correction
  float pdf = 0;      // solid angle; for delta lobes the discrete selection probability
  bool is_delta = false;
};

class Bsdf {
 public:
  static constexpr int kMaxLobes = 4;

  Bsdf() = default;
  // ng: geometric normal, ns: shading normal (both unit); wo: direction to the viewer
  // (for light paths, to the previous vertex). Two-sided: the frame is flipped to
  // wo's side of the geometry.
  Bsdf(Vec3 ng, Vec3 ns, Vec3 wo);

  void add_lobe(const Lobe &lobe, float sample_weight);
  int num_lobes() const { return n_; }
  bool is_delta() const;  // every lobe is delta: no point connecting to lights
  bool has_lobes() const { return n_ > 0; }

  Color eval(Vec3 wo, Vec3 wi, TransportMode mode) const;  // f * |cos(wi, ns)|
  float pdf(Vec3 wo, Vec3 wi) const;
  bool sample(Vec3 wo, float u_lobe, Vec2 u, TransportMode mode, BsdfSample &out) const;
  // Directional albedo-like colour for the Diffuse Color AOV.
  Color albedo() const;
  const Frame &frame() const { return frame_; }
  Vec3 geometric_normal() const { return ng_; }

 private:
  float shading_correction(Vec3 wo, Vec3 wi, TransportMode mode) const;
  Frame frame_;
  Vec3 ng_;
  int n_ = 0;
  std::array<Lobe, kMaxLobes> lobes_{};
  std::array<float, kMaxLobes> raw_weight_{};  // as given to add_lobe
  std::array<float, kMaxLobes> pick_{};        // normalised lobe selection probabilities
};

// Per-lobe routines in the local frame, exposed for the statistical tests.
Color lobe_eval(const Lobe &lobe, Vec3 wo, Vec3 wi);  // f (without cosine)
float lobe_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
// Returns false when no direction is sampled. weight = f * cos / pdf.
bool lobe_sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);

}  // namespace rdv
