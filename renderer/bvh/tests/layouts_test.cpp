// The wide SIMD layout against the basic binary BVH, refit against rebuild, build determinism
// across thread counts, and the ray origin offset helper.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <tbb/task_arena.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/ray_offset.h"
#include "renderer/bvh/reference_traversal.h"
#include "renderer/bvh/testing/identical_hits.h"
#include "renderer/bvh/tests/same_tree.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"
#include "renderer/bvh/wide_collapse.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// Built layouts of one mesh.
struct Layouts {
  TriangleMesh mesh;
  BinaryBvh binary;
  WideBvh wide;
  explicit Layouts(const TestMesh& m, const BvhBuildConfig& config = {}) : mesh(makeTriangleMesh(m.input())) {
    binary = buildBinaryBvh(triangleBounds(mesh), config);
    wide = collapseToWide(binary, mesh);
  }
};

/// Wide and reference traversals must return the same t bit for bit (same arithmetic); the
/// triangle may differ only on an exact tie.
void expectSameAsReference(const TestMesh& m, const BvhBuildConfig& config, uint32_t seed) {
  const Layouts l(m, config);
  Bounds region = m.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  const std::vector<Ray> rays = makeRandomRays(region, 200000, seed);
  const Tracer wide{[&](Ray& r, Hit& h) { return intersectWide(l.wide, r, h, {}, 0); },
                    [&](const Ray& r) { return occludedWide(l.wide, r, {}, 0); }};
  const Tracer reference{[&](Ray& r, Hit& h) { return intersectReference(l.mesh, l.binary, r, h, {}, 0); },
                         [&](const Ray& r) { return occludedReference(l.mesh, l.binary, r, {}, 0); }};
  uint32_t hits = 0;
  expectIdenticalHits(wide, reference, rays, hits);
  EXPECT_GT(hits, rays.size() / 50);
}

TEST(WideLayout, AgreesWithBasicBvh) {
  expectSameAsReference(makeTriangleSoup(30000, 31), {}, 1);
  expectSameAsReference(makeThinTriangles(30000, 32), {}, 2);
  expectSameAsReference(makeSphere(10000), {}, 3);
}

TEST(WideLayout, AgreesWithBasicBvhForEveryLeafSize) {
  const TestMesh m = makeTriangleSoup(5000, 33);
  for (uint32_t leaf : {1u, 3u, 4u, 5u, 16u, 64u}) {
    BvhBuildConfig config;
    config.maxLeafTriangles = leaf;
    config.traversalCost = 0.0f;   // pushes leaves towards the bound
    expectSameAsReference(m, config, 10 + leaf);
  }
}

TEST(WideLayout, LeavesRespectMaxLeafTriangles) {
  const TestMesh m = makeTriangleSoup(5000, 34);
  for (uint32_t leaf : {1u, 2u, 8u}) {
    BvhBuildConfig config;
    config.maxLeafTriangles = leaf;
    config.traversalCost = 100.0f;   // SAH would like large leaves
    const Layouts l(m, config);
    for (const BinaryNode& n : l.binary.nodes)
      if (n.isLeaf()) {
        EXPECT_LE(n.count, leaf);
      }
  }
}

/// Animated mesh: refit to new positions must give the same hits as a fresh build.
TEST(Refit, EqualsRebuild) {
  const TestMesh base = makeSphere(8000);
  TestMesh moved = base;
  for (glm::vec3& p : moved.positions) p += 0.3f * glm::vec3(std::sin(4.0f * p.y), std::cos(3.0f * p.z), 0.5f * p.x);
  Blas refitted, rebuilt;
  refitted.build(base.input());
  refitted.refit(moved.positions);
  rebuilt.build(moved.input());
  EXPECT_EQ(refitted.bounds().min, rebuilt.bounds().min);
  EXPECT_EQ(refitted.bounds().max, rebuilt.bounds().max);
  const std::vector<Ray> rays = makeRandomRays({glm::vec3(-2.0f), glm::vec3(2.0f)}, 200000, 35);
  uint32_t hits = 0;
  expectIdenticalHits(tracerOf(refitted), tracerOf(rebuilt), rays, hits);
  EXPECT_GT(hits, rays.size() / 10);
  // A rebuilt Blas keeps its collapse plan and refits along it (the wide tree of the build with
  // moved boxes): the same hits too.
  Blas kept;
  kept.build(base.input());
  kept.build(base.input());
  kept.refit(moved.positions);
  uint32_t keptHits = 0;
  expectIdenticalHits(tracerOf(kept), tracerOf(rebuilt), rays, keptHits);
  EXPECT_EQ(keptHits, hits);
  std::vector<glm::vec3> wrongCount(3);
  EXPECT_THROW(refitted.refit(wrongCount), std::invalid_argument);
}

