// Numerical extremes: far-from-origin and tiny geometry, zero-area triangles, rays parallel to
// faces or along shared edges and through shared vertices, watertightness of closed meshes.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/tests/oracle_compare.h"

namespace pa::testing {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Number of rays from `origin` that escape the closed mesh (hit nothing).
uint64_t countEscapes(const Blas& blas, const glm::vec3& origin, uint32_t rays, uint32_t seed) {
  const std::vector<Ray> set = makeRaysFromPoint(origin, rays, seed);
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, set.size(), 1 << 14), uint64_t(0),
      [&](const tbb::blocked_range<size_t>& r, uint64_t escapes) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
          Ray ray = set[i];
          Hit hit;
          escapes += !blas.intersect(ray, hit);
          escapes += !blas.occluded(set[i]);
        }
        return escapes;
      },
      std::plus<>());
}

TEST(Watertight, NoRayEscapesClosedSphere) {
  const TestMesh sphere = makeSphere(20000);
  Blas blas;
  blas.build(sphere.input());
  EXPECT_EQ(countEscapes(blas, glm::vec3(0.0f), 1u << 20, 21), 0u);
  // Off-centre origins make rays hit edges and vertices at all angles.
  EXPECT_EQ(countEscapes(blas, glm::vec3(0.3f, -0.2f, 0.1f), 1u << 18, 22), 0u);
}

TEST(Watertight, NoRayEscapesAtOffset1e5) {
  const glm::vec3 center(1e5f, -1e5f, 1e5f);
  const TestMesh sphere = makeSphere(20000, center, 10.0f);
  Blas blas;
  blas.build(sphere.input());
  EXPECT_EQ(countEscapes(blas, center, 1u << 20, 23), 0u);
}

TEST(Watertight, RaysThroughSharedEdgesAndVerticesHit) {
  // A fan of 8 triangles around a shared centre vertex in the z = 0 plane (integer coordinates,
  // so the edges are exactly representable), each edge shared by two triangles.
  TestMesh fan;
  fan.positions.push_back({0, 0, 0});
  const glm::vec3 rim[8] = {{4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {-4, 4, 0}, {-4, 0, 0}, {-4, -4, 0}, {0, -4, 0}, {4, -4, 0}};
  for (const glm::vec3& p : rim) fan.positions.push_back(p);
  for (uint32_t i = 0; i < 8; ++i) fan.indices.insert(fan.indices.end(), {0u, 1 + i, 1 + (i + 1) % 8});
  Blas blas;
  blas.build(fan.input());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    // Points on the shared edges (along the axes and diagonals) and the shared centre vertex.
    const float s = 3.0f * std::fabs(u(rng));
    const glm::vec3 onEdge[5] = {{s, 0, 0}, {0, s, 0}, {s, s, 0}, {-s, s, 0}, {0, 0, 0}};
    for (const glm::vec3& target : onEdge) {
      const glm::vec3 from(u(rng) * 10.0f, u(rng) * 10.0f, 5.0f + std::fabs(u(rng)) * 5.0f);
      Ray ray{from, 0.0f, target - from, kInf};
      Hit hit;
      ASSERT_TRUE(blas.intersect(ray, hit)) << "ray through shared edge point (" << target.x << "," << target.y << ")";
      EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
      Ray shadow{from, 0.0f, target - from, 1.0001f};
      EXPECT_TRUE(blas.occluded(shadow));
    }
  }
}

TEST(Parallel, RaysInTheTrianglePlaneReportNoHitCleanly) {
  TestMesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  Blas blas;
  blas.build(quad.input());
  for (const glm::vec3 dir : {glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(0, -1, 0)}) {
    for (const glm::vec3 o : {glm::vec3(-1, 0.5f, 0), glm::vec3(-1, -1, 0), glm::vec3(0.5f, 2, 0), glm::vec3(-1, 0, 0)}) {
      Ray ray{o, 0.0f, dir, kInf};
      Hit hit;
      EXPECT_FALSE(blas.intersect(ray, hit)) << "in-plane ray must not report a hit";
      EXPECT_FALSE(blas.occluded(ray));
    }
  }
  // Just above the plane, parallel: no hit; just through it at a grazing angle: hit.
  Ray above{{-1, 0.5f, 1e-6f}, 0.0f, {1, 0, 0}, kInf};
  Hit hit;
  EXPECT_FALSE(blas.intersect(above, hit));
  Ray grazing{{-1, 0.5f, 1e-3f}, 0.0f, {1, 0, -1e-3f / 1.5f}, kInf};
  ASSERT_TRUE(blas.intersect(grazing, hit));
  EXPECT_NEAR(hit.t, 1.5f, 1e-4f);
}

