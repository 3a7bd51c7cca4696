// Binned SAH build of the reference binary BVH.
//
// Costs: SAH counts triangles in blocks of eight (the leaf packs of the wide layout), so a
// leaf of 1..8 triangles costs one pack test. Leaves hold at most maxLeafTriangles.
// Parallelism: large ranges bin in parallel (tbb::parallel_reduce; min/max/count merges are
// exact and order independent) and their two children are built as parallel tasks. Nodes are
// allocated in pairs from an atomic counter while building, then renumbered depth-first, so
// the tree and its layout are identical whatever the thread count.
#include "renderer/bvh/binary_bvh.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdlib>
#include <memory>
#include <cmath>
#include <limits>
#include <new>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include "renderer/core/reuse.h"

namespace pa::bvh_detail {
namespace {

constexpr uint32_t kMaxBins = 64;
constexpr uint32_t kBinGrain = 4096;   // primitives per parallel binning task
constexpr uint32_t kTwoBinSetsFrom = 256;   // ranges this large bin into two interleaved bin sets
constexpr uint32_t kSahBlock = 8;      // triangles per leaf pack (kPackWidth of the wide layout)
// Past this depth splits are object medians, so the depth stays below kMaxSahDepth + 32 and
// traversal stacks of 128 levels cannot overflow even for pathological inputs.
constexpr uint32_t kMaxSahDepth = 64;
constexpr float kMaxSplitBudget = 4.0f;   // extra references per triangle, at most

/// Box as two SSE registers (x, y, z, unused).
struct Box {
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  void extend(__m128 p) { lo = _mm_min_ps(lo, p); hi = _mm_max_ps(hi, p); }
  void extend(const Box& b) { lo = _mm_min_ps(lo, b.lo); hi = _mm_max_ps(hi, b.hi); }
  Bounds toBounds() const {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    Bounds b;
    b.min = {l[0], l[1], l[2]};
    b.max = {h[0], h[1], h[2]};
    return b;
  }
  float halfArea() const {
    alignas(16) float d[4];
    _mm_store_ps(d, _mm_sub_ps(hi, lo));
    if (!(d[0] >= 0.0f)) return 0.0f;   // empty
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
  }
};

inline __m128 load3(const glm::vec3& v) { return _mm_setr_ps(v.x, v.y, v.z, 0.0f); }

/// A primitive's box with its index in lane 3 of `lo` (as raw bits). The builder partitions
/// these in place, so binning and partitioning stream through memory.
struct PrimRef {
  __m128 lo, hi;
  uint32_t prim() const { return static_cast<uint32_t>(_mm_extract_ps(lo, 3)); }
  /// Twice the centroid (lane 3 unused); the factor 2 cancels in the bin mapping.
  __m128 centroid2() const { return _mm_add_ps(lo, hi); }
  Box box() const { return {lo, hi}; }
};

/// One bin; no default member initialisers, so a BinSet only initialises the bins it uses.
struct Bin {
  Box box;
  uint32_t count;
};

/// Bins along all three axes for one range (only the first binCount of each axis are used).
struct BinSet {
  uint32_t binCount;
  union {   // left uninitialised beyond binCount: small nodes use few bins
    Bin bins[3][kMaxBins];
  };
  explicit BinSet(uint32_t n) : binCount(n) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < binCount; ++i) {
        new (&bins[a][i].box) Box();
        bins[a][i].count = 0;
      }
  }
  BinSet(const BinSet& o) : binCount(o.binCount) {
    for (int a = 0; a < 3; ++a) std::copy_n(o.bins[a], binCount, bins[a]);
  }
  BinSet& operator=(const BinSet& o) {
    binCount = o.binCount;
    for (int a = 0; a < 3; ++a) std::copy_n(o.bins[a], binCount, bins[a]);
    return *this;
  }
  /// Counts of bin i on the three axes (lanes 0..2).
  friend __m128i binCounts(const BinSet& set, uint32_t i) {
    return _mm_setr_epi32(int(set.bins[0][i].count), int(set.bins[1][i].count), int(set.bins[2][i].count), 0);
  }
  void merge(const BinSet& o) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < binCount; ++i) {
        bins[a][i].box.extend(o.bins[a][i].box);
        bins[a][i].count += o.bins[a][i].count;
      }
  }
};

