#pragma once
// Two binary BVHs built from the same input must be the same tree, node for node (builds are
// deterministic whatever the thread count or the scratch memory reused).
#include <string>

#include <gtest/gtest.h>

#include "renderer/bvh/binary_bvh.h"

namespace pa::testing {

/// Same leaf order, same node count, and every node the same (range, children, box).
inline void expectSameTree(const bvh_detail::BinaryBvh& a, const bvh_detail::BinaryBvh& b) {
  ASSERT_EQ(a.primIndices, b.primIndices);
  ASSERT_EQ(a.nodeCount, b.nodeCount);
  ASSERT_EQ(a.leafCount, b.leafCount);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i));
    ASSERT_EQ(a.nodes[i].count, b.nodes[i].count);
    ASSERT_EQ(a.nodes[i].first, b.nodes[i].first);
    ASSERT_EQ(a.nodes[i].left, b.nodes[i].left);
    ASSERT_EQ(a.nodes[i].right, b.nodes[i].right);
    ASSERT_EQ(a.nodes[i].bounds.min, b.nodes[i].bounds.min);
    ASSERT_EQ(a.nodes[i].bounds.max, b.nodes[i].bounds.max);
  }
}

}  // namespace pa::testing
