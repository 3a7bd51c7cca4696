#pragma once
// Pieces shared by the wide traversal kernels (wide_traversal.cpp for AVX2 / SSE and
// wide_traversal_avx512.cpp for the 8- and 16-wide AVX-512 lanes): the traversal stack
// and its culled pop, the acceptance of one pack's candidate hits, and the leaf reference
// decoding.
#include <bit>
#include <cstdint>

#include "renderer/bvh/wide_bvh.h"

namespace pa::bvh_detail {

/// Bound for the stack of a kWidth-wide tree: it is no deeper than the binary one (< 128
/// levels) and each level pushes at most kWidth - 1 entries.
template <uint32_t kWidth>
inline constexpr int kStackSizeFor = int(kWidth - 1) * 128 + 1;

/// Traversal stack: child references with, for closest-hit rays, their entry distances.
/// Pushes write kWidth lanes at once, so the arrays have a register's worth of slack.
template <bool kWithDistance, uint32_t kWidth = kWideWidth>
struct TraversalStack {
  alignas(4 * kWidth) uint32_t node[kStackSizeFor<kWidth> + kWidth];
  alignas(4 * kWidth) float entry[kWithDistance ? kStackSizeFor<kWidth> + kWidth : 1];
  int top = 0;
};

/// For a node where exactly the two children in mask were entered, at the entry distances in
/// entry (one per lane): pushes the farther child and returns the nearer one (the lower lane on
/// a tie, as a SIMD minimum would pick). A branch rather than a SIMD reduction: the CPU
/// speculates past the branch, while the reduction's latency sat between the node test and the
/// next node load (renderer/bvh/README.md, "Choices inside the loop").
inline uint32_t takeNearerOfTwo(const WideNode& node, uint32_t mask, const float* entry,
                                TraversalStack<true>& stack) {
  const int first = std::countr_zero(mask);
  const int second = std::countr_zero(mask & (mask - 1));
  const float firstEntry = entry[first], secondEntry = entry[second];
  const uint32_t firstChild = node.child[first], secondChild = node.child[second];
  const bool firstIsNearer = firstEntry <= secondEntry;
  stack.node[stack.top] = firstIsNearer ? secondChild : firstChild;
  stack.entry[stack.top] = firstIsNearer ? secondEntry : firstEntry;
  ++stack.top;
  return firstIsNearer ? firstChild : secondChild;
}

/// Closest-hit rays: pops the next entry whose entry distance is within cull (the farther ones
/// cannot hold a nearer hit) into current; false when the stack runs empty.
template <uint32_t kWidth>
inline bool popEntryWithin(TraversalStack<true, kWidth>& stack, float cull, uint32_t& current) {
  while (stack.top > 0) {
    --stack.top;
    if (stack.entry[stack.top] <= cull) {
      current = stack.node[stack.top];
      return true;
    }
  }
  return false;
}

/// Accepts the candidate lanes of one pack test (t, u, v per lane, already within [tmin, tmax]
/// when tested) in lane order: a lane behind a nearer hit of the same pack or rejected by the
/// filter (alpha-masked lanes only) is skipped. Closest hit (kAnyHit false) shortens tmax and
/// writes hit for every accepted lane; any hit returns true at the first one.
template <bool kAnyHit, class Pack>
inline bool acceptPackHits(const Pack& pack, unsigned lanes, const float* t, const float* u, const float* v,
                           float& tmax, Hit& hit, const HitFilter& filter, uint32_t instanceId) {
  bool found = false;
  for (; lanes; lanes &= lanes - 1) {
    const int lane = std::countr_zero(lanes);
    if (!(t[lane] <= tmax)) continue;   // a nearer hit earlier in this pack
    if ((pack.maskedBits >> lane & 1) && !filter(instanceId, pack.prim[lane], u[lane], v[lane], t[lane])) continue;
    if constexpr (kAnyHit) {
      return true;
    } else {
      tmax = t[lane];
      hit = {t[lane], u[lane], v[lane], pack.prim[lane], instanceId};
      found = true;
    }
  }
  return found;
}

/// Decodes a leaf reference into its pack range.
inline void leafPacks(uint32_t ref, uint32_t& first, uint32_t& count) {
  first = ref & kFirstPackMask;
  count = ((ref & ~kLeafBit) >> kPackCountShift) + 1;
}

}  // namespace pa::bvh_detail
