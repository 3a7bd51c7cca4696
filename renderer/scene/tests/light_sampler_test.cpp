// Known answers for light selection: the choice among point and spot lights follows their
// contribution at the shading point (light tree), and the estimator stays exact (unbiased) for
// any mix.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/lights/light_sampler.h"

namespace pa {
namespace {

/// The exact unshadowed sum of colour * intensity * falloff * spot over the lights at p.
glm::vec3 exactSum(const std::vector<LightDesc>& lights, const glm::vec3& p) {
  glm::vec3 sum(0.0f);
  for (const LightDesc& l : lights) {
    const glm::vec3 d = p - l.position;
    const float dist = glm::length(d);
    float f = distanceFalloff(l, dist);
    if (l.type == LightType::Spot) f *= spotFactor(l, d / dist);
    sum += l.color * l.intensity * f;
  }
  return sum;
}

/// Point lights: one weak lamp next to the shading point among many strong distant ones.
std::vector<LightDesc> lampAmongDistantLights() {
  std::vector<LightDesc> lights;
  for (int i = 0; i < 60; ++i) {
    LightDesc far;
    far.position = glm::vec3(2000.0f + 10.0f * float(i), -500.0f, 300.0f);
    far.intensity = 5000.0f;
    lights.push_back(far);
  }
  LightDesc lamp;
  lamp.position = glm::vec3(0.0f, 0.0f, 20.0f);
  lamp.intensity = 40.0f;
  lamp.color = glm::vec3(1.0f, 0.5f, 0.25f);
  lights.push_back(lamp);
  return lights;
}

/// lampAmongDistantLights() in white, sampled from a point on the ground below the lamp, with
/// the exact sum of their irradiance there.
struct WhiteLampAmongDistantLights {
  std::vector<LightDesc> lights = [] {
    std::vector<LightDesc> white = lampAmongDistantLights();
    for (LightDesc& l : white) l.color = glm::vec3(1.0f);
    return white;
  }();
  LightSampler sampler{lights, {}, Sky{}, Bounds{}};
  glm::vec3 p{1.0f, 2.0f, 0.0f};
  glm::vec3 n{0.0f, 0.0f, 1.0f};
  glm::vec3 exact = exactSum(lights, p);
};

TEST(LightSampler, EveryPointLightSampleEstimatesTheExactSum) {
  // Selection in proportion to each light's contribution to a diffuse surface (radiance x the
  // cosine toward it, above lampCosineFactor's floor here) makes radiance x cosine / pdf the
  // same for every sample (equal colours apart): each single sample must give the exact sum.
  const WhiteLampAmongDistantLights scene;
  const auto& [lights, sampler, p, n, exact] = scene;
  double exactIrradiance = 0.0;
  for (const LightDesc& l : lights) {
    const glm::vec3 toLight = l.position - p;
    const float cosine = glm::dot(glm::normalize(toLight), n);
    ASSERT_GT(cosine, kLeastLampCosine);
    exactIrradiance += double(l.intensity * distanceFalloff(l, glm::length(toLight)) * cosine);
  }
  for (int i = 0; i < 1000; ++i) {
    const float u = (float(i) + 0.5f) / 1000.0f;
    LightSample ls;
    ASSERT_TRUE(sampler.sample(p, n, glm::vec4(u, 0.3f, 0.7f, 1.0f - u), ls));
    const double estimate = double(ls.radiance.x * glm::dot(ls.wi, n) / ls.pdf);
    EXPECT_NEAR(estimate, exactIrradiance, 1e-3 * exactIrradiance) << "sample " << i;
  }
}

TEST(LightSampler, NearbyLampGetsMostSamplesAndTheMeanIsExact) {
  // The lamp 20 units above the point gives ~60% of the light there but 0.01% of the power: the
  // choice at the shading point must spend most samples on it, and the mean must stay exact.
  const WhiteLampAmongDistantLights scene;
  const auto& [lights, sampler, p, n, exact] = scene;
  constexpr int kSamples = 1 << 14;
  int onLamp = 0;
  double mean = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const float u = (float(i) + 0.5f) / float(kSamples);
    LightSample ls;
    if (!sampler.sample(p, n, glm::vec4(0.5f, 0.3f, 0.7f, u), ls)) continue;
    if (glm::length(ls.lightPoint - lights.back().position) == 0.0f) ++onLamp;
    mean += double(ls.radiance.x / ls.pdf) / kSamples;
  }
  EXPECT_GT(onLamp, kSamples / 2);
  EXPECT_NEAR(mean, exact.x, 1e-3 * exact.x);
}

TEST(LightSampler, MixedLightsMeanIsTheExactSum) {
  // Coloured point lights, a linear light, a spot light and a light out of range.
  std::vector<LightDesc> lights = lampAmongDistantLights();
  LightDesc linear;
  linear.position = glm::vec3(100.0f, 0.0f, 50.0f);
  linear.falloff = Falloff::Linear;
  linear.range = 400.0f;
  linear.intensity = 2.0f;
  lights.push_back(linear);
  LightDesc spot;
  spot.type = LightType::Spot;
  spot.position = glm::vec3(0.0f, 0.0f, 200.0f);
  spot.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  spot.cosInnerAngle = 0.99f;
  spot.cosOuterAngle = 0.9f;
  spot.intensity = 3000.0f;
  lights.push_back(spot);
  LightDesc outOfRange = linear;
  outOfRange.position = glm::vec3(0.0f, 5000.0f, 0.0f);
  lights.push_back(outOfRange);
  const LightSampler sampler(lights, {}, Sky{}, Bounds{});
  const glm::vec3 p(10.0f, 5.0f, 0.0f);
  const glm::vec3 exact = exactSum(lights, p);
  const int n = 1 << 16;
  glm::dvec3 mean(0.0);
  for (int i = 0; i < n; ++i) {
    // Stratified in u.w (the within-category choice), u.x fixed on the category.
    const float uw = (float(i) + 0.5f) / float(n);
    LightSample ls;
    if (!sampler.sample(p, glm::vec3(0.0f, 0.0f, 1.0f), glm::vec4(0.5f, 0.5f, 0.5f, uw), ls)) continue;
    EXPECT_NE(glm::length(ls.lightPoint - outOfRange.position), 0.0f) << "an unreachable light was chosen";
    mean += glm::dvec3(ls.radiance / ls.pdf) / double(n);
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], exact[c], 1e-3 * exact[c]) << "channel " << c;
}