/// A kept Blas reserved like a much larger one afterwards (a pooled slot): the reservation may
/// reallocate the collapse plan's arrays, so the next refit must not collapse along the old plan.
TEST(Refit, AfterReservingLikeALargerBlasEqualsRebuild) {
  const TestMesh small = makeSphere(2000);
  const TestMesh large = makeSphere(60000);
  TestMesh moved = small;
  for (glm::vec3& p : moved.positions) p += 0.2f * glm::vec3(std::sin(3.0f * p.y), 0.0f, std::cos(2.0f * p.x));
  Blas example;
  example.build(large.input());
  example.build(large.input());
  Blas slot, rebuilt;
  slot.build(small.input());
  slot.build(small.input());   // keeps its memory and its plan
  slot.reserveLike(example);
  slot.refit(moved.positions);
  rebuilt.build(moved.input());
  const std::vector<Ray> rays = makeRandomRays({glm::vec3(-2.0f), glm::vec3(2.0f)}, 100000, 36);
  uint32_t hits = 0;
  expectIdenticalHits(tracerOf(slot), tracerOf(rebuilt), rays, hits);
  EXPECT_GT(hits, rays.size() / 10);
}

/// BvhBuildConfig::allowAvx512 = false (the AVX2 kernel, as on CPUs without AVX-512) answers
/// exactly as the default, after a build and after a refit (which keeps the build's kernel).
TEST(Build, KernelChoiceGivesIdenticalHits) {
  const TestMesh base = makeThinTriangles(20000, 52);
  TestMesh moved = base;
  for (glm::vec3& p : moved.positions) p += 0.01f * glm::vec3(std::sin(5.0f * p.y), 0.0f, std::cos(5.0f * p.x));
  BvhBuildConfig avx2Only;
  avx2Only.allowAvx512 = false;
  Blas best, baseline;
  best.build(base.input());
  baseline.build(base.input(), avx2Only);
  Bounds region = base.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  uint32_t hits = 0;
  expectIdenticalHits(tracerOf(best), tracerOf(baseline), makeRandomRays(region, 50000, 53), hits);
  EXPECT_GT(hits, 1000u);
  best.refit(moved.positions);
  baseline.refit(moved.positions);
  expectIdenticalHits(tracerOf(best), tracerOf(baseline), makeRandomRays(region, 50000, 54), hits);
  EXPECT_GT(hits, 1000u);
}

TEST(Build, DeterministicForAnyThreadCount) {
  const TestMesh m = makeTriangleSoup(60000, 36);
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  const std::vector<Bounds> bounds = triangleBounds(mesh);
  BvhBuildConfig config;
  config.parallelThreshold = 1024;
  config.splitBudget = 0.0f;   // the bounds-only build cannot split (presplit_test.cpp covers splitting)
  auto buildWith = [&](int threads) {
    tbb::task_arena arena(threads);
    BinaryBvh out;
    arena.execute([&] { out = buildBinaryBvh(bounds, config); });
    return out;
  };
  const BinaryBvh one = buildWith(1), two = buildWith(2), four = buildWith(4);
  // Building straight from the mesh must give the same tree as from its triangle bounds.
  BinaryBvh fromMesh;
  tbb::task_arena(2).execute([&] { fromMesh = buildBinaryBvh(mesh, config); });
  // Reused scratch memory and output vectors (left over from a larger and a smaller build)
  // must not change the tree either.
  BinaryBuildScratch scratch;
  BinaryBvh reused;
  const TriangleMesh larger = makeTriangleMesh(makeTriangleSoup(90000, 7).input());
  const TriangleMesh smaller = makeTriangleMesh(makeTriangleSoup(500, 8).input());
  tbb::task_arena(2).execute([&] {
    for (const TriangleMesh* m : {&larger, &smaller, &mesh}) buildBinaryBvh(*m, config, scratch, reused);
  });
  for (const BinaryBvh* other : std::initializer_list<const BinaryBvh*>{&two, &four, &fromMesh, &reused})
    expectSameTree(one, *other);
}