/// Maps a (doubled) centroid to bins on the three axes; used for binning and partition alike.
struct BinMapping {
  __m128 origin, scale;
  alignas(16) float scaleLanes[4];
  uint32_t binCount;
  BinMapping(const Box& centroids, uint32_t bins) : binCount(bins) {
    origin = centroids.lo;
    alignas(16) float extent[4];
    _mm_store_ps(extent, _mm_sub_ps(centroids.hi, centroids.lo));
    for (int a = 0; a < 3; ++a) scaleLanes[a] = extent[a] > 0.0f ? float(bins) * 0.99999f / extent[a] : 0.0f;
    scaleLanes[3] = 0.0f;
    scale = _mm_load_ps(scaleLanes);
  }
  /// Bin index per axis (lanes 0..2).
  __m128i bins(__m128 centroid) const {
    const __m128i i = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(centroid, origin), scale));
    return _mm_min_epi32(_mm_max_epi32(i, _mm_setzero_si128()), _mm_set1_epi32(int(binCount) - 1));
  }
  uint32_t bin(__m128 centroid, int axis) const {
    alignas(16) int32_t b[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(b), bins(centroid));
    return static_cast<uint32_t>(b[axis]);
  }
};

struct Split {
  int axis = -1;
  uint32_t bin = 0;   // left side = bins [0, bin]
  uint32_t leftCount = 0;   // primitives in the left side
  float cost = std::numeric_limits<float>::infinity();
  Box left, right;
};

inline float blocks(uint32_t n) { return float((n + kSahBlock - 1) / kSahBlock); }
static_assert((kSahBlock & (kSahBlock - 1)) == 0, "blocks(__m128i) divides by shifting");
/// blocks() of four counts.
inline __m128 blocks(__m128i n) {
  return _mm_cvtepi32_ps(_mm_srli_epi32(_mm_add_epi32(n, _mm_set1_epi32(kSahBlock - 1)), std::countr_zero(kSahBlock)));
}

/// Half surface areas of three boxes in lanes 0..2, with the same operations as Box::halfArea
/// (empty boxes give +inf or NaN, not 0: callers skip them by their counts).
inline __m128 halfAreas(const Box (&boxes)[3]) {
  __m128 x = _mm_sub_ps(boxes[0].hi, boxes[0].lo), y = _mm_sub_ps(boxes[1].hi, boxes[1].lo);
  __m128 z = _mm_sub_ps(boxes[2].hi, boxes[2].lo), w = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(x, y, z, w);   // now x, y, z hold the three boxes' extents along x, y, z
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, y), _mm_mul_ps(y, z)), _mm_mul_ps(z, x));
}

