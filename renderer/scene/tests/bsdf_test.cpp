// BSDF consistency: sample() weights agree with evalCos()/pdf(), pdf integrates to 1, and the
// estimate of directional albedo by sampling matches brute-force integration.
#include <gtest/gtest.h>

#include <numbers>

#include "renderer/scene/materials/bsdf.h"
#include "renderer/scene/sampling/sobol_sampler.h"

namespace pa {
namespace {

using sampling::PixelSampler;

constexpr float kPi = std::numbers::pi_v<float>;

/// Integrates evalCos and pdf over the sphere with uniform sphere samples (pdf 1 / 4 pi).
struct Integrals {
  double albedo = 0.0;   // integral of f cos (green channel)
  double pdf = 0.0;      // integral of pdf
};

Integrals integrate(const Bsdf& bsdf, const glm::vec3& wo) {
  Integrals out;
  constexpr uint32_t kN = 1u << 18;
  for (uint32_t i = 0; i < kN; ++i) {
    const glm::vec4 u = PixelSampler(5, i).get4(0);
    const glm::vec3 wi = sampling::uniformSphere({u.x, u.y});
    out.albedo += bsdf.evalCos(wo, wi).g * 4.0 * kPi;
    out.pdf += bsdf.pdf(wo, wi) * 4.0 * kPi;
  }
  out.albedo /= kN;
  out.pdf /= kN;
  return out;
}

double sampledAlbedo(const Bsdf& bsdf, const glm::vec3& wo) {
  constexpr uint32_t kN = 1u << 16;
  double sum = 0.0;
  for (uint32_t i = 0; i < kN; ++i) {
    const glm::vec4 u = PixelSampler(9, i).get4(1);
    BsdfSample s;
    if (!bsdf.sample(wo, {u.x, u.y, u.z}, s)) continue;
    // The weight must equal evalCos / pdf for the sampled direction.
    const glm::vec3 f = bsdf.evalCos(wo, s.wi);
    EXPECT_NEAR(s.weight.g, f.g / bsdf.pdf(wo, s.wi), 1e-3f * std::max(1.0f, s.weight.g));
    EXPECT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-3f * s.pdf);
    sum += s.weight.g;
  }
  return sum / kN;
}

TEST(Bsdf, LambertAlbedoAndPdfNormalisation) {
  const glm::vec3 n(0, 0, 1);
  const Bsdf lambert(glm::vec3(0.6f), 0.0f, 0.3f, false, n, n);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
  const Integrals in = integrate(lambert, wo);
  EXPECT_NEAR(in.albedo, 0.6, 0.01);
  EXPECT_NEAR(in.pdf, 1.0, 0.01);
  EXPECT_NEAR(sampledAlbedo(lambert, wo), 0.6, 1e-4);   // cosine sampling: zero variance
}

TEST(Bsdf, GlossyLobeSamplingMatchesIntegration) {
  const glm::vec3 n(0, 0, 1);
  for (float roughness : {0.3f, 0.6f, 1.0f}) {
    const Bsdf glossy(glm::vec3(0.5f), 0.5f, roughness, false, n, n);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.5f, 0.0f, 0.8f));
    const Integrals in = integrate(glossy, wo);
    // D(h)cos(h) sampling reflects part of the GGX lobe under the surface (those samples fail
    // and count as zero): the pdf integrates to at most 1 and at least the diffuse share.
    EXPECT_LE(in.pdf, 1.01) << roughness;
    EXPECT_GE(in.pdf, 1.0 - 2.0 / 3.0) << roughness;
    EXPECT_LE(in.albedo, 0.5 * 0.5 + 0.5 + 0.01) << roughness;   // energy: diffuse + specular weight
    EXPECT_NEAR(sampledAlbedo(glossy, wo), in.albedo, 0.02 * in.albedo) << roughness;
  }
}