/// Bytes of a vector of trivially copyable values, for bit-for-bit layout comparisons.
template <class T>
std::vector<std::byte> bytesOf(const std::vector<T>& v) {
  std::vector<std::byte> out(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size());
  return out;
}

TEST(Collapse, ReusedWorkspaceGivesTheSameLayoutBitForBit) {
  // A workspace that planned larger and smaller trees before gives the layout a fresh collapse
  // gives (the plan's arrays are not zeroed between plans: every entry read must be rewritten).
  const TriangleMesh mesh = makeTriangleMesh(makeTriangleSoup(3000, 21).input());
  const TriangleMesh larger = makeTriangleMesh(makeTriangleSoup(9000, 22).input());
  const TriangleMesh smaller = makeTriangleMesh(makeTriangleSoup(700, 23).input());
  const BinaryBvh binary = buildBinaryBvh(mesh, {});
  WideBvh fresh8, reused8;
  collapseToWide(binary, mesh, fresh8);
  CollapseWorkspace workspace;
  for (const TriangleMesh* m : {&larger, &smaller}) {
    const BinaryBvh other = buildBinaryBvh(*m, {});
    collapseToWide(other, *m, reused8, &workspace);
  }
  collapseToWide(binary, mesh, reused8, &workspace);
  EXPECT_EQ(bytesOf(fresh8.nodes), bytesOf(reused8.nodes));
  EXPECT_EQ(bytesOf(fresh8.packs), bytesOf(reused8.packs));
  if (!wide16Available()) return;   // the 16-wide layout needs AVX-512
  Wide16Bvh fresh16, reused16;
  collapseToWide16(binary, mesh, fresh16);
  for (const TriangleMesh* m : {&larger, &smaller}) {
    const BinaryBvh other = buildBinaryBvh(*m, {});
    collapseToWide16(other, *m, reused16, &workspace);
  }
  collapseToWide16(binary, mesh, reused16, &workspace);
  EXPECT_EQ(bytesOf(fresh16.nodes), bytesOf(reused16.nodes));
  EXPECT_EQ(bytesOf(fresh16.packs), bytesOf(reused16.packs));
  EXPECT_EQ(bytesOf(fresh16.smallPacks), bytesOf(reused16.smallPacks));
}

TEST(Build, ScratchBufferGrowsOnlyAndAlignsHugeBlocks) {
  ScratchBuffer buffer;
  EXPECT_EQ(buffer.capacityBytes(), 0u);
  std::byte* small = buffer.reserve(100);
  ASSERT_NE(small, nullptr);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(small) % 64, 0u);
  EXPECT_EQ(buffer.capacityBytes(), 128u);
  EXPECT_EQ(buffer.reserve(50), small);   // never shrinks or moves for a smaller request
  buffer.reserve(129);                    // growing again: at least doubles
  EXPECT_EQ(buffer.capacityBytes(), 256u);
  // From kHugePagesFrom on: whole 2 MiB pages, 2 MiB aligned, all of it writable.
  const size_t big = size_t(3) << 20;   // 3 MiB, above kHugePagesFrom
  std::byte* huge = buffer.reserve(big);
  ASSERT_NE(huge, nullptr);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(huge) % (size_t(2) << 20), 0u);
  EXPECT_EQ(buffer.capacityBytes(), size_t(4) << 20);
  std::fill_n(huge, buffer.capacityBytes(), std::byte{0x5a});
  EXPECT_EQ(huge[buffer.capacityBytes() - 1], std::byte{0x5a});
  ScratchBuffer moved = std::move(buffer);
  EXPECT_EQ(moved.reserve(big), huge);
  EXPECT_EQ(buffer.capacityBytes(), 0u);
  moved.release();
  EXPECT_EQ(moved.capacityBytes(), 0u);
}