class Builder {
 public:
  /// boundsOf(i, lo, hi) gives reference i's box as two SSE registers (lane 3 is overwritten)
  /// and returns its primitive index. With repeatsPrims, several references may name the same
  /// primitive (pre-split triangles): leaves then list each primitive once.
  template <typename BoundsOf>
  Builder(size_t count, const BoundsOf& boundsOf, const BvhBuildConfig& config, BinaryBuildScratch& scratch,
          BinaryBvh& out, bool repeatsPrims = false)
      : config_(config), out_(out), renumberStack_(scratch.renumberStack), primCount_(static_cast<uint32_t>(count)),
        repeatsPrims_(repeatsPrims) {
    // One block: refs | partitioned | nodes (room for the worst case, 2n - 1 nodes).
    static_assert(alignof(PrimRef) <= 64 && alignof(BinaryNode) <= 64 && std::is_trivially_copyable_v<PrimRef>);
    const size_t refBytes = (count * sizeof(PrimRef) + 63) / 64 * 64;
    std::byte* memory = scratch.memory.reserve(binaryBuildScratchBytes(count));
    refs_ = reinterpret_cast<PrimRef*>(memory);
    partitioned_ = reinterpret_cast<PrimRef*>(memory + refBytes);
    nodes_ = reinterpret_cast<BinaryNode*>(memory + 2 * refBytes);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1 << 14), [&](const auto& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        __m128 lo, hi;
        const uint32_t prim = boundsOf(i, lo, hi);
        const __m128 id = _mm_castsi128_ps(_mm_cvtsi32_si128(static_cast<int>(prim)));
        refs_[i] = {_mm_insert_ps(lo, id, 0x30), hi};
      }
    });
  }

  void run() {
    const uint32_t n = primCount_;
    nextNode_ = 1;   // nodes_ holds the worst case, 2n - 1 nodes; only built ones are touched
    Box all, centroids;
    rangeBoxes(refs_, 0, n, all, centroids);
    resizeReusing(out_.primIndices, n);   // written by the leaves
    buildNode({0, 0, n, 0}, all, centroids, refs_, partitioned_);
    renumberDepthFirst();
  }

 private:
  bool parallel(uint32_t count) const { return count >= config_.parallelThreshold; }
  static void rangeBoxes(const PrimRef* refs, uint32_t begin, uint32_t end, Box& bounds, Box& centroids) {
    for (uint32_t i = begin; i < end; ++i) {
      bounds.extend(refs[i].box());
      centroids.extend(refs[i].centroid2());
    }
  }

  static void binOne(const BinMapping& map, const PrimRef& ref, BinSet& set) {
    const __m128i b = map.bins(ref.centroid2());
    const Box box = ref.box();
    Bin& x = set.bins[0][_mm_extract_epi32(b, 0)];
    Bin& y = set.bins[1][_mm_extract_epi32(b, 1)];
    Bin& z = set.bins[2][_mm_extract_epi32(b, 2)];
    x.box.extend(box);
    ++x.count;
    y.box.extend(box);
    ++y.count;
    z.box.extend(box);
    ++z.count;
  }

  static void binRange(const BinMapping& map, const PrimRef* refs, uint32_t begin, uint32_t end, BinSet& set) {
    if (end - begin < kTwoBinSetsFrom) {
      for (uint32_t i = begin; i < end; ++i) binOne(map, refs[i], set);
      return;
    }
    // Neighbouring primitives often fall into the same bins; alternating between two bin sets
    // lets one primitive's bin update proceed without waiting for the previous one's store.
    BinSet other(set.binCount);
    uint32_t i = begin;
    for (; i + 1 < end; i += 2) {
      binOne(map, refs[i], set);
      binOne(map, refs[i + 1], other);
    }
    if (i < end) binOne(map, refs[i], set);
    set.merge(other);
  }

  Split findSplit(const PrimRef* refs, uint32_t begin, uint32_t end, const BinMapping& map) const {
    const uint32_t binCount = map.binCount;
    BinSet set(binCount);
    if (parallel(end - begin)) {
      set = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(begin, end, kBinGrain), BinSet(binCount),
          [&](const tbb::blocked_range<uint32_t>& r, BinSet acc) {
            binRange(map, refs, r.begin(), r.end(), acc);
            return acc;
          },
          [](BinSet a, const BinSet& b) { a.merge(b); return a; });
    } else {
      binRange(map, refs, begin, end, set);
    }
    // SAH costs of every candidate plane, the three axes at once (lane = axis): the right
    // sides accumulated from the last bin down, the left sides from the first bin up.
    alignas(16) float rightCost[kMaxBins][4], leftCost[kMaxBins][4];
    alignas(16) uint32_t leftCount[kMaxBins][4];
    Box acc[3];
    __m128i accCount = _mm_setzero_si128();
    for (uint32_t i = binCount - 1; i > 0; --i) {
      for (int a = 0; a < 3; ++a) acc[a].extend(set.bins[a][i].box);
      accCount = _mm_add_epi32(accCount, binCounts(set, i));
      _mm_store_ps(rightCost[i - 1], _mm_mul_ps(halfAreas(acc), blocks(accCount)));
    }
    acc[0] = acc[1] = acc[2] = Box();
    accCount = _mm_setzero_si128();
    for (uint32_t i = 0; i + 1 < binCount; ++i) {
      for (int a = 0; a < 3; ++a) acc[a].extend(set.bins[a][i].box);
      accCount = _mm_add_epi32(accCount, binCounts(set, i));
      _mm_store_ps(leftCost[i], _mm_mul_ps(halfAreas(acc), blocks(accCount)));
      _mm_store_si128(reinterpret_cast<__m128i*>(leftCount[i]), accCount);
    }
    // Cheapest plane; ties go to the lower axis, then the lower bin.
    Split best;
    const uint32_t count = end - begin;
    for (int a = 0; a < 3; ++a) {
      if (map.scaleLanes[a] == 0.0f) continue;
      for (uint32_t i = 0; i + 1 < binCount; ++i) {
        if (leftCount[i][a] == 0 || leftCount[i][a] == count) continue;
        const float cost = leftCost[i][a] + rightCost[i][a];
        if (cost < best.cost) {
          best.cost = cost;
          best.axis = a;
          best.bin = i;
          best.leftCount = leftCount[i][a];
        }
      }
    }
    if (best.axis >= 0)
      for (uint32_t i = 0; i < binCount; ++i) (i <= best.bin ? best.left : best.right).extend(set.bins[best.axis][i].box);
    return best;
  }

  /// A node under construction: its slot in nodes_ and its primitive range. Inside a subtree
  /// built serially, nextSlot points at that subtree's own block of free node slots (nullptr:
  /// allocate from the shared counter).
  struct Task {
    uint32_t slot, begin, end, depth;
    uint32_t* nextSlot = nullptr;
  };

  void makeLeaf(const Task& t, const Box& box, const PrimRef* refs) {
    BinaryNode& node = *new (&nodes_[t.slot]) BinaryNode();
    node.bounds = box.toBounds();
    node.first = t.begin;
    node.count = t.end - t.begin;
    if (!repeatsPrims_) {
      for (uint32_t i = t.begin; i < t.end; ++i) out_.primIndices[i] = refs[i].prim();
      return;
    }
    // Pieces of one triangle that land in the same leaf: keep one (the leaf's box already
    // covers all of them). The range's tail is left unused and packed by renumberDepthFirst.
    uint32_t* prims = &out_.primIndices[t.begin];
    uint32_t unique = 0;
    for (uint32_t i = t.begin; i < t.end; ++i) {
      const uint32_t prim = refs[i].prim();
      if (std::find(prims, prims + unique, prim) == prims + unique) prims[unique++] = prim;
    }
    node.count = unique;
    if (unique < t.end - t.begin) repeatsDropped_.fetch_add(t.end - t.begin - unique, std::memory_order_relaxed);
  }

  /// Copies [begin, end) of src into dst split by the split plane, the left side first, each
  /// side in input order (so the result is deterministic); returns the middle and the children's
  /// centroid boxes. Branch-free (the left/right test is unpredictable): the binning already
  /// counted the left side, so both sides are written forwards from their known starts.
  static uint32_t partition(const PrimRef* src, PrimRef* dst, uint32_t begin, uint32_t end, const BinMapping& map,
                            const Split& split, Box& leftCentroids, Box& rightCentroids) {
    const uint32_t mid = begin + split.leftCount;
    uint32_t left = begin, right = mid;
    const __m128i limit = _mm_set1_epi32(static_cast<int>(split.bin) + 1);
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef ref = src[i];
      const __m128 c = ref.centroid2();
      const int leftAxes = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(limit, map.bins(c))));
      const uint32_t isLeft = (leftAxes >> split.axis) & 1;
      // The target index by arithmetic, not a ternary: GCC compiled that into a branch, which
      // mispredicts on half the primitives.
      dst[right + (left - right) * isLeft] = ref;
      left += isLeft;
      right += 1 - isLeft;
      const __m128 keep = _mm_castsi128_ps(_mm_set1_epi32(-static_cast<int>(isLeft)));
      leftCentroids.lo = _mm_blendv_ps(leftCentroids.lo, _mm_min_ps(leftCentroids.lo, c), keep);
      leftCentroids.hi = _mm_blendv_ps(leftCentroids.hi, _mm_max_ps(leftCentroids.hi, c), keep);
      rightCentroids.lo = _mm_blendv_ps(_mm_min_ps(rightCentroids.lo, c), rightCentroids.lo, keep);
      rightCentroids.hi = _mm_blendv_ps(_mm_max_ps(rightCentroids.hi, c), rightCentroids.hi, keep);
    }
    return mid;
  }

  /// Builds the subtree of t, whose primitives are in refs[t.begin, t.end); other is the second
  /// buffer, free over the same range (partitions alternate between the two).
  void buildNode(const Task& t, const Box& box, const Box& centroids, PrimRef* refs, PrimRef* other) {
    const uint32_t count = t.end - t.begin;
    // One block or less: with a node costing >= one block test, SAH always prefers the leaf, so
    // skip the binning (the result is the same; small nodes are most of the nodes).
    if (count == 1 || (count <= kSahBlock && count <= config_.maxLeafTriangles && config_.traversalCost >= 1.0f))
      return makeLeaf(t, box, refs);
    // Small nodes need no more bins than primitives (deterministic: depends on count only).
    const BinMapping map(centroids, std::min(config_.binCount, std::max(4u, count)));
    const Split split = t.depth < kMaxSahDepth ? findSplit(refs, t.begin, t.end, map) : Split{};
    uint32_t mid;
    Box left, right, leftCentroids, rightCentroids;
    PrimRef* childRefs = refs;
    PrimRef* childOther = other;
    if (split.axis >= 0) {
      const float area = box.halfArea();
      const float splitCost = config_.traversalCost + (area > 0.0f ? split.cost / area : blocks(count));
      if (count <= config_.maxLeafTriangles && blocks(count) <= splitCost) return makeLeaf(t, box, refs);
      mid = partition(refs, other, t.begin, t.end, map, split, leftCentroids, rightCentroids);
      std::swap(childRefs, childOther);
      left = split.left;
      right = split.right;
    } else {
      // All centroids coincide (or the tree is too deep): split at the object median.
      if (count <= config_.maxLeafTriangles) return makeLeaf(t, box, refs);
      mid = t.begin + count / 2;
      rangeBoxes(refs, t.begin, mid, left, leftCentroids);
      rangeBoxes(refs, mid, t.end, right, rightCentroids);
    }
    BinaryNode& node = *new (&nodes_[t.slot]) BinaryNode();
    node.bounds = box.toBounds();
    node.count = 0;
    // A subtree built serially takes one block of slots for all its nodes (a binary tree over
    // count references has at most 2 * count - 2 below its root), so the threads do not contend
    // on the shared counter, nor write nodes into each other's cache lines, node by node. The
    // blocks add up to no more than the 2n - 1 slots of nodes_; renumberDepthFirst drops the gaps.
    uint32_t blockNext = 0;
    uint32_t* nextSlot = t.nextSlot;
    if (!nextSlot && !parallel(count)) {
      blockNext = nextNode_.fetch_add(2 * count - 2, std::memory_order_relaxed);
      nextSlot = &blockNext;
    }
    if (nextSlot) {
      node.left = *nextSlot;
      *nextSlot += 2;
    } else {
      node.left = nextNode_.fetch_add(2, std::memory_order_relaxed);
    }
    node.right = node.left + 1;
    const Task leftTask{node.left, t.begin, mid, t.depth + 1, nextSlot};
    const Task rightTask{node.right, mid, t.end, t.depth + 1, nextSlot};
    auto buildLeft = [&] { buildNode(leftTask, left, leftCentroids, childRefs, childOther); };
    auto buildRight = [&] { buildNode(rightTask, right, rightCentroids, childRefs, childOther); };
    if (parallel(count)) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
  }

  /// Copies the nodes into out_.nodes in depth-first order (left child = parent + 1), which
  /// removes the dependence on task timing and keeps children after their parents. Leaves that
  /// dropped repeated primitives are packed: depth-first order is the order of their ranges,
  /// so each moves its primitives down in place.
  void renumberDepthFirst() {
    // Slots reserved for serial subtrees but never used are not reachable: only the tree's own
    // nodes are appended (the reservation touches no memory).
    out_.nodes.clear();
    reserveGeometric(out_.nodes, nextNode_.load());
    const bool pack = repeatsDropped_.load() > 0;
    uint32_t leaves = 0, written = 0, packedPrims = 0;
    std::vector<std::pair<uint32_t, uint32_t>>& stack = renumberStack_;   // (source, parent to patch)
    stack.assign(1, {0u, kInvalidId});
    while (!stack.empty()) {
      const auto [source, parent] = stack.back();
      stack.pop_back();
      const uint32_t target = written++;
      if (parent != kInvalidId) out_.nodes[parent].right = target;   // left is always parent + 1
      BinaryNode node = nodes_[source];
      if (node.isLeaf()) {
        ++leaves;
        if (pack) {
          std::copy_n(out_.primIndices.begin() + node.first, node.count, out_.primIndices.begin() + packedPrims);
          node.first = packedPrims;
          packedPrims += node.count;
        }
      } else {
        stack.push_back({node.right, target});
        stack.push_back({node.left, kInvalidId});
        node.left = target + 1;
      }
      out_.nodes.push_back(node);   // at index target
    }
    out_.nodeCount = written;
    out_.leafCount = leaves;
    if (pack) out_.primIndices.resize(packedPrims);
  }

  const BvhBuildConfig& config_;
  BinaryBvh& out_;
  std::vector<std::pair<uint32_t, uint32_t>>& renumberStack_;
  PrimRef* refs_;          // the primitives, partitioned back and forth with partitioned_
  PrimRef* partitioned_;   // second buffer: disjoint ranges per task
  BinaryNode* nodes_;      // build-time nodes, indexed by allocation order (room for 2n)
  uint32_t primCount_;
  bool repeatsPrims_;
  std::atomic<uint32_t> nextNode_{1};
  std::atomic<uint32_t> repeatsDropped_{0};   // references dropped from leaves as repeats
};

}  // namespace