TEST(Bsdf, TintedGlossyLobeReflectsInTheAlbedosColour) {
  // A stock shine that multiplies the surface under it: the glossy lobe is albedo x the white
  // one, so a coloured surface's highlight keeps its colour; sampling stays consistent.
  const glm::vec3 n(0, 0, 1);
  const glm::vec3 albedo(0.1f, 0.2f, 0.5f);
  const Bsdf white(albedo, 0.5f, 0.3f, false, n, n), tinted(albedo, 0.5f, 0.3f, false, n, n, true);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.5f, 0.0f, 0.8f));
  const glm::vec3 mirrorDir(-wo.x, -wo.y, wo.z);   // the highlight's peak
  const glm::vec3 diffuse = 0.5f * albedo / kPi * mirrorDir.z;
  const glm::vec3 whiteGlossy = white.evalCos(wo, mirrorDir) - diffuse;
  const glm::vec3 tintedGlossy = tinted.evalCos(wo, mirrorDir) - diffuse;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(tintedGlossy[c], albedo[c] * whiteGlossy[c], 1e-4f * whiteGlossy[c]) << c;
  EXPECT_GT(whiteGlossy.g, 10.0f * diffuse.g);   // the peak is the lobe's, not the diffuse part
  const Integrals in = integrate(tinted, wo);
  EXPECT_LE(in.pdf, 1.01);
  EXPECT_LE(in.albedo, albedo.g + 0.01);   // energy: never above the albedo
  EXPECT_NEAR(sampledAlbedo(tinted, wo), in.albedo, 0.02 * in.albedo);
}

TEST(Bsdf, ReflectanceIsTheLambertWeightAndBoundsTheGlossyAlbedo) {
  // The path integrator's roulette reads reflectance() before a direction is drawn: for a
  // diffuse surface it must be exactly what a sample's weight multiplies the throughput by.
  const glm::vec3 n(0, 0, 1);
  const glm::vec3 albedo(0.15f, 0.35f, 0.8f);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
  const Bsdf lambert(albedo, 0.0f, 0.3f, false, n, n);
  EXPECT_EQ(lambert.reflectance(), albedo);
  for (uint32_t i = 0; i < 4096; ++i) {
    const glm::vec4 u = PixelSampler(3, i).get4(0);
    BsdfSample s;
    if (!lambert.sample(wo, {u.x, u.y, u.z}, s)) continue;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.weight[c], albedo[c], 1e-6f) << i;
  }
  EXPECT_EQ(Bsdf(albedo, 0.0f, 0.3f, true, n, n).reflectance(), albedo);   // a mirror
  // With a glossy lobe: the lobes' mix, above what sampling reflects (the lobe's shadowing).
  for (const bool tinted : {false, true}) {
    const Bsdf glossy(albedo, 0.5f, 0.4f, false, n, n, tinted);
    const glm::vec3 expected = 0.5f * albedo + 0.5f * (tinted ? albedo : glm::vec3(1.0f));
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(glossy.reflectance()[c], expected[c]) << tinted;
    EXPECT_GE(double{glossy.reflectance().g} + 1e-3, sampledAlbedo(glossy, wo)) << tinted;
  }
}

TEST(Bsdf, MirrorIsDeltaWithAlbedoWeight) {
  const glm::vec3 n(0, 0, 1);
  const Bsdf mirror(glm::vec3(0.8f, 0.7f, 0.6f), 0.0f, 0.3f, true, n, n);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.4f, 0.8f));
  BsdfSample s;
  ASSERT_TRUE(mirror.sample(wo, {0.5f, 0.5f, 0.5f}, s));
  EXPECT_TRUE(s.delta);
  EXPECT_NEAR(s.wi.x, -wo.x, 1e-6f);
  EXPECT_NEAR(s.wi.z, wo.z, 1e-6f);
  EXPECT_EQ(s.weight, glm::vec3(0.8f, 0.7f, 0.6f));
  EXPECT_EQ(mirror.evalCos(wo, s.wi), glm::vec3(0.0f));
  EXPECT_EQ(mirror.pdf(wo, s.wi), 0.0f);
}

TEST(Bsdf, NothingBelowTheGeometricSurface) {
  // Shading normal tilted away from the geometric one: directions under the geometric
  // surface get no value (no light leaks through walls).
  const glm::vec3 ng(0, 0, 1);
  const glm::vec3 ns = glm::normalize(glm::vec3(0.5f, 0, 1));
  const Bsdf b(glm::vec3(1.0f), 0.0f, 0.3f, false, ns, ng);
  const glm::vec3 below = glm::normalize(glm::vec3(1, 0, -0.1f));
  EXPECT_EQ(b.evalCos(glm::vec3(0, 0, 1), below), glm::vec3(0.0f));
  EXPECT_EQ(b.pdf(glm::vec3(0, 0, 1), below), 0.0f);
}

}  // namespace
}  // namespace pa
