#pragma once
// Scalar front-to-back traversal of the binary BVH, shared by the reference BLAS traversal
// and the TLAS.
#include <cstdint>
#include <limits>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/slab_test.h"
#include "renderer/core/ray.h"

namespace pa::bvh_detail {

/// Traversal stack size; the builder bounds the tree depth well below it.
inline constexpr int kStackSize = 128;

/// Visits leaves front to back; leafFn(first, count) returns true to stop.
template <typename LeafFn>
void traverseBinary(const BinaryBvh& bvh, const Ray& ray, const float& tmax, LeafFn&& leafFn) {
  if (bvh.empty()) return;
  const SlabRay slab(ray.origin, ray.dir);
  if (slabEntry(slab, bvh.nodes[0].bounds, ray.tmin, tmax) == std::numeric_limits<float>::infinity()) return;
  uint32_t stack[kStackSize];
  int top = 0;
  uint32_t current = 0;
  for (;;) {
    const BinaryNode& node = bvh.nodes[current];
    if (node.isLeaf()) {
      if (leafFn(node.first, node.count)) return;
    } else {
      const float tl = slabEntry(slab, bvh.nodes[node.left].bounds, ray.tmin, tmax);
      const float tr = slabEntry(slab, bvh.nodes[node.right].bounds, ray.tmin, tmax);
      constexpr float inf = std::numeric_limits<float>::infinity();
      if (tl != inf && tr != inf) {
        const bool leftFirst = tl <= tr;
        stack[top++] = leftFirst ? node.right : node.left;
        current = leftFirst ? node.left : node.right;
        continue;
      }
      if (tl != inf) { current = node.left; continue; }
      if (tr != inf) { current = node.right; continue; }
    }
    if (top == 0) return;
    current = stack[--top];
  }
}


}  // namespace pa::bvh_detail