size_t binaryBuildScratchBytes(size_t prims) {
  // refs | partitioned | nodes (room for the worst case, 2n - 1 nodes)
  const size_t refBytes = (prims * sizeof(PrimRef) + 63) / 64 * 64;
  return 2 * refBytes + 2 * prims * sizeof(BinaryNode);
}

void validateBuildConfig(const BvhBuildConfig& config) {
  if (config.binCount < 2 || config.binCount > kMaxBins)
    throw std::invalid_argument("BvhBuildConfig.binCount must be in [2, " + std::to_string(kMaxBins) +
                                "], got " + std::to_string(config.binCount));
  if (config.nodeWidth != 0 && config.nodeWidth != 8 && config.nodeWidth != 16)
    throw std::invalid_argument("BvhBuildConfig.nodeWidth must be 0, 8 or 16, got " + std::to_string(config.nodeWidth));
  if (config.maxLeafTriangles < 1 || config.maxLeafTriangles > 64)
    throw std::invalid_argument("BvhBuildConfig.maxLeafTriangles must be in [1, 64], got " +
                                std::to_string(config.maxLeafTriangles));
  if (!(config.traversalCost >= 0.0f) || !std::isfinite(config.traversalCost))
    throw std::invalid_argument("BvhBuildConfig.traversalCost must be finite and >= 0");
  if (!(config.splitBudget >= 0.0f && config.splitBudget <= kMaxSplitBudget))
    throw std::invalid_argument("BvhBuildConfig.splitBudget must be in [0, " + std::to_string(kMaxSplitBudget) +
                                "], got " + std::to_string(config.splitBudget));
}