TEST(LightSampler, NoSampleWhereNoPointLightReaches) {
  LightDesc linear;
  linear.falloff = Falloff::Linear;
  linear.range = 100.0f;
  const std::vector<LightDesc> lights{linear};
  const LightSampler sampler(lights, {}, Sky{}, Bounds{});
  LightSample ls;
  EXPECT_FALSE(sampler.sample(glm::vec3(500.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec4(0.5f), ls));
  EXPECT_TRUE(sampler.sample(glm::vec3(50.0f, 0.0f, -10.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec4(0.5f), ls));
  // In range but in the plane of the point's surface (or below it): nothing to reflect.
  EXPECT_FALSE(sampler.sample(glm::vec3(50.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec4(0.5f), ls));
  EXPECT_FALSE(sampler.sample(glm::vec3(50.0f, 0.0f, 10.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec4(0.5f), ls));
}

TEST(LightSampler, SunsWithoutLightAreNoSunDirections) {
  // A renderer's light pool keeps switched-off slots: a dark directional light must not count as
  // a sun (the sun/sky visibility map is traced anew whenever the number of suns changes).
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  LightDesc off = sun;
  off.direction = glm::vec3(1.0f, 0.0f, 0.0f);
  off.intensity = 0.0f;
  LightDesc black = sun;
  black.color = glm::vec3(0.0f);
  LightDesc lamp;
  lamp.position = glm::vec3(0.0f, 0.0f, 10.0f);
  const std::vector<LightDesc> lights{off, sun, lamp, black};
  Bounds bounds;
  bounds.extend(glm::vec3(-10.0f));
  bounds.extend(glm::vec3(10.0f));
  const LightSampler sampler(lights, {}, Sky{}, bounds);
  const std::vector<glm::vec3> suns = sampler.sunDirections();
  ASSERT_EQ(suns.size(), 1u);
  EXPECT_EQ(suns[0], sun.direction);
}

TEST(LightSampler, DarkPointLightsChangeNoSample) {
  // Switched-off pool lights (intensity 0) are skipped when choosing a lamp: every sample equals
  // the one drawn without them.
  std::vector<LightDesc> lit = lampAmongDistantLights();
  std::vector<LightDesc> withDark;
  for (const LightDesc& l : lit) {
    LightDesc dark = l;
    dark.position += glm::vec3(1.0f);
    dark.intensity = 0.0f;
    withDark.push_back(dark);
    withDark.push_back(l);
  }
  Bounds bounds;
  bounds.extend(glm::vec3(-100.0f));
  bounds.extend(glm::vec3(3000.0f));
  const LightSampler plain(lit, {}, Sky{}, bounds);
  const LightSampler padded(withDark, {}, Sky{}, bounds);
  const glm::vec3 p(1.0f, 2.0f, 0.0f), n(0.0f, 0.0f, 1.0f);
  for (int i = 0; i < 256; ++i) {
    const glm::vec4 u((i + 0.5f) / 256.0f, 0.37f, 0.61f, std::fmod(0.618034f * float(i), 1.0f));
    LightSample a, b;
    const bool okA = plain.sample(p, n, u, a);
    ASSERT_EQ(padded.sample(p, n, u, b), okA) << i;
    if (!okA) continue;
    EXPECT_EQ(a.wi, b.wi) << i;
    EXPECT_EQ(a.radiance, b.radiance) << i;
    EXPECT_EQ(a.pdf, b.pdf) << i;
  }
}

TEST(LightSampler, LampCosineFactorIsTheCosineTowardTheLampWithinItsBounds) {
  LightDesc lamp;
  lamp.position = glm::vec3(0.0f, 0.0f, 10.0f);
  const glm::vec3 up(0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT_EQ(lampCosineFactor(lamp, glm::vec3(0.0f), up), 1.0f);                    // straight above
  EXPECT_NEAR(lampCosineFactor(lamp, glm::vec3(10.0f, 0.0f, 0.0f), up), std::sqrt(0.5f), 1e-6f);   // at 45 degrees
  EXPECT_FLOAT_EQ(lampCosineFactor(lamp, glm::vec3(1000.0f, 0.0f, 0.0f), up), kLeastLampCosine);   // grazing: the floor
  EXPECT_EQ(lampCosineFactor(lamp, glm::vec3(0.0f, 0.0f, 20.0f), up), 0.0f);             // below the tangent plane
  EXPECT_EQ(lampCosineFactor(lamp, glm::vec3(0.0f, 0.0f, 20.0f), glm::vec3(0.0f)), 1.0f);   // no surface
  // A sphere lamp whose centre lies in the plane still lights it: radius / distance.
  lamp.radius = 2.0f;
  EXPECT_NEAR(lampCosineFactor(lamp, glm::vec3(-8.0f, 0.0f, 10.0f), up), 0.25f, 1e-6f);
  EXPECT_EQ(lampCosineFactor(lamp, glm::vec3(-8.0f, 0.0f, 12.5f), up), 0.0f);            // wholly below
}

TEST(LightSampler, LampChoiceProbabilityIsItsWeightShare) {
  // The lamps' weights are computed eight at a time; the probability of each chosen lamp must be
  // its localLightWeight x lampCosineFactor over the sum of all (lamps wholly below the tangent
  // plane weigh 0), for a mix of point, spot, linear, inverse-square and out-of-range lamps (13:
  // a partial group).
  std::vector<LightDesc> lights;
  for (int i = 0; i < 13; ++i) {
    LightDesc l;
    l.type = i % 3 == 0 ? LightType::Spot : LightType::Point;
    l.position = glm::vec3(37.0f * float(i % 5) - 60.0f, 23.0f * float(i % 4) - 30.0f, float(i) * 9.0f - 40.0f);
    l.intensity = 100.0f + 50.0f * float(i);
    l.color = glm::vec3(1.0f, 0.2f + 0.05f * float(i), 0.5f);
    if (i % 2) {
      l.falloff = Falloff::Linear;
      l.range = 60.0f + 10.0f * float(i);
    }
    if (l.type == LightType::Spot) {
      l.direction = glm::normalize(glm::vec3(0.3f, -0.2f, -1.0f));
      l.cosInnerAngle = 0.95f;
      l.cosOuterAngle = 0.6f;
    }
    lights.push_back(l);
  }
  const LightSampler sampler(lights, {}, Sky{}, Bounds{});
  const glm::vec3 n = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(20.0f, -10.0f, -5.0f), glm::vec3(-50.0f, 30.0f, 40.0f)}) {
    double total = 0.0;
    for (const LightDesc& l : lights)
      if (glm::dot(l.position - p, n) + l.radius > 0.0f) total += localLightWeight(l, p) * lampCosineFactor(l, p, n);
    ASSERT_GT(total, 0.0);
    int chosen = 0;
    for (int i = 0; i < 512; ++i) {
      LightSample ls;
      if (!sampler.sample(p, n, glm::vec4(0.5f, 0.5f, 0.5f, (float(i) + 0.5f) / 512.0f), ls)) continue;
      for (const LightDesc& l : lights) {
        if (ls.lightPoint != l.position) continue;
        ++chosen;
        EXPECT_GT(glm::dot(l.position - p, n) + l.radius, 0.0f) << "a lamp below the tangent plane was chosen";
        EXPECT_NEAR(ls.pdf, localLightWeight(l, p) * lampCosineFactor(l, p, n) / total, 1e-5 * ls.pdf);
      }
    }
    EXPECT_GT(chosen, 400);
  }
}

TEST(LightSampler, StoredLampWeightsChooseAsRecomputedOnes) {
  // sample() keeps the weights of the first lamps from the split to the choice; the lamp chosen
  // and its probability must be those of recomputing every weight while choosing, bit for bit,
  // with fewer lamps than are stored (300) and more (700: the rest are recomputed).
  for (const int count : {300, 700}) {
    std::mt19937 rng(1234u + unsigned(count));
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<LightDesc> lights;
    for (int i = 0; i < count; ++i) {
      LightDesc l;
      l.type = i % 4 == 0 ? LightType::Spot : LightType::Point;
      l.position = glm::vec3(unit(rng), unit(rng), unit(rng)) * 400.0f - 200.0f;
      l.intensity = 10.0f + 500.0f * unit(rng);
      l.color = glm::vec3(unit(rng), unit(rng), unit(rng));
      l.radius = i % 5 == 0 ? 4.0f * unit(rng) : 0.0f;
      if (i % 3 == 0) {
        l.falloff = Falloff::Linear;
        l.range = 50.0f + 150.0f * unit(rng);   // many lamps out of range: weight 0
      }
      if (l.type == LightType::Spot) {
        l.direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) - 0.5f);
        l.cosInnerAngle = 0.9f;
        l.cosOuterAngle = 0.5f;
      }
      lights.push_back(l);
    }
    const LightSampler sampler(lights, {}, Sky{}, Bounds{});
    int chosen = 0;
    for (int i = 0; i < 4000; ++i) {
      const glm::vec3 p = glm::vec3(unit(rng), unit(rng), unit(rng)) * 400.0f - 200.0f;
      const glm::vec3 n = i % 7 == 0 ? glm::vec3(0.0f) : glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) - 0.5f);
      const float u = i % 50 == 0 ? 0x1.fffffep-1f : i % 50 == 1 ? 0.0f : unit(rng);
      uint32_t stored = UINT32_MAX, recomputed = UINT32_MAX;
      float storedProbability = -1.0f, recomputedProbability = -1.0f;
      const bool a = sampler.pickLamp(p, n, u, true, stored, storedProbability);
      const bool b = sampler.pickLamp(p, n, u, false, recomputed, recomputedProbability);
      ASSERT_EQ(a, b) << "lamps " << count << " sample " << i;
      if (!a) continue;
      ++chosen;
      ASSERT_EQ(stored, recomputed) << "lamps " << count << " sample " << i;
      ASSERT_EQ(std::bit_cast<uint32_t>(storedProbability), std::bit_cast<uint32_t>(recomputedProbability))
          << "lamps " << count << " sample " << i;
    }
    EXPECT_GT(chosen, 3000) << "lamps " << count;
  }
}

