#pragma once
// The surface scattering model: Lambert diffuse, an optional GGX glossy lobe weighted by
// `specular` (white, or in the albedo's colour when tinted; Fresnel = 1 so the sum never exceeds
// albedo), or a perfect mirror.
// All directions are world space, unit length, pointing away from the surface.
#include <glm/vec3.hpp>

#include "renderer/scene/sampling/warp.h"

namespace pa {

/// Result of sampling the BSDF: direction, weight = f * |cos| / pdf, and the solid-angle pdf.
struct BsdfSample {
  glm::vec3 wi{0.0f};
  glm::vec3 weight{0.0f};
  float pdf = 0.0f;
  bool delta = false;    ///< Mirror: pdf is a Dirac delta (no MIS with light sampling).
  bool glossy = false;   ///< Sampled the GGX lobe (ray cone stays narrower).
};

/// A BSDF instance at one shading point.
class Bsdf {
 public:
  /// shadingNormal and geometricNormal must face the outgoing direction's side; a tinted glossy
  /// lobe reflects albedo x its white value.
  Bsdf(const glm::vec3& albedo, float specular, float roughness, bool mirror,
       const glm::vec3& shadingNormal, const glm::vec3& geometricNormal, bool tintedSpecular = false);

  /// True for the perfect mirror (no light sampling).
  bool isDelta() const { return mirror_; }
  /// What the surface reflects of light from above, per channel, ignoring the glossy lobe's
  /// shadowing: the albedo for a diffuse surface or a mirror, the lobes' mix of albedo and white
  /// (or the albedo, when tinted) with a glossy one. For a diffuse surface it is sample()'s weight.
  glm::vec3 reflectance() const {
    if (mirror_) return albedo_;
    return (1.0f - specular_) * albedo_ + specular_ * (tintedSpecular_ ? albedo_ : glm::vec3(1.0f));
  }
  /// f(wo, wi) * |cos(n, wi)|; zero for directions below the geometric surface.
  glm::vec3 evalCos(const glm::vec3& wo, const glm::vec3& wi) const;
  /// Solid-angle pdf of sample() producing wi.
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  /// Samples wi from u (lobe choice in u.z). Returns false when no valid direction.
  bool sample(const glm::vec3& wo, const glm::vec3& u, BsdfSample& out) const;

 private:
  float specularProbability() const;
  float ggxD(float cosH) const;
  float ggxG1(float cosV) const;

  glm::vec3 albedo_;
  float specular_;
  bool tintedSpecular_;
  float alpha_;
  bool mirror_;
  sampling::Frame frame_;
  glm::vec3 ng_;
};

}  // namespace pa
