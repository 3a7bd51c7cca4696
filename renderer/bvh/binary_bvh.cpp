// Binned SAH build of the reference binary BVH.
//
// Parallelism: large ranges bin in parallel (tbb::parallel_reduce; min/max/count merges are
// exact and order independent) and their two children are built as parallel tasks. Each
// subtree over n primitives owns the fixed node slot range [slot, slot + 2n - 1), so the tree
// and its layout are identical whatever the thread count.
#include "renderer/bvh/binary_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

namespace pa::bvh_detail {
namespace {

constexpr uint32_t kMaxBins = 64;
constexpr uint32_t kBinGrain = 2048;   // primitives per binning task
// Past this depth splits are object medians, so the depth stays below kMaxSahDepth + 32 and
// traversal stacks of 128 entries cannot overflow even for pathological inputs.
constexpr uint32_t kMaxSahDepth = 64;

struct Bin {
  Bounds bounds;
  Bounds centroids;
  uint32_t count = 0;
  void merge(const Bin& o) {
    bounds.extend(o.bounds);
    centroids.extend(o.centroids);
    count += o.count;
  }
};

/// Bins along all three axes for one range.
struct BinSet {
  std::array<std::array<Bin, kMaxBins>, 3> axis;
  void merge(const BinSet& o, uint32_t binCount) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < binCount; ++i) axis[a][i].merge(o.axis[a][i]);
  }
};

/// Maps a centroid coordinate to its bin; the same formula is used for binning and partition.
struct BinMapping {
  glm::vec3 origin{0.0f};
  glm::vec3 scale{0.0f};   // 0 on axes with no centroid extent
  uint32_t binCount = 1;

  BinMapping(const Bounds& centroidBounds, uint32_t bins) : origin(centroidBounds.min), binCount(bins) {
    const glm::vec3 extent = centroidBounds.max - centroidBounds.min;
    for (int a = 0; a < 3; ++a)
      scale[a] = extent[a] > 0.0f ? float(bins) * 0.99999f / extent[a] : 0.0f;
  }
  uint32_t bin(const glm::vec3& c, int a) const {
    const float f = (c[a] - origin[a]) * scale[a];
    const auto i = static_cast<int64_t>(f);
    return static_cast<uint32_t>(std::clamp<int64_t>(i, 0, binCount - 1));
  }
};

struct Split {
  int axis = -1;
  uint32_t bin = 0;       // left side = bins [0, bin]
  float cost = 0.0f;
  Bounds leftBounds, rightBounds, leftCentroids, rightCentroids;
  uint32_t leftCount = 0;
};

class Builder {
 public:
  Builder(std::span<const Bounds> primBounds, const BvhBuildConfig& config, BinaryBvh& out)
      : bounds_(primBounds), config_(config), out_(out), centroids_(primBounds.size()) {}