TEST(LightSampler, LocalWeightBoundsSphereLights) {
  // A sphere light whose centre is out of range still reaches p with its near side: weight > 0.
  LightDesc sphere;
  sphere.position = glm::vec3(110.0f, 0.0f, 0.0f);
  sphere.radius = 20.0f;
  sphere.range = 100.0f;
  EXPECT_GT(localLightWeight(sphere, glm::vec3(0.0f)), 0.0f);
  sphere.radius = 0.0f;
  EXPECT_EQ(localLightWeight(sphere, glm::vec3(0.0f)), 0.0f);
}

/// A sky that is brighter toward +X and +Z, so that every direction has its own radiance.
class GradientSkyPicture : public SkyPicture {
 public:
  glm::vec3 radiance(const glm::vec3& dir) const override {
    return glm::vec3(1.0f + dir.x, 2.0f + dir.z, 0.5f + 0.25f * dir.y);
  }
};

TEST(LightSampler, SkyRadianceLeftForTheCallerIsWhatTheSampleWouldCarry) {
  // Lamps, a sun and a picture sky: sample() without the sky's radiance picks the same light
  // and point with the same pdf; a sky sample's radiance is then 0 and skyRadiance() of its
  // direction gives, bit for bit, what sample() with it carries.
  SkyDesc desc;
  desc.color = glm::vec3(1.0f);
  desc.intensity = 0.8f;
  desc.lightingScale = 1.5f;
  desc.picture = std::make_shared<GradientSkyPicture>();
  const Sky sky(desc, {});
  std::vector<LightDesc> lights = lampAmongDistantLights();
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  sun.intensity = 2.0f;
  lights.push_back(sun);
  Bounds bounds;
  bounds.extend(glm::vec3(-500.0f));
  bounds.extend(glm::vec3(500.0f));
  const LightSampler sampler(lights, {}, sky, bounds);
  const glm::vec3 p(1.0f, 2.0f, 0.0f), n(0.0f, 0.0f, 1.0f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  int skySamples = 0, others = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::vec4 u(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
    LightSample with, without;
    const bool sampled = sampler.sample(p, n, u, with);
    ASSERT_EQ(sampler.sample(p, n, u, without, false), sampled);
    if (!sampled) continue;
    EXPECT_EQ(without.wi, with.wi);
    EXPECT_EQ(without.pdf, with.pdf);
    EXPECT_EQ(without.light.kind, with.light.kind);
    EXPECT_EQ(without.light.index, with.light.index);
    if (with.light.kind == LightPoint::Kind::Sky) {
      ++skySamples;
      EXPECT_EQ(without.radiance, glm::vec3(0.0f));
      EXPECT_EQ(sampler.skyRadiance(with.wi), with.radiance);
      EXPECT_NE(with.radiance, glm::vec3(0.0f));
    } else {
      ++others;
      EXPECT_EQ(without.radiance, with.radiance);
    }
  }
  EXPECT_GT(skySamples, 100);
  EXPECT_GT(others, 100);
}

}  // namespace
}  // namespace pa