TEST(Extremes, TinyTrianglesAreHitAtTheirCentroids) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  TestMesh tiny;
  std::vector<glm::vec3> centroids;
  for (uint32_t i = 0; i < 20000; ++i) {
    const glm::vec3 c(u(rng), u(rng), u(rng));
    const glm::vec3 a = c + 1e-6f * glm::vec3(u(rng), u(rng), u(rng));
    const glm::vec3 b = c + 1e-6f * glm::vec3(u(rng), u(rng), u(rng));
    const glm::vec3 d = c + 1e-6f * glm::vec3(u(rng), u(rng), u(rng));
    tiny.positions.insert(tiny.positions.end(), {a, b, d});
    tiny.indices.insert(tiny.indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    centroids.push_back((a + b + d) / 3.0f);
  }
  Blas blas;
  blas.build(tiny.input());
  uint32_t hits = 0, sameTriangle = 0, nondegenerate = 0;
  for (uint32_t i = 0; i < centroids.size(); ++i) {
    const glm::vec3 a = tiny.positions[3 * i], b = tiny.positions[3 * i + 1], c = tiny.positions[3 * i + 2];
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (!(glm::length(n) > 1e-15f)) continue;
    ++nondegenerate;
    const glm::vec3 from = centroids[i] + glm::normalize(n) * 0.5f;
    Ray ray{from, 0.0f, centroids[i] - from, 2.0f};
    Hit hit;
    if (!blas.intersect(ray, hit)) continue;
    ++hits;
    sameTriangle += hit.prim == i || std::fabs(hit.t - 1.0f) > 1e-3f;   // another triangle in front is fine
  }
  // Centroids computed in float can fall a rounding error outside sliver triangles; the bulk
  // must be hit.
  EXPECT_GT(hits, nondegenerate * 99 / 100);
  EXPECT_EQ(sameTriangle, hits);
}

/// Our hits vs Embree's on geometry far from the origin.
void expectOracleAgreementAt(const glm::vec3& offset, float size) {
  TestMesh mesh = makeTriangleSoup(20000, 6, 0.05f);
  for (glm::vec3& p : mesh.positions) p = p * size + offset;
  mesh.append([&] {
    TestMesh s = makeSphere(4000, offset, 0.7f * size);
    return s;
  }());
  Blas blas;
  blas.build(mesh.input());
  EmbreeDevice device;
  EmbreeScene embree(device);
  embree.addMesh(mesh);
  embree.commit();
  Bounds region = mesh.bounds();
  const std::vector<Ray> rays = makeRandomRays(region, 200000, 7);
  OracleTally tally;
  const float scale = glm::length(region.max - region.min);
  for (const Ray& r : rays) {
    Ray a = r, b = r;
    Hit ha, hb;
    const bool hitA = blas.intersect(a, ha), hitB = embree.intersect(b, hb);
    compareClosest(tally, hitA, ha, hitB, hb, scale);
  }
  EXPECT_EQ(tally.unexplained, 0u) << tally.firstProblem;
  EXPECT_GT(tally.hits, rays.size() / 10);
}

TEST(Extremes, FarFromOriginAgreesWithEmbree) {
  expectOracleAgreementAt(glm::vec3(1e5f, 2e5f, -1e5f), 100.0f);
  expectOracleAgreementAt(glm::vec3(1e7f, -1e7f, 1e7f), 1e4f);
}

TEST(Extremes, ZeroAreaTrianglesInALargeMeshNeverHit) {
  TestMesh mesh = makeTriangleSoup(5000, 8);
  const uint32_t firstDegenerate = mesh.triangleCount();
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> targets;
  for (uint32_t i = 0; i < 2000; ++i) {
    // Multiples of 1/64: a, a + d and a + 2d are exact, so the triangle is exactly collinear.
    auto grid = [&] { return std::round(u(rng) * 64.0f) / 64.0f; };
    const glm::vec3 a(grid(), grid(), grid()), d(grid(), grid(), grid());
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {a, a + d, a + 2.0f * d});   // collinear
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
    mesh.indices.insert(mesh.indices.end(), {base, base, base});   // a point
    targets.push_back(a + d);
  }
  Blas blas;
  blas.build(mesh.input());
  for (const glm::vec3& t : targets) {
    for (const glm::vec3& from : {t + glm::vec3(0, 0, 3), t + glm::vec3(3, 1, 0)}) {
      Ray ray{from, 0.0f, t - from, kInf};
      Hit hit;
      if (blas.intersect(ray, hit)) {
        EXPECT_LT(hit.prim, firstDegenerate);
      }
    }
  }
}

}  // namespace
}  // namespace pa::testing

namespace pa::testing {
namespace {

/// Axis-aligned rays whose zero direction components are -0 must hit like +0 ones
/// (the slab test picks near planes by the sign bit, and 1/-0 is -inf).
TEST(Extremes, NegativeZeroDirectionComponentsHit) {
  const std::vector<glm::vec3> positions = {{-1, -1, 5}, {1, -1, 5}, {1, 1, 5}, {-1, 1, 5}};
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  Blas blas;
  blas.build({positions, indices, {}});
  Tlas tlas;
  const TlasInstance instance{&blas, glm::mat4x3(1.0f), 0xffffffffu};
  tlas.build(std::span<const TlasInstance>(&instance, 1));
  for (const glm::vec3 dir : {glm::vec3(-0.0f, -0.0f, 1.0f), glm::vec3(0.0f, -0.0f, 1.0f), glm::vec3(-0.0f, 0.0f, 1.0f)}) {
    Ray ray;
    ray.origin = {0.25f, -0.25f, 0.0f};
    ray.dir = dir;
    Hit hit;
    EXPECT_TRUE(blas.intersect(ray, hit));
    EXPECT_FLOAT_EQ(hit.t, 5.0f);
    EXPECT_TRUE(blas.occluded(Ray{ray.origin, 0.0f, dir, 100.0f}));
    Ray worldRay{ray.origin, 0.0f, dir, std::numeric_limits<float>::infinity()};
    Hit worldHit;
    EXPECT_TRUE(tlas.intersect(worldRay, worldHit));
    EXPECT_TRUE(tlas.occluded(Ray{ray.origin, 0.0f, dir, 100.0f}));
  }
}

}  // namespace
}  // namespace pa::testing