  void run() {
    const auto n = static_cast<uint32_t>(bounds_.size());
    out_.primIndices.resize(n);
    std::iota(out_.primIndices.begin(), out_.primIndices.end(), 0u);
    out_.nodes.assign(size_t(2) * n - 1, BinaryNode{});
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kBinGrain), [&](const auto& r) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) centroids_[i] = bounds_[i].center();
    });
    Bin all = rangeBounds(0, n);
    buildNode(0, 0, n, all.bounds, all.centroids, 0);
    // Count reachable nodes and leaves.
    uint32_t nodes = 0, leaves = 0;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
      const BinaryNode& node = out_.nodes[stack.back()];
      stack.pop_back();
      ++nodes;
      if (node.isLeaf()) {
        ++leaves;
      } else {
        stack.push_back(node.left);
        stack.push_back(node.right);
      }
    }
    out_.nodeCount = nodes;
    out_.leafCount = leaves;
  }

 private:
  bool parallel(uint32_t count) const { return count >= config_.parallelThreshold; }

  Bin rangeBounds(uint32_t begin, uint32_t end) const {
    auto body = [&](const tbb::blocked_range<uint32_t>& r, Bin acc) {
      for (uint32_t i = r.begin(); i < r.end(); ++i) {
        const uint32_t p = out_.primIndices[i];
        acc.bounds.extend(bounds_[p]);
        acc.centroids.extend(centroids_[p]);
        ++acc.count;
      }
      return acc;
    };
    if (!parallel(end - begin)) return body({begin, end}, Bin{});
    return tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, kBinGrain), Bin{}, body,
                                [](Bin a, const Bin& b) { a.merge(b); return a; });
  }

  void binRange(const BinMapping& map, uint32_t begin, uint32_t end, BinSet& bins) const {
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t p = out_.primIndices[i];
      const glm::vec3& c = centroids_[p];
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins.axis[a][map.bin(c, a)];
        b.bounds.extend(bounds_[p]);
        b.centroids.extend(c);
        ++b.count;
      }
    }
  }

  Split findSplit(uint32_t begin, uint32_t end, const Bounds& centroidBounds) const {
    const uint32_t binCount = config_.binCount;
    const BinMapping map(centroidBounds, binCount);
    BinSet bins;
    if (parallel(end - begin)) {
      bins = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(begin, end, kBinGrain), BinSet{},
          [&](const tbb::blocked_range<uint32_t>& r, BinSet acc) {
            binRange(map, r.begin(), r.end(), acc);
            return acc;
          },
          [binCount](BinSet a, const BinSet& b) { a.merge(b, binCount); return a; });
    } else {
      binRange(map, begin, end, bins);
    }
    Split best;
    best.cost = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (map.scale[a] == 0.0f) continue;
      const auto& axisBins = bins.axis[a];
      // Sweep from the right to get the right-side areas, then from the left.
      std::array<float, kMaxBins> rightArea{};
      Bin acc;
      for (uint32_t i = binCount - 1; i > 0; --i) {
        acc.merge(axisBins[i]);
        rightArea[i - 1] = acc.bounds.halfArea() * float(acc.count);
      }
      Bin left;
      for (uint32_t i = 0; i + 1 < binCount; ++i) {
        left.merge(axisBins[i]);
        if (left.count == 0 || left.count == end - begin) continue;
        const float cost = left.bounds.halfArea() * float(left.count) + rightArea[i];
        if (cost < best.cost) {
          best.cost = cost;
          best.axis = a;
          best.bin = i;
        }
      }
    }
    if (best.axis >= 0) {
      Bin l, r;
      for (uint32_t i = 0; i < binCount; ++i) (i <= best.bin ? l : r).merge(bins.axis[best.axis][i]);
      best.leftBounds = l.bounds;
      best.rightBounds = r.bounds;
      best.leftCentroids = l.centroids;
      best.rightCentroids = r.centroids;
      best.leftCount = l.count;
    }
    return best;
  }

  void makeLeaf(uint32_t slot, uint32_t begin, uint32_t end, const Bounds& nodeBounds) {
    BinaryNode& node = out_.nodes[slot];
    node.bounds = nodeBounds;
    node.first = begin;
    node.count = end - begin;
  }

  void buildNode(uint32_t slot, uint32_t begin, uint32_t end, const Bounds& nodeBounds,
                 const Bounds& centroidBounds, uint32_t depth) {
    const uint32_t count = end - begin;
    if (count == 1) return makeLeaf(slot, begin, end, nodeBounds);
    const Split split = depth < kMaxSahDepth ? findSplit(begin, end, centroidBounds) : Split{};
    const float area = nodeBounds.halfArea();
    uint32_t mid;
    Bin left, right;
    if (split.axis >= 0) {
      const float splitCost =
          config_.traversalCost + (area > 0.0f ? split.cost / area : float(count));
      if (count <= config_.maxLeafTriangles && float(count) <= splitCost)
        return makeLeaf(slot, begin, end, nodeBounds);
      const BinMapping map(centroidBounds, config_.binCount);
      const int axis = split.axis;
      const uint32_t splitBin = split.bin;
      auto* first = out_.primIndices.data() + begin;
      auto* pivot = std::stable_partition(first, first + count, [&](uint32_t p) {
        return map.bin(centroids_[p], axis) <= splitBin;
      });
      mid = begin + static_cast<uint32_t>(pivot - first);
      left.bounds = split.leftBounds;
      left.centroids = split.leftCentroids;
      right.bounds = split.rightBounds;
      right.centroids = split.rightCentroids;
    } else {
      // All centroids coincide (or the tree is too deep): split at the object median.
      if (count <= config_.maxLeafTriangles) return makeLeaf(slot, begin, end, nodeBounds);
      mid = begin + count / 2;
      left = rangeBounds(begin, mid);
      right = rangeBounds(mid, end);
    }
    BinaryNode& node = out_.nodes[slot];
    node.bounds = nodeBounds;
    node.count = 0;
    node.left = slot + 1;
    node.right = slot + 2 * (mid - begin);
    const uint32_t leftSlot = node.left, rightSlot = node.right;
    auto buildLeft = [&, leftSlot] { buildNode(leftSlot, begin, mid, left.bounds, left.centroids, depth + 1); };
    auto buildRight = [&, rightSlot] { buildNode(rightSlot, mid, end, right.bounds, right.centroids, depth + 1); };
    if (parallel(count)) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
  }

  std::span<const Bounds> bounds_;
  const BvhBuildConfig& config_;
  BinaryBvh& out_;
  std::vector<glm::vec3> centroids_;
};

}  // namespace

void validateBuildConfig(const BvhBuildConfig& config) {
  if (config.binCount < 2 || config.binCount > kMaxBins)
    throw std::invalid_argument("BvhBuildConfig.binCount must be in [2, " + std::to_string(kMaxBins) +
                                "], got " + std::to_string(config.binCount));
  if (config.maxLeafTriangles < 1 || config.maxLeafTriangles > 64)
    throw std::invalid_argument("BvhBuildConfig.maxLeafTriangles must be in [1, 64], got " +
                                std::to_string(config.maxLeafTriangles));
  if (!(config.traversalCost >= 0.0f) || !std::isfinite(config.traversalCost))
    throw std::invalid_argument("BvhBuildConfig.traversalCost must be finite and >= 0");
}

BinaryBvh buildBinaryBvh(std::span<const Bounds> primBounds, const BvhBuildConfig& config) {
  validateBuildConfig(config);
  BinaryBvh bvh;
  if (primBounds.empty()) return bvh;
  Builder(primBounds, config, bvh).run();
  return bvh;
}

void refitBinaryBvh(BinaryBvh& bvh, std::span<const Bounds> primBounds) {
  if (bvh.empty()) return;
  // Post-order without recursion: children always have larger slots than their parent,
  // so a reverse sweep over reachable slots in decreasing order visits children first.
  std::vector<uint32_t> order;
  order.reserve(bvh.nodeCount);
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    order.push_back(i);
    if (!bvh.nodes[i].isLeaf()) {
      stack.push_back(bvh.nodes[i].left);
      stack.push_back(bvh.nodes[i].right);
    }
  }
  std::sort(order.begin(), order.end(), std::greater<>());
  for (uint32_t i : order) {
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
