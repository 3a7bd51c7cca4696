// Known answers of the SAH-optimal collapse (wide_collapse.h) on small hand-made binary trees,
// and its invariants on a built tree.
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_collapse.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// Unit cube at x offset `x`.
Bounds cubeAt(float x) { return {glm::vec3(x, 0.0f, 0.0f), glm::vec3(x + 1.0f, 1.0f, 1.0f)}; }

/// A balanced binary tree over four leaves of `perLeaf` triangles (unit cubes at x = 0, 2, 4, 6),
/// depth-first numbered: 0 = root, 1 = left inner, 2, 3 its leaves, 4 = right inner, 5, 6.
BinaryBvh fourLeafTree(uint32_t perLeaf) {
  BinaryBvh bvh;
  auto inner = [](Bounds b, uint32_t left, uint32_t right) {
    BinaryNode n;
    n.bounds = b;
    n.left = left;
    n.right = right;
    return n;
  };
  auto leaf = [&](float x, uint32_t index) {
    BinaryNode n;
    n.bounds = cubeAt(x);
    n.first = index * perLeaf;
    n.count = perLeaf;
    return n;
  };
  Bounds all = cubeAt(0.0f), left = cubeAt(0.0f), right = cubeAt(4.0f);
  all.extend(cubeAt(6.0f));
  left.extend(cubeAt(2.0f));
  right.extend(cubeAt(6.0f));
  bvh.nodes = {inner(all, 1, 4), inner(left, 2, 3), leaf(0.0f, 0), leaf(2.0f, 1), inner(right, 5, 6), leaf(4.0f, 2),
               leaf(6.0f, 3)};
  for (uint32_t i = 0; i < 4 * perLeaf; ++i) bvh.primIndices.push_back(i);
  bvh.nodeCount = 7;
  bvh.leafCount = 4;
  return bvh;
}

TEST(OptimalCollapse, WideEnoughNodeTakesAllLeaves) {
  const BinaryBvh bvh = fourLeafTree(8);
  CollapseCosts costs;
  costs.width = 4;
  const OptimalCollapse plan(bvh, costs);
  uint32_t children[4];
  ASSERT_EQ(plan.children(0, children), 4u);   // one node over four leaves beats three nodes
  std::sort(children, children + 4);
  EXPECT_EQ(std::vector<uint32_t>(children, children + 4), (std::vector<uint32_t>{2, 3, 5, 6}));
  for (uint32_t c : children) EXPECT_TRUE(plan.isLeaf(c));
}

TEST(OptimalCollapse, BinaryWidthKeepsTheBinaryTree) {
  const BinaryBvh bvh = fourLeafTree(8);
  CollapseCosts costs;
  costs.width = 2;
  costs.maxLeaf = 8;   // no merging of the 8-triangle leaves
  const OptimalCollapse plan(bvh, costs);
  uint32_t children[2];
  ASSERT_EQ(plan.children(0, children), 2u);
  std::sort(children, children + 2);
  EXPECT_EQ(children[0], 1u);
  EXPECT_EQ(children[1], 4u);
  EXPECT_FALSE(plan.isLeaf(1));
  EXPECT_FALSE(plan.isLeaf(4));
}

TEST(OptimalCollapse, CheapLeavesAreMergedUpToTheLeafLimit) {
  // Two leaves of 4 triangles each fit one small leaf (8); a node visit costs far more than
  // testing a pack, so the left pair merges (and so does the right one).
  const BinaryBvh bvh = fourLeafTree(4);
  CollapseCosts costs;
  costs.width = 2;
  costs.node = 10.0f;
  costs.smallLeaf = 1.0f;
  costs.largePack = 100.0f;
  costs.maxLeaf = 8;
  const OptimalCollapse plan(bvh, costs);
  uint32_t children[2];
  ASSERT_EQ(plan.children(0, children), 2u);
  for (uint32_t c : children) {
    EXPECT_TRUE(plan.isLeaf(c));
    EXPECT_EQ(plan.triangleCount(c), 8u);
    std::vector<uint32_t> tris;
    plan.trianglesBelow(c, tris);
    EXPECT_EQ(tris.size(), 8u);
  }
  // With a limit of 4 triangles a leaf cannot merge: back to binary inner nodes.
  costs.maxLeaf = 4;
  const OptimalCollapse limited(bvh, costs);
  ASSERT_EQ(limited.children(0, children), 2u);
  for (uint32_t c : children) EXPECT_FALSE(limited.isLeaf(c));
}

TEST(OptimalCollapse, CoversEveryBinaryLeafOnceWithinTheWidth) {
  const TriangleMesh mesh = makeTriangleMesh(makeTriangleSoup(20000, 71).input());
  const BinaryBvh bvh = buildBinaryBvh(mesh, BvhBuildConfig{});
  for (uint32_t width : {4u, 8u, 16u}) {
    CollapseCosts costs;
    costs.width = width;
    const OptimalCollapse plan(bvh, costs);
    std::vector<int> seen(mesh.triangleCount(), 0);
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
      const uint32_t n = stack.back();
      stack.pop_back();
      std::vector<uint32_t> children(width);
      const uint32_t count = plan.children(n, children.data());
      ASSERT_GE(count, 1u);
      ASSERT_LE(count, width);
      for (uint32_t i = 0; i < count; ++i) {
        if (!plan.isLeaf(children[i])) {
          stack.push_back(children[i]);
          continue;
        }
        EXPECT_LE(plan.triangleCount(children[i]), std::max(costs.maxLeaf, 8u));
        std::vector<uint32_t> tris;
        plan.trianglesBelow(children[i], tris);
        for (uint32_t t : tris) ++seen[t];
      }
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(seen.size())) << "width " << width;
  }
}

}  // namespace
}  // namespace pa::testing
