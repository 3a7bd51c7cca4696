// Known-answer tests of the Blas / Tlas API.
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include <glm/vector_relational.hpp>
#include <gtest/gtest.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/scene_generators.h"

namespace pa {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// One unit right triangle in the z = 0 plane plus one at z = 2.
testing::TestMesh twoTriangles() {
  testing::TestMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
  m.indices = {0, 1, 2, 3, 4, 5};
  return m;
}

TEST(Blas, HitsNearestTriangleWithBarycentrics) {
  const testing::TestMesh m = twoTriangles();
  Blas blas;
  blas.build(m.input());
  EXPECT_EQ(blas.triangleCount(), 2u);
  Ray ray{{0.25f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, kInf};
  Hit hit;
  ASSERT_TRUE(blas.intersect(ray, hit, {}, 7));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_FLOAT_EQ(ray.tmax, 1.0f);
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_EQ(hit.instance, 7u);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.5f);
  // From above, the z = 2 triangle is first; the direction is not normalised: t scales.
  Ray down{{0.25f, 0.25f, 4.0f}, 0.0f, {0, 0, -2}, kInf};
  ASSERT_TRUE(blas.intersect(down, hit));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_EQ(hit.prim, 1u);
}

TEST(Blas, RespectsRayInterval) {
  const testing::TestMesh m = twoTriangles();
  Blas blas;
  blas.build(m.input());
  Ray ray{{0.25f, 0.25f, -1.0f}, 1.5f, {0, 0, 1}, kInf};
  Hit hit;
  ASSERT_TRUE(blas.intersect(ray, hit));
  EXPECT_EQ(hit.prim, 1u);
  Ray shortRay{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, 0.5f};
  EXPECT_FALSE(blas.intersect(shortRay, hit));
  EXPECT_FALSE(blas.occluded(shortRay));
  shortRay.tmax = 1.0f;   // hit exactly at tmax counts
  EXPECT_TRUE(blas.occluded(shortRay));
}

TEST(Blas, InvalidRaysReportNoHit) {
  const testing::TestMesh m = twoTriangles();
  Blas blas;
  blas.build(m.input());
  Hit hit;
  for (const glm::vec3 dir : {glm::vec3(0.0f), glm::vec3(kNaN, 0, 1), glm::vec3(0, 0, kInf)}) {
    Ray ray{{0.25f, 0.25f, -1.0f}, 0.0f, dir, kInf};
    EXPECT_FALSE(blas.intersect(ray, hit));
    EXPECT_FALSE(blas.occluded(ray));
  }
  Ray nanOrigin{{kNaN, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, kInf};
  EXPECT_FALSE(blas.intersect(nanOrigin, hit));
  Ray nanRange{{0.25f, 0.25f, -1.0f}, kNaN, {0, 0, 1}, kInf};
  EXPECT_FALSE(blas.occluded(nanRange));
  EXPECT_FALSE(hit.valid());
}

TEST(Blas, DegenerateTrianglesNeverHit) {
  testing::TestMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2, 0, 0, 0, 0, 1, 1, 0, 3, 4};   // collinear, point, line, point-ish (0 == 3)
  Blas blas;
  blas.build(m.input());
  Hit hit;
  for (const glm::vec3 dir : {glm::vec3(0, 0, 1), glm::vec3(0, 1, 0), glm::vec3(1, 0, 0)}) {
    for (const glm::vec3 o : {glm::vec3(0.5f, 0, -1), glm::vec3(0, 0, -1), glm::vec3(-1, 0, 0), glm::vec3(0.5f, -1, 0)}) {
      Ray ray{o, 0.0f, dir, kInf};
      EXPECT_FALSE(blas.intersect(ray, hit));
      EXPECT_FALSE(blas.occluded(ray));
    }
  }
}

TEST(Blas, RejectsBadInput) {
  std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<uint32_t> ok = {0, 1, 2}, outOfRange = {0, 1, 3}, notTriples = {0, 1};
  Blas blas;
  EXPECT_THROW(blas.build({p, outOfRange, {}}), std::invalid_argument);
  EXPECT_THROW(blas.build({p, notTriples, {}}), std::invalid_argument);
  std::vector<HitRule> wrongCount = {HitRule::Filtered, HitRule::Opaque};
  EXPECT_THROW(blas.build({p, ok, wrongCount}), std::invalid_argument);
  std::vector<HitRule> unknown = {static_cast<HitRule>(3)};
  EXPECT_THROW(blas.build({p, ok, unknown}), std::invalid_argument);
  p[1].y = kNaN;
  EXPECT_THROW(blas.build({p, ok, {}}), std::invalid_argument);
  p[1].y = kInf;
  EXPECT_THROW(blas.build({p, ok, {}}), std::invalid_argument);
  BvhBuildConfig bad;
  bad.binCount = 1;
  p[1].y = 0.0f;
  EXPECT_THROW(blas.build({p, ok, {}}, bad), std::invalid_argument);
}

// Two Blas over the same triangles answer 2000 random rays alike (closest hit and occlusion),
// more than 100 of which hit.
void expectSameHits(const Blas& expected, const Blas& actual, uint32_t seed) {
  const std::vector<Ray> rays = testing::makeRandomRays(expected.bounds(), 2000, seed);
  uint32_t hits = 0;
  for (const Ray& ray : rays) {
    Ray a = ray, b = ray;
    Hit ha, hb;
    const bool hitA = expected.intersect(a, ha);
    ASSERT_EQ(hitA, actual.intersect(b, hb));
    ASSERT_EQ(ha.prim, hb.prim);
    ASSERT_EQ(ha.t, hb.t);
    ASSERT_EQ(expected.occluded(ray), actual.occluded(ray));
    hits += hitA;
  }
  EXPECT_GT(hits, 100u);
}

TEST(Blas, RebuildGivesTheSameHitsAsAFreshBuild) {
  // A rebuilt Blas reuses its previous build's memory; different sizes in between (and an
  // empty mesh) must not leave anything behind.
  const testing::TestMesh target = testing::makeTriangleSoup(3000, 11);
  Blas fresh, rebuilt;
  fresh.build(target.input());
  for (uint32_t count : {20000u, 0u, 100u, 3000u}) rebuilt.build(testing::makeTriangleSoup(count, 12).input());
  rebuilt.build(target.input());
  ASSERT_EQ(rebuilt.triangleCount(), 3000u);
  EXPECT_EQ(rebuilt.bounds().min, fresh.bounds().min);
  EXPECT_EQ(rebuilt.bounds().max, fresh.bounds().max);
  expectSameHits(fresh, rebuilt, 13);
}

TEST(Blas, ReservedLikeALargerBlasBuildsTheSameHits) {
  // reserveLike only gives memory: builds after it (smaller, as large, and of an empty or a
  // never-built example) answer as a fresh build.
  const testing::TestMesh large = testing::makeTriangleSoup(5000, 21);
  const testing::TestMesh target = testing::makeTriangleSoup(3000, 22);
  Blas example, fresh, reserved, emptyExample;
  example.build(large.input());
  example.build(large.input());   // rebuilt: it keeps its build memory, as dynamic meshes do
  fresh.build(target.input());
  reserved.reserveLike(emptyExample);
  reserved.reserveLike(example);
  reserved.build(testing::makeTriangleSoup(100, 23).input());
  reserved.build(target.input());
  expectSameHits(fresh, reserved, 24);
}

TEST(Blas, BadInputLeavesTheBuiltBlasUnchanged) {
  testing::TestMesh m = twoTriangles();
  Blas blas;
  blas.build(m.input());
  std::vector<uint32_t> outOfRange = {0, 1, 9};
  EXPECT_THROW(blas.build({m.positions, outOfRange, {}}), std::invalid_argument);
  ASSERT_EQ(blas.triangleCount(), 2u);
  Ray ray;
  ray.origin = {0.25f, 0.25f, 5.0f};
  ray.dir = {0, 0, -1};
  Hit hit;
  ASSERT_TRUE(blas.intersect(ray, hit));
  EXPECT_EQ(hit.prim, 1u);
  EXPECT_FLOAT_EQ(hit.t, 3.0f);
}

TEST(Blas, EmptyMeshNeverHits) {
  Blas blas;
  blas.build({});
  Ray ray;
  Hit hit;
  EXPECT_FALSE(blas.intersect(ray, hit));
  EXPECT_TRUE(blas.bounds().empty());
  Blas unbuilt;
  EXPECT_FALSE(unbuilt.occluded(ray));
}

TEST(Blas, MaskedTrianglesGoThroughFilter) {
  testing::TestMesh m = twoTriangles();
  m.rules = {HitRule::Filtered, HitRule::Opaque};   // the near triangle is alpha tested
  Blas blas;
  blas.build(m.input());
  auto rejectAll = [](const void*, uint32_t, uint32_t, float, float, float) { return false; };
  HitFilter reject{+rejectAll, nullptr};
  Ray ray{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, kInf};
  Hit hit;
  ASSERT_TRUE(blas.intersect(ray, hit, reject));
  EXPECT_EQ(hit.prim, 1u);   // continued past the rejected hit
  Ray shortRay{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, 2.0f};
  EXPECT_FALSE(blas.occluded(shortRay, reject));
  EXPECT_TRUE(blas.occluded(shortRay));
  // The filter sees the candidate's ids, barycentrics and distance.
  struct Seen { uint32_t instance = 0, prim = 0; float u = 0, v = 0, t = 0; } seen;
  auto record = [](const void* ctx, uint32_t instance, uint32_t prim, float u, float v, float t) {
    auto* s = const_cast<Seen*>(static_cast<const Seen*>(ctx));
    *s = {instance, prim, u, v, t};
    return true;
  };
  Ray again{{0.25f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, kInf};
  ASSERT_TRUE(blas.intersect(again, hit, HitFilter{+record, &seen}, 3));
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_EQ(seen.instance, 3u);
  EXPECT_EQ(seen.prim, 0u);
  EXPECT_FLOAT_EQ(seen.u, 0.25f);
  EXPECT_FLOAT_EQ(seen.v, 0.5f);
  EXPECT_EQ(seen.t, hit.t);   // the distance the accepted hit then has
}

// A frame's marks over a map: small clusters far apart. Their pieces hold every triangle and are
// much smaller than the mesh's box; a compact mesh has none.
TEST(Blas, PieceBoundsHoldEveryTriangleOfAScatteredMesh) {
  testing::TestMesh marks;
  for (int i = 0; i < 12; ++i) {
    testing::TestMesh cluster = testing::makeTriangleSoup(6, 40 + i, 0.5f);
    cluster.translate(glm::vec3(float(i % 3) * 300.0f, float(i / 3 % 2) * 200.0f, float(i / 6) * 150.0f));
    marks.append(cluster);
  }
  Blas blas;
  blas.build(marks.input());
  std::array<Bounds, kMaxBlasPieces + 4> pieces;
  const size_t count = blas.pieceBounds(pieces);
  ASSERT_GE(count, 12u);   // at least one piece per cluster
  ASSERT_LE(count, kMaxBlasPieces);
  float area = 0.0f;
  for (size_t p = 0; p < count; ++p) area += pieces[p].halfArea();
  EXPECT_LT(area, 0.01f * blas.bounds().halfArea());
  for (uint32_t t = 0; t < marks.triangleCount(); ++t) {
    bool held = false;
    for (size_t p = 0; p < count && !held; ++p) {
      held = true;
      for (int corner = 0; corner < 3; ++corner) {
        const glm::vec3& v = marks.positions[marks.indices[3 * t + corner]];
        held = held && glm::all(glm::greaterThanEqual(v, pieces[p].min)) && glm::all(glm::lessThanEqual(v, pieces[p].max));
      }
    }
    EXPECT_TRUE(held) << "triangle " << t << " lies in no piece";
  }
  EXPECT_EQ(blas.pieceBounds(std::span(pieces).first(1)), 0u);   // one box is the mesh's own
  Blas sphere;
  sphere.build(testing::makeSphere(500).input());
  EXPECT_EQ(sphere.pieceBounds(pieces), 0u);
  EXPECT_EQ(Blas{}.pieceBounds(pieces), 0u);
}

TEST(Tlas, InstancesTransformMaskAndWorldT) {
  const testing::TestMesh m = twoTriangles();
  Blas blas;
  blas.build(m.input());
  // Instance 0: moved to z = 10 and scaled by 2; instance 1: identity, mask bit 2 only.
  glm::mat4x3 moved(2.0f);
  moved[3] = glm::vec3(0, 0, 10);
  const std::vector<TlasInstance> instances = {{&blas, moved, 0x1u}, {&blas, glm::mat4x3(1.0f), 0x2u}};
  Tlas tlas;
  tlas.build(instances);
  Ray ray{{0.5f, 0.5f, 20.0f}, 0.0f, {0, 0, -1}, kInf};
  Hit hit;
  ASSERT_TRUE(tlas.intersect(ray, hit));
  EXPECT_FLOAT_EQ(hit.t, 6.0f);   // top triangle of instance 0 at world z = 14
  EXPECT_EQ(hit.instance, 0u);
  EXPECT_EQ(hit.prim, 1u);
  Ray masked{{0.25f, 0.25f, 20.0f}, 0.0f, {0, 0, -1}, kInf};
  ASSERT_TRUE(tlas.intersect(masked, hit, 0x2u));
  EXPECT_EQ(hit.instance, 1u);
  EXPECT_FLOAT_EQ(hit.t, 18.0f);
  EXPECT_FALSE(tlas.occluded(masked, 0x4u));
  EXPECT_TRUE(tlas.occluded(masked, 0x1u));
  EXPECT_FLOAT_EQ(tlas.bounds().max.z, 14.0f);
}

TEST(Tlas, FilterSeesWorldDistancesInScaledInstances) {
  testing::TestMesh m = twoTriangles();
  m.rules = {HitRule::Filtered, HitRule::Filtered};
  Blas blas;
  blas.build(m.input());
  glm::mat4x3 moved(2.0f);   // scaled by 2, at z = 10: the triangles at world z = 10 and 14
  moved[3] = glm::vec3(0, 0, 10);
  const std::vector<TlasInstance> instances = {{&blas, moved, 0x1u}};
  Tlas tlas;
  tlas.build(instances);
  // Rejects every candidate and records its distance.
  auto record = [](const void* ctx, uint32_t, uint32_t prim, float, float, float t) {
    (*const_cast<std::array<float, 2>*>(static_cast<const std::array<float, 2>*>(ctx)))[prim] = t;
    return false;
  };
  std::array<float, 2> seen{};
  Ray ray{{0.5f, 0.5f, 20.0f}, 0.0f, {0, 0, -0.5f}, kInf};   // a direction of length 1/2
  Hit hit;
  EXPECT_FALSE(tlas.intersect(ray, hit, ~0u, HitFilter{+record, &seen}));
  EXPECT_FLOAT_EQ(seen[1], 12.0f);
  EXPECT_FLOAT_EQ(seen[0], 20.0f);
  std::array<Ray, 4> rays;
  std::array<Hit, 4> hits;
  std::array<std::array<float, 2>, 4> seenByRay{};
  std::array<HitFilter, 4> filters;
  for (uint32_t i = 0; i < 4; ++i) {
    rays[i] = Ray{{0.1f + 0.1f * float(i), 0.2f, 20.0f}, 0.0f, {0, 0, -0.5f}, kInf};
    filters[i] = HitFilter{+record, &seenByRay[i]};
  }
  EXPECT_EQ(tlas.intersectPacket(rays, hits, 0xfu, ~0u, filters), 0u);
  for (const auto& s : seenByRay) {
    EXPECT_FLOAT_EQ(s[1], 12.0f);
    EXPECT_FLOAT_EQ(s[0], 20.0f);
  }
}

TEST(Tlas, RejectsBadInstances) {
  Blas blas;
  const testing::TestMesh m = twoTriangles();
  blas.build(m.input());
  Tlas tlas;
  std::vector<TlasInstance> nullBlas = {{nullptr, glm::mat4x3(1.0f), 1u}};
  EXPECT_THROW(tlas.build(nullBlas), std::invalid_argument);
  std::vector<TlasInstance> singular = {{&blas, glm::mat4x3(0.0f), 1u}};
  EXPECT_THROW(tlas.build(singular), std::invalid_argument);
  glm::mat4x3 nan(1.0f);
  nan[3].x = kNaN;
  std::vector<TlasInstance> nonFinite = {{&blas, nan, 1u}};
  EXPECT_THROW(tlas.build(nonFinite), std::invalid_argument);
}

}  // namespace
}  // namespace pa
