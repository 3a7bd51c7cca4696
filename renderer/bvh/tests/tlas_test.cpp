// The Tlas against a brute-force loop over its instances, each in a Tlas of its own (the same
// object-space transform, so the same float operations): the same closest hit (t, instance,
// triangle, barycentrics) and the same occlusion, with one to four levels of instance groups,
// masks included, and instances placed by the identity (the static world, which shadow rays
// take before the tree).
#include <limits>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/scene_generators.h"

namespace pa {
namespace {

/// One single-instance Tlas per instance.
std::vector<Tlas> oneTlasEach(const std::vector<TlasInstance>& instances) {
  std::vector<Tlas> out(instances.size());
  for (size_t i = 0; i < instances.size(); ++i) out[i].build(std::span<const TlasInstance>(&instances[i], 1));
  return out;
}

/// Closest hit over every instance in index order, each traced through its own Tlas.
bool bruteForceClosest(const std::vector<Tlas>& single, Ray ray, Hit& hit, uint32_t rayMask) {
  bool found = false;
  for (uint32_t i = 0; i < single.size(); ++i) {
    Hit h;
    if (single[i].intersect(ray, h, rayMask)) {
      hit = h;
      hit.instance = i;
      found = true;
    }
  }
  return found;
}

class TlasAgainstBruteForce : public ::testing::TestWithParam<uint32_t> {};

TEST_P(TlasAgainstBruteForce, SameClosestHitsAndOcclusion) {
  const uint32_t instanceCount = GetParam();
  std::mt19937 rng(1234 + instanceCount);
  const testing::TestMesh soup = testing::makeTriangleSoup(400, 7, 0.2f);
  const testing::TestMesh sphere = testing::makeSphere(200);
  Blas soupBlas, sphereBlas;
  soupBlas.build(soup.input());
  sphereBlas.build(sphere.input());
  std::vector<TlasInstance> instances;
  for (uint32_t i = 0; i < instanceCount; ++i) {
    TlasInstance instance;
    instance.blas = i % 3 == 0 ? &sphereBlas : &soupBlas;
    // Two instances placed by the identity (where there are that many), a soup and a sphere: the
    // larger box is the world, and rays of mask 0x5 take neither.
    instance.objectToWorld = i == 1 || i == 3 ? glm::mat4x3(1.0f) : testing::makeRandomTransform(rng, 6.0f);
    instance.mask = 1u << (i % 4);
    instances.push_back(instance);
  }
  Tlas tlas;
  tlas.build(instances);
  const std::vector<Tlas> single = oneTlasEach(instances);
  const std::vector<Ray> rays = testing::makeRandomRays(tlas.bounds(), 3000, 99 + instanceCount);
  uint32_t hits = 0;
  for (size_t r = 0; r < rays.size(); ++r) {
    const uint32_t rayMask = r % 5 == 0 ? 0x5u : 0xffffffffu;
    Ray ours = rays[r];
    Hit expected, got;
    const bool expectHit = bruteForceClosest(single, rays[r], expected, rayMask);
    ASSERT_EQ(tlas.intersect(ours, got, rayMask), expectHit) << "ray " << r;
    if (expectHit) {
      ++hits;
      EXPECT_EQ(got.t, expected.t) << "ray " << r;
      EXPECT_EQ(got.instance, expected.instance) << "ray " << r;
      EXPECT_EQ(got.prim, expected.prim) << "ray " << r;
      EXPECT_EQ(got.u, expected.u) << "ray " << r;
      EXPECT_EQ(got.v, expected.v) << "ray " << r;
      EXPECT_EQ(ours.tmax, expected.t) << "ray " << r;
      // Occluded up to just past the hit, not up to just short of it.
      Ray past = rays[r];
      past.tmax = expected.t * 1.001f;
      EXPECT_TRUE(tlas.occluded(past, rayMask)) << "ray " << r;
      Ray shortOf = rays[r];
      shortOf.tmax = expected.t * 0.999f;
      Hit none;
      EXPECT_EQ(tlas.occluded(shortOf, rayMask), bruteForceClosest(single, shortOf, none, rayMask)) << "ray " << r;
    } else {
      EXPECT_FALSE(tlas.occluded(rays[r], rayMask)) << "ray " << r;
    }
  }
  EXPECT_GT(hits, rays.size() / 50);   // the comparison saw hits, not only misses
}

// One group of 8 lanes (1..8 instances, partly filled included), two levels (9..64), three (65..512)
// and four (600: groups of groups of groups).
INSTANTIATE_TEST_SUITE_P(InstanceCounts, TlasAgainstBruteForce,
                         ::testing::Values(1u, 7u, 8u, 9u, 64u, 65u, 200u, 512u, 600u));

}  // namespace
}  // namespace pa
