// SAH-optimal choice of the wide tree over the binary BVH (see wide_collapse.h).
#include "renderer/bvh/wide_collapse.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pa::bvh_detail {

void OptimalCollapse::reserve(size_t nodes, uint32_t width) {
  binary_ = nullptr;   // the arrays below may be reallocated without their contents
  plannedNodes_ = 0;
  subtreeCost_.ensure(nodes * width);
  leavesBelow_.ensure(nodes);
  leftSlots_.ensure(nodes * width);
  usedSlots_.ensure(nodes * width);
  leaf_.ensure(nodes);
  count_.ensure(nodes);
  distributedLeftW_.ensure(nodes);
}

void OptimalCollapse::plan(const BinaryBvh& binary, const CollapseCosts& costs) {
  if (costs.width < 2 || costs.width > 64) throw std::invalid_argument("collapse width must be in [2, 64]");
  binary_ = &binary;
  plannedNodes_ = 0;   // set when the plan is complete
  width_ = costs.width;
  const size_t n = binary.nodes.size();
  const uint32_t w = width_;
  // Every entry the sweep below writes before it is read (no zero fill: these are the largest
  // arrays of the collapse); the slot arrays are read for inner nodes only.
  float* const subtreeCost = subtreeCost_.ensure(n * w);
  uint32_t* const leaves = leavesBelow_.ensure(n);
  leftSlots_.ensure(n * w);
  usedSlots_.ensure(n * w);
  leaf_.ensure(n);
  count_.ensure(n);
  distributedLeftW_.ensure(n);
  constexpr float inf = std::numeric_limits<float>::infinity();
  float distributed[65];
  uint8_t distributedLeft[65];
  // Children come after their parents (depth-first order): a reverse sweep sees them first.
  for (size_t i = n; i-- > 0;) {
    const BinaryNode& node = binary.nodes[i];
    const float area = node.bounds.halfArea();
    float* cost = &subtreeCost[i * w];
    uint8_t* leftSlots = &leftSlots_[i * w];
    uint8_t* used = &usedSlots_[i * w];
    if (node.isLeaf()) {
      count_[i] = node.count;
    } else {
      count_[i] = count_[node.left] + count_[node.right];
    }
    const uint32_t tris = count_[i];
    float leafCost = inf;
    if (node.isLeaf() || tris <= costs.maxLeaf) {
      leafCost = tris <= costs.smallLeafMax ? area * costs.smallLeaf
                                            : area * costs.largePack * float((tris + costs.packWidth - 1) / costs.packWidth);
    }
    distributedLeftW_[i] = 1;
    if (node.isLeaf()) {
      leaves[i] = 1;
      leaf_[i] = 1;
      std::fill_n(cost, w, leafCost);
      continue;
    }
    const float* left = &subtreeCost[size_t(node.left) * w];
    const float* right = &subtreeCost[size_t(node.right) * w];
    // A subtree never gains from more slots than it has binary leaves (its costs stay level
    // from there on), so the slot counts are bounded by the leaves below: exact, and it skips
    // most of the search near the leaves, where most nodes are.
    const uint32_t leftLeaves = leaves[node.left], rightLeaves = leaves[node.right];
    leaves[i] = leftLeaves + rightLeaves;
    const uint32_t maxSlots = std::min(w, leaves[i]);
    for (uint32_t j = 2; j <= w; ++j) {
      if (j > maxSlots) {
        distributed[j] = distributed[maxSlots];
        distributedLeft[j] = distributedLeft[maxSlots];
        continue;
      }
      float best = inf;
      uint8_t bestK = 1;
      const uint32_t kEnd = std::min(j - 1, leftLeaves);
      for (uint32_t k = j > rightLeaves ? j - rightLeaves : 1; k <= kEnd; ++k) {
        const float c = left[k - 1] + right[j - k - 1];
        if (c < best) {
          best = c;
          bestK = static_cast<uint8_t>(k);
        }
      }
      distributed[j] = best;
      distributedLeft[j] = bestK;
    }
    const float internalCost = area * costs.node + distributed[w];
    leaf_[i] = leafCost <= internalCost;
    cost[0] = std::min(leafCost, internalCost);
    // Slot counts 2..w: n split between its children, unless n as one slot is cheaper.
    leftSlots[0] = 0;
    used[0] = 1;
    for (uint32_t j = 2; j <= w; ++j) {
      if (distributed[j] < cost[j - 2]) {
        cost[j - 1] = distributed[j];
        leftSlots[j - 1] = distributedLeft[j];
        used[j - 1] = static_cast<uint8_t>(j);
      } else {
        cost[j - 1] = cost[j - 2];
        leftSlots[j - 1] = leftSlots[j - 2];
        used[j - 1] = used[j - 2];
      }
    }
    distributedLeftW_[i] = distributedLeft[w];   // for children(): n's own wide node
  }
  plannedNodes_ = binary.nodeCount;
}

void OptimalCollapse::collect(uint32_t n, uint32_t slots, uint32_t* out, uint32_t& count) const {
  const size_t e = size_t(n) * width_ + slots - 1;
  if (binary_->nodes[n].isLeaf() || leftSlots_[e] == 0) {
    out[count++] = n;
    return;
  }
  const uint32_t k = leftSlots_[e];
  collect(binary_->nodes[n].left, k, out, count);
  collect(binary_->nodes[n].right, usedSlots_[e] - k, out, count);
}

uint32_t OptimalCollapse::children(uint32_t n, uint32_t* out) const {
  uint32_t count = 0;
  const BinaryNode& node = binary_->nodes[n];
  if (node.isLeaf()) {
    out[count++] = n;
  } else {
    const uint32_t k = distributedLeftW_[n];
    collect(node.left, k, out, count);
    collect(node.right, width_ - k, out, count);
  }
  // Decreasing box area, ties in collection order: a stable insertion sort (at most 64 entries,
  // and std::stable_sort would allocate a buffer on every call).
  float area[64];
  for (uint32_t i = 0; i < count; ++i) area[i] = binary_->nodes[out[i]].bounds.halfArea();
  for (uint32_t i = 1; i < count; ++i) {
    const uint32_t node = out[i];
    const float key = area[i];
    uint32_t at = i;
    for (; at > 0 && area[at - 1] < key; --at) {
      out[at] = out[at - 1];
      area[at] = area[at - 1];
    }
    out[at] = node;
    area[at] = key;
  }
  return count;
}

void OptimalCollapse::trianglesBelow(uint32_t n, std::vector<uint32_t>& out) const {
  const BinaryNode& node = binary_->nodes[n];
  if (node.isLeaf()) {
    out.insert(out.end(), binary_->primIndices.begin() + node.first, binary_->primIndices.begin() + node.first + node.count);
    return;
  }
  trianglesBelow(node.left, out);   // a leaf slot holds <= maxLeaf triangles: shallow
  trianglesBelow(node.right, out);
}

void OptimalCollapse::trianglesBelow(uint32_t n, std::span<uint32_t> out, uint32_t& count) const {
  const BinaryNode& node = binary_->nodes[n];
  if (node.isLeaf()) {
    if (count + node.count > out.size()) throw std::invalid_argument("BVH leaf too large for the wide layout");
    std::copy_n(binary_->primIndices.begin() + node.first, node.count, out.begin() + count);
    count += node.count;
    return;
  }
  trianglesBelow(node.left, out, count);
  trianglesBelow(node.right, out, count);
}

}  // namespace pa::bvh_detail
