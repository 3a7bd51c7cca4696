#include "renderer/scene/materials/bsdf.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace pa {

using sampling::kInvPi;
using sampling::kPi;

Bsdf::Bsdf(const glm::vec3& albedo, float specular, float roughness, bool mirror,
           const glm::vec3& shadingNormal, const glm::vec3& geometricNormal, bool tintedSpecular)
    : albedo_(glm::clamp(albedo, glm::vec3(0.0f), glm::vec3(1.0f))),
      specular_(std::clamp(specular, 0.0f, 1.0f)),
      tintedSpecular_(tintedSpecular),
      alpha_(std::max(1e-3f, roughness * roughness)),
      mirror_(mirror),
      frame_(shadingNormal),
      ng_(geometricNormal) {}

float Bsdf::specularProbability() const {
  if (specular_ <= 0.0f) return 0.0f;
  const float brightest = std::max({albedo_.r, albedo_.g, albedo_.b});
  const float diffuseWeight = (1.0f - specular_) * brightest;
  const float specularWeight = tintedSpecular_ ? specular_ * brightest : specular_;
  return specularWeight > 0.0f ? specularWeight / (specularWeight + diffuseWeight) : 0.0f;
}

float Bsdf::ggxD(float cosH) const {
  if (cosH <= 0.0f) return 0.0f;
  const float a2 = alpha_ * alpha_;
  const float d = cosH * cosH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float Bsdf::ggxG1(float cosV) const {
  if (cosV <= 0.0f) return 0.0f;
  const float a2 = alpha_ * alpha_;
  return 2.0f * cosV / (cosV + std::sqrt(a2 + (1.0f - a2) * cosV * cosV));
}

glm::vec3 Bsdf::evalCos(const glm::vec3& wo, const glm::vec3& wi) const {
  if (mirror_) return glm::vec3(0.0f);
  if (glm::dot(wi, ng_) <= 0.0f) return glm::vec3(0.0f);
  const float cosI = glm::dot(wi, frame_.n);
  const float cosO = glm::dot(wo, frame_.n);
  if (cosI <= 0.0f || cosO <= 0.0f) return glm::vec3(0.0f);
  glm::vec3 f = (1.0f - specular_) * albedo_ * kInvPi;
  if (specular_ > 0.0f) {
    const glm::vec3 h = glm::normalize(wi + wo);
    const float spec = ggxD(glm::dot(h, frame_.n)) * ggxG1(cosI) * ggxG1(cosO) / (4.0f * cosI * cosO);
    f += tintedSpecular_ ? specular_ * spec * albedo_ : glm::vec3(specular_ * spec);
  }
  return f * cosI;
}

float Bsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (mirror_) return 0.0f;
  const float cosI = glm::dot(wi, frame_.n);
  if (cosI <= 0.0f || glm::dot(wi, ng_) <= 0.0f) return 0.0f;
  const float ps = specularProbability();
  float p = (1.0f - ps) * cosI * kInvPi;
  if (ps > 0.0f) {
    const glm::vec3 h = glm::normalize(wi + wo);
    const float cosH = glm::dot(h, frame_.n);
    const float woH = std::abs(glm::dot(wo, h));
    if (woH > 0.0f) p += ps * ggxD(cosH) * cosH / (4.0f * woH);
  }
  return p;
}

bool Bsdf::sample(const glm::vec3& wo, const glm::vec3& u, BsdfSample& out) const {
  if (mirror_) {
    const glm::vec3 wi = 2.0f * glm::dot(wo, frame_.n) * frame_.n - wo;
    if (glm::dot(wi, ng_) <= 0.0f) return false;
    out = {wi, albedo_, 1.0f, true, true};
    return true;
  }
  const float ps = specularProbability();
  glm::vec3 wi;
  bool glossy = false;
  if (u.z < ps) {
    // Sample the GGX normal distribution D(h) cos(h), reflect wo about h.
    const float tan2 = alpha_ * alpha_ * u.x / std::max(1e-7f, 1.0f - u.x);
    const float cosH = 1.0f / std::sqrt(1.0f + tan2);
    const float sinH = std::sqrt(std::max(0.0f, 1.0f - cosH * cosH));
    const float phi = 2.0f * kPi * u.y;
    const glm::vec3 h = frame_.toWorld({sinH * std::cos(phi), sinH * std::sin(phi), cosH});
    wi = 2.0f * glm::dot(wo, h) * h - wo;
    glossy = true;
  } else {
    wi = frame_.toWorld(sampling::cosineHemisphere({u.x, u.y}));
  }
  const float p = pdf(wo, wi);
  if (!(p > 0.0f)) return false;
  const glm::vec3 f = evalCos(wo, wi);
  out = {wi, f / p, p, false, glossy};
  return true;
}

}  // namespace pa
