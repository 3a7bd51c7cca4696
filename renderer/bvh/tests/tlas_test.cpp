// The Tlas against a brute-force loop over its instances, each in a Tlas of its own (the same
// object-space transform, so the same float operations): the same closest hit (t, instance,
// triangle, barycentrics) and the same occlusion, with one to four levels of instance groups,
// masks included, and instances placed by the identity (the static world, which shadow rays
// take before the tree).
#include <array>
#include <cstdint>
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

/// Counts the candidate hits a filter sees, and accepts them all.
struct CandidateCount {
  uint32_t calls = 0;
  static bool accept(const void* ctx, uint32_t, uint32_t, float, float, float) {
    ++static_cast<CandidateCount*>(const_cast<void*>(ctx))->calls;
    return true;
  }
};

// A scattered instance (marks over a map in one mesh) is in the tree by its pieces' boxes; a ray
// that enters several pieces traces it once: the same hits as its Blas alone, and the filter sees
// each candidate once, with single rays and with packets.
TEST(TlasScattered, TracedOnceWhateverPiecesARayEnters) {
  testing::TestMesh marks;
  for (int i = 0; i < 10; ++i) {
    testing::TestMesh cluster = testing::makeTriangleSoup(8, 70 + i, 0.6f);
    cluster.translate(glm::vec3(float(i % 5) * 6.0f - 12.0f, float(i / 5) * 6.0f - 3.0f, float(i % 3) * 2.0f));
    marks.append(cluster);
  }
  marks.rules.assign(marks.triangleCount(), HitRule::Filtered);
  Blas marksBlas, sphereBlas;
  marksBlas.build(marks.input());
  sphereBlas.build(testing::makeSphere(300, glm::vec3(0.0f), 2.0f).input());
  std::array<Bounds, kMaxBlasPieces> pieces;
  ASSERT_GE(marksBlas.pieceBounds(pieces), 10u);
  // The marks moved by an exact translation (so their object-space rays are the world rays less
  // it, bit for bit), beside two compact movers.
  const glm::vec3 offset(32.0f, -16.0f, 8.0f);
  std::vector<TlasInstance> instances(3);
  instances[0].blas = &marksBlas;
  instances[0].objectToWorld[3] = offset;
  for (int i = 1; i < 3; ++i) {
    instances[i].blas = &sphereBlas;
    instances[i].objectToWorld[3] = offset + glm::vec3(float(i) * 40.0f, 0.0f, 0.0f);
  }
  Tlas tlas, spheres;
  tlas.build(instances);
  spheres.build(std::span(instances).subspan(1));
  // Rays along the rows of marks, so that most cross several pieces.
  std::vector<Ray> rays;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> jitter(-4.0f, 4.0f);
  for (int i = 0; i < 2048; ++i) {
    Ray r;
    r.origin = offset + glm::vec3(-40.0f, jitter(rng), jitter(rng) + 2.0f);
    r.dir = glm::vec3(1.0f, 0.01f * jitter(rng), 0.01f * jitter(rng));
    rays.push_back(r);
  }
  uint32_t hits = 0;
  for (size_t first = 0; first < rays.size(); first += kMaxPacketRays) {
    std::array<Ray, kMaxPacketRays> packet, local;
    std::array<Hit, kMaxPacketRays> packetHits;
    std::array<CandidateCount, kMaxPacketRays> packetCounts;
    std::array<HitFilter, kMaxPacketRays> filters;
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      packet[lane] = rays[first + lane];
      filters[lane] = HitFilter{&CandidateCount::accept, &packetCounts[lane]};
    }
    const uint32_t found = tlas.intersectPacket(packet, packetHits, 0xffffu, ~0u, filters);
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      const Ray& ray = rays[first + lane];
      // The marks alone, in object space, then what the spheres add (no filter on them).
      CandidateCount alone, ours;
      Ray objectRay = ray;
      objectRay.origin -= offset;
      Hit expected;
      bool expectHit = marksBlas.intersect(objectRay, expected, HitFilter{&CandidateCount::accept, &alone});
      Ray rest = ray;
      rest.tmax = objectRay.tmax;
      Hit sphereHit;
      if (spheres.intersect(rest, sphereHit)) expected = sphereHit, expected.instance += 1, expectHit = true;
      Ray single = ray;
      Hit got;
      ASSERT_EQ(tlas.intersect(single, got, ~0u, HitFilter{&CandidateCount::accept, &ours}), expectHit) << first + lane;
      ASSERT_EQ(found >> lane & 1, expectHit ? 1u : 0u) << first + lane;
      if (expectHit) {
        ++hits;
        EXPECT_EQ(got.t, expected.t);
        EXPECT_EQ(got.instance, expected.instance);
        EXPECT_EQ(got.prim, expected.prim);
        EXPECT_EQ(packetHits[lane].t, expected.t);
      }
      // Each candidate once: as many as the marks' Blas saw alone.
      EXPECT_EQ(ours.calls, alone.calls) << first + lane;   // the marks lie nearer than the spheres
      EXPECT_EQ(packetCounts[lane].calls, alone.calls) << first + lane;
    }
  }
  EXPECT_GT(hits, 300u);
}

}  // namespace
}  // namespace pa
