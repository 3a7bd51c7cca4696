// The bench's "our kernels over Embree's tree" layout: every triangle packed once, and the same
// answers (distance bit for bit) as our own BVH, since only the tree differs.
#include <bit>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bench/embree_tree.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"
#include "renderer/bvh/testing/identical_hits.h"
#include "renderer/bvh/testing/scene_generators.h"

namespace pa::bench {
namespace {

void expectSameHitsAsBlas(const testing::TestMesh& mesh, uint32_t seed, uint32_t minHits,
                          const EmbreeTreeConfig& config = {}) {
  testing::EmbreeDevice device("threads=1");
  const bvh_detail::TriangleMesh triangles = bvh_detail::makeTriangleMesh(mesh.input());
  const bvh_detail::WideBvh tree = buildWideFromEmbreeTree(device.get(), triangles, config);
  ASSERT_FALSE(tree.empty());

  // Every non-degenerate triangle sits in exactly one valid lane (with spatial splits: in one or
  // more, and some in more).
  std::vector<int> seen(triangles.triangleCount(), 0);
  for (const bvh_detail::TrianglePack& pack : tree.packs)
    for (uint32_t lane = 0; lane < bvh_detail::kPackWidth; ++lane)
      if (pack.validBits >> lane & 1) ++seen[pack.prim[lane]];
  uint32_t repeated = 0;
  for (uint32_t tri = 0; tri < triangles.triangleCount(); ++tri) {
    if (triangles.degenerate[tri] || !config.spatialSplits)
      ASSERT_EQ(seen[tri], triangles.degenerate[tri] ? 0 : 1) << "triangle " << tri;
    else
      ASSERT_GE(seen[tri], 1) << "triangle " << tri;
    repeated += seen[tri] > 1;
  }
  if (config.spatialSplits) EXPECT_GT(repeated, 0u) << "no reference was split";

  Blas blas;
  blas.build(mesh.input());
  Bounds region = mesh.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  const testing::Tracer embreeTree{[&](Ray& r, Hit& h) { return bvh_detail::intersectWide(tree, r, h, {}, 0); },
                                   [&](const Ray& r) { return bvh_detail::occludedWide(tree, r, {}, 0); }};
  const testing::Tracer ours{[&](Ray& r, Hit& h) { return blas.intersect(r, h); },
                             [&](const Ray& r) { return blas.occluded(r); }};
  uint32_t hits = 0;
  testing::expectIdenticalHits(embreeTree, ours, testing::makeRandomRays(region, 100000, seed), hits);
  EXPECT_GE(hits, minHits);   // the comparison saw real hits, not only misses
}

TEST(EmbreeTree, SoupHasOurHits) { expectSameHitsAsBlas(testing::makeTriangleSoup(3000, 11), 5, 1000); }

TEST(EmbreeTree, ThinTrianglesHaveOurHits) { expectSameHitsAsBlas(testing::makeThinTriangles(3000, 12), 6, 300); }

TEST(EmbreeTree, SpatialSplitsKeepOurHits) {
  EmbreeTreeConfig splits;
  splits.spatialSplits = true;
  expectSameHitsAsBlas(testing::makeTriangleSoup(3000, 13), 7, 1000, splits);
  expectSameHitsAsBlas(testing::makeThinTriangles(3000, 14), 8, 300, splits);
}

TEST(EmbreeTree, OneTriangleIsOneLeaf) {
  testing::TestMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  testing::EmbreeDevice device("threads=1");
  const bvh_detail::WideBvh tree = buildWideFromEmbreeTree(device.get(), bvh_detail::makeTriangleMesh(mesh.input()));
  ASSERT_EQ(tree.nodes.size(), 1u);
  ASSERT_EQ(tree.packs.size(), 1u);
  Ray ray;
  ray.origin = {0.25f, 0.25f, 1.0f};
  ray.dir = {0.0f, 0.0f, -1.0f};
  Hit hit;
  ASSERT_TRUE(bvh_detail::intersectWide(tree, ray, hit, {}, 0));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
}

}  // namespace
}  // namespace pa::bench
