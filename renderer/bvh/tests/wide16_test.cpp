// The 16-wide layout (wide16_bvh.h) against the scalar reference traversal: same hit distances
// bit for bit and the same occlusion answers, with and without alpha-masked (and one-sided) triangles, with
// small and multi-pack leaves; its structure (every triangle in exactly one leaf, boxes that
// contain their triangles, per-octant orders that are permutations); and a Blas on it against a
// Blas on the 8-wide layout, after a build and after a refit. Skipped on CPUs without AVX-512.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/reference_traversal.h"
#include "renderer/bvh/testing/identical_hits.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide16_bvh.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// Alpha test stand-in (as in wide_kernels_test): depends on the triangle and the barycentrics.
bool rejectSome(const void*, uint32_t, uint32_t prim, float u, float, float) { return prim % 3 != 0 && u <= 0.6f; }

Bounds padded(const TestMesh& m) {
  Bounds region = m.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  return region;
}

void expectMatchesReference(TestMesh m, const BvhBuildConfig& config, uint32_t seed, bool masked) {
  if (!wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  if (masked) {
    m.rules.assign(m.triangleCount(), HitRule::Opaque);
    for (uint32_t i = 0; i < m.triangleCount(); ++i)   // and one-sided triangles, back faces culled
      m.rules[i] = i % 2 == 0 ? HitRule::Filtered : i % 4 == 1 ? HitRule::OneSided : HitRule::Opaque;
  }
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  const BinaryBvh binary = buildBinaryBvh(mesh, config);
  Wide16Bvh wide;
  collapseToWide16(binary, mesh, wide);
  const HitFilter filter = masked ? HitFilter{rejectSome, nullptr, FaceCull::Back} : HitFilter{};
  const Tracer wideTracer{[&](Ray& r, Hit& h) {
                            const bool hit = intersectWide16(wide, r, h, filter, 7);
                            EXPECT_TRUE(!hit || h.instance == 7u) << "hit reports instance " << h.instance;
                            return hit;
                          },
                          [&](const Ray& r) { return occludedWide16(wide, r, filter, 7); }};
  const Tracer reference{[&](Ray& r, Hit& h) { return intersectReference(mesh, binary, r, h, filter, 7); },
                         [&](const Ray& r) { return occludedReference(mesh, binary, r, filter, 7); }};
  uint32_t hits = 0;
  expectIdenticalHits(wideTracer, reference, makeRandomRays(padded(m), 100000, seed), hits);
  EXPECT_GT(hits, 2000u);
}

TEST(Wide16, MatchesReferenceOnSoup) { expectMatchesReference(makeTriangleSoup(20000, 61), {}, 1, false); }

TEST(Wide16, MatchesReferenceOnThinTriangles) { expectMatchesReference(makeThinTriangles(20000, 62), {}, 2, false); }

TEST(Wide16, MatchesReferenceOnSphere) { expectMatchesReference(makeSphere(8000), {}, 3, false); }

TEST(Wide16, MatchesReferenceWithAlphaMaskedTriangles) {
  expectMatchesReference(makeTriangleSoup(20000, 63), {}, 4, true);
}

/// Binary leaves of 1..64 triangles: single small packs, merged leaves and multi-pack leaves.
TEST(Wide16, MatchesReferenceForEveryLeafSize) {
  for (uint32_t leaf : {1u, 5u, 16u, 40u, 64u}) {
    SCOPED_TRACE(leaf);
    BvhBuildConfig config;
    config.maxLeafTriangles = leaf;
    config.traversalCost = leaf > 8 ? 8.0f : 0.0f;   // towards the bound
    expectMatchesReference(makeTriangleSoup(5000, 64), config, 10 + leaf, leaf == 40);
  }
}

TEST(Wide16, EveryTriangleInOneLeafInsideItsBoxes) {
  if (!wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  const TestMesh m = makeThinTriangles(30000, 65);
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  BvhBuildConfig config;
  config.maxLeafTriangles = 24;   // some leaves take two 16-wide packs
  config.traversalCost = 4.0f;
  const BinaryBvh binary = buildBinaryBvh(mesh, config);
  Wide16Bvh wide;
  collapseToWide16(binary, mesh, wide);
  std::vector<int> seen(mesh.triangleCount(), 0);
  size_t smallLeaves = 0, largeLeaves = 0;
  // Every triangle of a pack lies inside each box on the path to it.
  std::vector<std::pair<uint32_t, Bounds>> stack{{0u, Bounds{glm::vec3(-1e30f), glm::vec3(1e30f)}}};
  auto checkPack = [&](const auto& pack, const Bounds& box, uint32_t lanes) {
    for (uint32_t lane = 0; lane < lanes; ++lane) {
      if (pack.prim[lane] == kInvalidId) continue;
      ++seen[pack.prim[lane]];
      for (int vtx = 0; vtx < 3; ++vtx)
        for (int axis = 0; axis < 3; ++axis) {
          EXPECT_GE(pack.v[vtx][axis][lane], box.min[axis]);
          EXPECT_LE(pack.v[vtx][axis][lane], box.max[axis]);
        }
    }
  };
  while (!stack.empty()) {
    const auto [index, outer] = stack.back();
    stack.pop_back();
    const Wide16Node& node = wide.nodes[index];
    for (uint32_t octant = 0; octant < 8; ++octant) {
      std::vector<uint32_t> slots;
      for (uint32_t i = 0; i < kWide16Width; ++i) slots.push_back(node.order[i] >> (4 * octant) & 15);
      std::sort(slots.begin(), slots.end());
      for (uint32_t i = 0; i < kWide16Width; ++i) EXPECT_EQ(slots[i], i) << "octant " << octant << " order";
    }
    for (uint32_t slot = 0; slot < kWide16Width; ++slot) {
      Bounds box;
      box.min = {node.bounds[0][0][slot], node.bounds[0][1][slot], node.bounds[0][2][slot]};
      box.max = {node.bounds[1][0][slot], node.bounds[1][1][slot], node.bounds[1][2][slot]};
      if (box.min.x > box.max.x) continue;   // unused
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(box.min[axis], outer.min[axis]);
        EXPECT_LE(box.max[axis], outer.max[axis]);
      }
      const uint32_t ref = node.child[slot];
      if (!(ref & kLeafBit)) {
        stack.push_back({ref, box});
      } else if (ref & kSmallLeafBit) {
        ++smallLeaves;
        checkPack(wide.smallPacks[ref & kFirstPackMask], box, 8);
      } else {
        ++largeLeaves;
        const uint32_t first = ref & kFirstPackMask, count = ((ref & ~kLeafBit) >> kPackCountShift) + 1;
        for (uint32_t p = first; p < first + count; ++p) checkPack(wide.packs[p], box, kWide16Width);
      }
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(seen.size()));
  EXPECT_GT(smallLeaves, 0u);
  EXPECT_GT(largeLeaves, 0u);
}

/// A Blas on the 16-wide layout answers exactly as one on the 8-wide layout, after a build and
/// after a refit (which keeps the layout).
TEST(Wide16, BlasAnswersAsTheEightWideOne) {
  if (!wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  const TestMesh base = makeThinTriangles(20000, 66);
  TestMesh moved = base;
  for (glm::vec3& p : moved.positions) p += 0.01f * glm::vec3(std::sin(5.0f * p.y), 0.0f, std::cos(5.0f * p.x));
  BvhBuildConfig eight, sixteen;
  eight.nodeWidth = 8;
  sixteen.nodeWidth = 16;
  Blas a, b;
  a.build(base.input(), sixteen);
  b.build(base.input(), eight);
  EXPECT_EQ(a.nodeWidth(), 16u);
  EXPECT_EQ(b.nodeWidth(), 8u);
  uint32_t hits = 0;
  expectIdenticalHits(tracerOf(a), tracerOf(b), makeRandomRays(padded(base), 50000, 67), hits);
  EXPECT_GT(hits, 1000u);
  a.refit(moved.positions);
  b.refit(moved.positions);
  EXPECT_EQ(a.nodeWidth(), 16u);
  expectIdenticalHits(tracerOf(a), tracerOf(b), makeRandomRays(padded(base), 50000, 68), hits);
  EXPECT_GT(hits, 1000u);
}

TEST(Wide16, NodeWidthIsValidated) {
  BvhBuildConfig config;
  config.nodeWidth = 4;
  Blas blas;
  const TestMesh m = makeTriangleSoup(100, 69);
  EXPECT_THROW(blas.build(m.input(), config), std::invalid_argument);
  config.nodeWidth = 16;
  config.allowAvx512 = false;   // the 16-wide kernels are AVX-512 kernels
  EXPECT_THROW(blas.build(m.input(), config), std::invalid_argument);
}

}  // namespace
}  // namespace pa::testing