BinaryBvh buildBinaryBvh(std::span<const Bounds> primBounds, const BvhBuildConfig& config) {
  BinaryBvh bvh;
  BinaryBuildScratch scratch;
  buildBinaryBvh(primBounds, config, scratch, bvh);
  return bvh;
}

void buildBinaryBvh(std::span<const Bounds> primBounds, const BvhBuildConfig& config, BinaryBuildScratch& scratch,
                    BinaryBvh& out) {
  validateBuildConfig(config);
  if (primBounds.empty()) {
    out.nodes.clear();
    out.primIndices.clear();
    out.nodeCount = out.leafCount = 0;
    return;
  }
  const auto boundsOf = [&](size_t i, __m128& lo, __m128& hi) {
    lo = load3(primBounds[i].min);
    hi = load3(primBounds[i].max);
    return static_cast<uint32_t>(i);
  };
  Builder(primBounds.size(), boundsOf, config, scratch, out).run();
}

void buildBinaryBvh(const TriangleMesh& mesh, const BvhBuildConfig& config, BinaryBuildScratch& scratch,
                    BinaryBvh& out) {
  const uint32_t count = mesh.triangleCount();
  if (count == 0) {
    out = BinaryBvh{};
    return;
  }
  if (config.splitBudget > 0.0f) {
    const std::span<const SplitRef> refs = presplitTriangles(mesh, config.splitBudget, scratch.presplit);
    const auto boundsOf = [&](size_t i, __m128& lo, __m128& hi) {
      lo = _mm_loadu_ps(&refs[i].min.x);   // lane 3: the index, replaced by the builder
      hi = _mm_loadu_ps(&refs[i].max.x);
      return refs[i].tri;
    };
    Builder(refs.size(), boundsOf, config, scratch, out, refs.size() > count).run();
    return;
  }
  const auto boundsOf = [&](size_t i, __m128& lo, __m128& hi) {
    const uint32_t* tri = &mesh.indices[3 * i];
    const __m128 a = load3(mesh.positions[tri[0]]), b = load3(mesh.positions[tri[1]]), c = load3(mesh.positions[tri[2]]);
    lo = _mm_min_ps(_mm_min_ps(a, b), c);
    hi = _mm_max_ps(_mm_max_ps(a, b), c);
    return static_cast<uint32_t>(i);
  };
  Builder(count, boundsOf, config, scratch, out).run();
}

BinaryBvh buildBinaryBvh(const TriangleMesh& mesh, const BvhBuildConfig& config) {
  validateBuildConfig(config);
  BinaryBvh bvh;
  BinaryBuildScratch scratch;
  buildBinaryBvh(mesh, config, scratch, bvh);
  return bvh;
}

void refitBinaryBvh(BinaryBvh& bvh, std::span<const Bounds> primBounds) {
  // Depth-first order puts children after their parents: a reverse sweep updates children first.
  for (size_t i = bvh.nodes.size(); i-- > 0;) {
    BinaryNode& node = bvh.nodes[i];
    Bounds b;
    if (node.isLeaf()) {
      for (uint32_t k = 0; k < node.count; ++k) b.extend(primBounds[bvh.primIndices[node.first + k]]);
    } else {
      b = bvh.nodes[node.left].bounds;
      b.extend(bvh.nodes[node.right].bounds);
    }
    node.bounds = b;
  }
}

}  // namespace pa::bvh_detail