TEST(RayOffset, KnownValuesNearAndFarFromOrigin) {
  // Near the origin the offset is absolute: n / 65536.
  const glm::vec3 near = offsetRayOrigin(glm::vec3(0.0f), glm::vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(near.z, 1.0f / 65536.0f);
  EXPECT_EQ(near.x, 0.0f);
  // Far away it moves by 256 * n ulps in the direction of the normal.
  auto ulps = [](float f, int k) { return std::bit_cast<float>(std::bit_cast<int32_t>(f) + k); };
  const glm::vec3 far = offsetRayOrigin(glm::vec3(1000.0f, -1000.0f, 1000.0f), glm::vec3(1, 1, -1));
  EXPECT_EQ(far.x, ulps(1000.0f, 256));
  EXPECT_EQ(far.y, ulps(-1000.0f, -256));   // magnitude shrinks: moves towards +y
  EXPECT_EQ(far.z, ulps(1000.0f, -256));
  EXPECT_GT(far.y, -1000.0f);
  EXPECT_LT(far.z, 1000.0f);
}

/// Secondary rays leaving offset hit points never re-hit the surface they leave, near the
/// origin and far from it, for reflection and transmission.
TEST(RayOffset, AvoidsSelfIntersection) {
  for (const glm::vec3 offset : {glm::vec3(0.0f), glm::vec3(1e4f, -3e4f, 2e4f), glm::vec3(1e5f, 1e5f, -1e5f)}) {
    TestMesh mesh = makeSphere(20000, offset, 5.0f);
    Blas blas;
    blas.build(mesh.input());
    std::mt19937 rng(37);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::vector<Ray> primary = makeRaysFromPoint(offset + glm::vec3(0.5f, 0.2f, -0.3f), 50000, 38);
    uint32_t selfHits = 0, transmissionMisses = 0, tested = 0;
    for (Ray r : primary) {
      Hit hit;
      if (!blas.intersect(r, hit)) continue;
      ++tested;
      const glm::vec3 a = mesh.positions[mesh.indices[3 * hit.prim]];
      const glm::vec3 b = mesh.positions[mesh.indices[3 * hit.prim + 1]];
      const glm::vec3 c = mesh.positions[mesh.indices[3 * hit.prim + 2]];
      glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
      if (glm::dot(n, r.dir) > 0.0f) n = -n;   // faces the incoming ray (inside)
      const glm::vec3 p = (1.0f - hit.u - hit.v) * a + hit.u * b + hit.v * c;
      // Reflection: a random direction in the hemisphere of n, must not re-hit at t ~ 0.
      glm::vec3 d(u(rng), u(rng), u(rng));
      if (glm::dot(d, n) < 0.0f) d = -d;
      d += 1e-3f * n;
      Ray bounce{offsetRayOrigin(p, n), 0.0f, d, std::numeric_limits<float>::infinity()};
      Hit again;
      if (blas.intersect(bounce, again) && again.prim == hit.prim) ++selfHits;
      // Transmission: through the surface, must leave the sphere (no hit on this triangle).
      Ray through{offsetRayOrigin(p, -n), 0.0f, -d, std::numeric_limits<float>::infinity()};
      if (blas.intersect(through, again) && again.prim == hit.prim) ++transmissionMisses;
    }
    EXPECT_GT(tested, 40000u);
    EXPECT_EQ(selfHits, 0u) << "offset " << offset.x;
    EXPECT_EQ(transmissionMisses, 0u) << "offset " << offset.x;
  }
}

}  // namespace
}  // namespace pa::testing
