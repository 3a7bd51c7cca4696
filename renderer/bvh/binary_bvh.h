#pragma once
// The basic (reference) BVH: a binary tree built with a binned SAH, multithreaded with TBB.
// Every faster layout (the 8-wide SIMD BVH) is converted from it and validated against it.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/presplit.h"
#include "renderer/bvh/scratch_buffer.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/core/bounds.h"

namespace pa::bvh_detail {

/// One node of the binary BVH. Leaves have count > 0 and reference
/// primIndices[first, first + count); inner nodes have count == 0 and two children.
struct BinaryNode {
  Bounds bounds;
  uint32_t first = 0;
  uint32_t count = 0;
  uint32_t left = 0;
  uint32_t right = 0;
  bool isLeaf() const { return count > 0; }
};

/// Binary BVH over primitives given by their bounds. Nodes are in depth-first order: the root
/// is node 0, a left child directly follows its parent, children come after their parents.
struct BinaryBvh {
  std::vector<BinaryNode> nodes;
  std::vector<uint32_t> primIndices;   ///< Leaf order -> input primitive index.
  uint32_t nodeCount = 0;              ///< Nodes (== nodes.size()).
  uint32_t leafCount = 0;              ///< Leaves.
  bool empty() const { return primIndices.empty(); }
};

/// Memory for the binary builder's arrays (primitive references, their partition copy and the
/// nodes in allocation order): one block, kept between builds so a rebuild does not fault in
/// fresh pages.
struct BinaryBuildScratch {
  ScratchBuffer memory;
  PresplitScratch presplit;   ///< Pre-split references (BvhBuildConfig::splitBudget > 0).
  /// The depth-first renumbering's stack of (node, parent to patch).
  std::vector<std::pair<uint32_t, uint32_t>> renumberStack;
  /// Frees the block, the pre-split arrays and the stack.
  void release() {
    memory.release();
    presplit.release();
    renumberStack = {};
  }
};

/// Bytes of BinaryBuildScratch::memory a build over `prims` references uses.
size_t binaryBuildScratchBytes(size_t prims);

/// Builds over primBounds (each must be finite and non-empty). Deterministic: the result does
/// not depend on the number of threads. Runs in the caller's TBB arena. Pre-splitting needs the
/// triangles, so this overload ignores config.splitBudget.
BinaryBvh buildBinaryBvh(std::span<const Bounds> primBounds, const BvhBuildConfig& config);

/// Same, into out (whose vectors are reused) with the given scratch memory: a rebuild over as
/// many boxes as the last allocates nothing.
void buildBinaryBvh(std::span<const Bounds> primBounds, const BvhBuildConfig& config, BinaryBuildScratch& scratch,
                    BinaryBvh& out);

/// Builds over the triangles of mesh, with their bounds taken straight from the vertices (no
/// separate bounds array). With config.splitBudget == 0 the same tree as
/// buildBinaryBvh(triangleBounds(mesh), config); otherwise over pre-split references
/// (presplitTriangles), where a triangle may be listed in several leaves (once per leaf).
BinaryBvh buildBinaryBvh(const TriangleMesh& mesh, const BvhBuildConfig& config);

/// Same as buildBinaryBvh(mesh, config), into out (whose vectors are reused) with the given
/// scratch memory. The config must be valid (validateBuildConfig).
void buildBinaryBvh(const TriangleMesh& mesh, const BvhBuildConfig& config, BinaryBuildScratch& scratch,
                    BinaryBvh& out);

/// Recomputes every reachable node's bounds bottom-up from new primitive bounds.
void refitBinaryBvh(BinaryBvh& bvh, std::span<const Bounds> primBounds);

/// Validates config values; throws std::invalid_argument with the offending field.
void validateBuildConfig(const BvhBuildConfig& config);

}  // namespace pa::bvh_detail
