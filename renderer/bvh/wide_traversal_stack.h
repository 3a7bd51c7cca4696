#pragma once
// Pieces shared by the wide traversal kernels (wide_traversal.cpp for AVX2 / SSE,
// wide_traversal_avx512.cpp): the traversal stack and the leaf reference decoding.
#include <cstdint>

#include "renderer/bvh/wide_bvh.h"

namespace pa::bvh_detail {

/// Bound for the stack: the wide tree is no deeper than the binary one (< 128 levels) and each
/// level pushes at most 7 entries.
inline constexpr int kWideStackSize = 7 * 128 + 1;

/// Traversal stack: child references with, for closest-hit rays, their entry distances.
/// Pushes write eight lanes at once, so the arrays have a lane's worth of slack.
template <bool kWithDistance>
struct TraversalStack {
  alignas(32) uint32_t node[kWideStackSize + kWideWidth];
  alignas(32) float entry[kWithDistance ? kWideStackSize + kWideWidth : 1];
  int top = 0;
};

/// Decodes a leaf reference into its pack range.
inline void leafPacks(uint32_t ref, uint32_t& first, uint32_t& count) {
  first = ref & kFirstPackMask;
  count = ((ref & ~kLeafBit) >> kPackCountShift) + 1;
}

}  // namespace pa::bvh_detail
