// Our wide layout filled from Embree's rtcBuildBVH tree (see embree_tree.h).
#include "renderer/bench/embree_tree.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <new>

#include <embree3/rtcore_builder.h>

namespace pa::bench {
namespace {

using bvh_detail::kLeafBit;
using bvh_detail::kPackCountShift;
using bvh_detail::kPackWidth;
using bvh_detail::kWideWidth;

constexpr unsigned kMaxLeafTriangles = 16 * kPackWidth;   // 16 packs: what a leaf reference can name

/// What Embree's builder callbacks make, in memory from its thread-local allocator: inner
/// nodes and leaves start with this header.
struct BuiltNode {
  bool leaf = false;
  unsigned count = 0;   ///< Children, or triangles of a leaf.
};

/// An inner node: up to 8 children and their boxes.
struct BuiltInner : BuiltNode {
  std::array<const BuiltNode*, kWideWidth> children{};
  std::array<Bounds, kWideWidth> bounds{};
};

/// A leaf: its triangle indices follow it in the same allocation.
struct BuiltLeaf : BuiltNode {
  std::span<const uint32_t> triangles() const { return {reinterpret_cast<const uint32_t*>(this + 1), count}; }
};

void* createNode(RTCThreadLocalAllocator allocator, unsigned childCount, void*) {
  void* memory = rtcThreadLocalAlloc(allocator, sizeof(BuiltInner), alignof(BuiltInner));
  auto* node = new (memory) BuiltInner();
  node->count = childCount;
  return node;
}

void setNodeChildren(void* nodePtr, void** children, unsigned childCount, void*) {
  auto* node = static_cast<BuiltInner*>(nodePtr);
  for (unsigned i = 0; i < childCount; ++i) node->children[i] = static_cast<const BuiltNode*>(children[i]);
}

void setNodeBounds(void* nodePtr, const RTCBounds** bounds, unsigned childCount, void*) {
  auto* node = static_cast<BuiltInner*>(nodePtr);
  for (unsigned i = 0; i < childCount; ++i) {
    node->bounds[i].min = {bounds[i]->lower_x, bounds[i]->lower_y, bounds[i]->lower_z};
    node->bounds[i].max = {bounds[i]->upper_x, bounds[i]->upper_y, bounds[i]->upper_z};
  }
}

void* createLeaf(RTCThreadLocalAllocator allocator, const RTCBuildPrimitive* primitives, size_t count, void*) {
  // maxLeafSize (<= kMaxLeafTriangles) bounds count; the clamp only keeps the writes in bounds.
  const auto kept = static_cast<unsigned>(std::min<size_t>(count, kMaxLeafTriangles));
  void* memory = rtcThreadLocalAlloc(allocator, sizeof(BuiltLeaf) + kept * sizeof(uint32_t), alignof(BuiltLeaf));
  auto* leaf = new (memory) BuiltLeaf();
  leaf->leaf = true;
  leaf->count = kept;
  auto* triangles = reinterpret_cast<uint32_t*>(leaf + 1);
  for (unsigned i = 0; i < kept; ++i) triangles[i] = primitives[i].primID;
  return leaf;
}

/// Embree's spatial split of a reference: the bounds of the triangle's part on each side of the
/// plane (vertices on that side and the edges' crossings), within the reference's box and its
/// side of the plane; a side the triangle does not reach gets a flat box on the plane.
void splitTriangle(const RTCBuildPrimitive* primitive, unsigned dimension, float position, RTCBounds* leftBounds,
                   RTCBounds* rightBounds, void* userPtr) {
  const auto& mesh = *static_cast<const bvh_detail::TriangleMesh*>(userPtr);
  Bounds left, right;
  for (int corner = 0; corner < 3; ++corner) {
    const glm::vec3 a = mesh.vertex(primitive->primID, corner), b = mesh.vertex(primitive->primID, (corner + 1) % 3);
    const float av = a[dimension], bv = b[dimension];
    if (av <= position) left.extend(a);
    if (av >= position) right.extend(a);
    if ((av < position && bv > position) || (av > position && bv < position)) {
      glm::vec3 crossing = a + (b - a) * ((position - av) / (bv - av));
      crossing[dimension] = position;
      left.extend(crossing);
      right.extend(crossing);
    }
  }
  const glm::vec3 lower(primitive->lower_x, primitive->lower_y, primitive->lower_z);
  const glm::vec3 upper(primitive->upper_x, primitive->upper_y, primitive->upper_z);
  auto write = [&](const Bounds& part, bool leftSide, RTCBounds* out) {
    glm::vec3 lo = lower, hi = upper;
    if (leftSide) hi[dimension] = std::min(hi[dimension], position);
    else lo[dimension] = std::max(lo[dimension], position);
    if (part.empty()) lo[dimension] = hi[dimension] = position;
    else lo = glm::max(lo, part.min), hi = glm::min(hi, part.max);
    hi = glm::max(hi, lo);
    *out = RTCBounds{lo.x, lo.y, lo.z, 0.0f, hi.x, hi.y, hi.z, 0.0f};
  };
  write(left, true, leftBounds);
  write(right, false, rightBounds);
}

/// Writes Embree's tree into our layout, depth first like collapseToWide.
class Converter {
 public:
  Converter(const bvh_detail::TriangleMesh& mesh, bvh_detail::WideBvh& out) : mesh_(mesh), out_(out) {}

  void fill(uint32_t wide, const BuiltInner& built) {
    std::array<unsigned, kWideWidth> order{};
    for (unsigned i = 0; i < built.count; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.begin() + built.count,
                     [&](unsigned a, unsigned b) { return built.bounds[a].halfArea() > built.bounds[b].halfArea(); });
    bvh_detail::WideNode node = bvh_detail::makeEmptyWideNode();
    std::vector<std::pair<uint32_t, const BuiltInner*>> inner;
    for (unsigned slot = 0; slot < built.count; ++slot) {
      const BuiltNode* child = built.children[order[slot]];
      uint32_t reference = 0;
      if (child->leaf) {
        reference = leafReference(*static_cast<const BuiltLeaf*>(child));
      } else {
        reference = static_cast<uint32_t>(out_.nodes.size());
        out_.nodes.emplace_back();
        inner.emplace_back(reference, static_cast<const BuiltInner*>(child));
      }
      bvh_detail::setWideChild(node, slot, built.bounds[order[slot]], reference);
    }
    out_.nodes[wide] = node;
    for (const auto& [index, child] : inner) fill(index, *child);
  }

  /// Packs a leaf's triangles and returns its leaf reference.
  uint32_t leafReference(const BuiltLeaf& leaf) {
    const auto first = static_cast<uint32_t>(out_.packs.size());
    const uint32_t packs = (leaf.count + kPackWidth - 1) / kPackWidth;
    for (uint32_t p = 0; p < packs; ++p) {
      const uint32_t begin = p * kPackWidth;
      out_.packs.push_back(bvh_detail::makeTrianglePack(
          mesh_, leaf.triangles().subspan(begin, std::min(kPackWidth, leaf.count - begin))));
    }
    if (first + packs > bvh_detail::kFirstPackMask) throw std::runtime_error("too many triangles for the wide layout");
    return kLeafBit | ((packs - 1) << kPackCountShift) | first;
  }

 private:
  const bvh_detail::TriangleMesh& mesh_;
  bvh_detail::WideBvh& out_;
};

}  // namespace

bvh_detail::WideBvh buildWideFromEmbreeTree(RTCDevice device, const bvh_detail::TriangleMesh& mesh,
                                            const EmbreeTreeConfig& config) {
  if (config.maxLeafSize < 1 || config.maxLeafSize > kMaxLeafTriangles)
    throw std::runtime_error("Embree tree: maxLeafSize must be in [1, " + std::to_string(kMaxLeafTriangles) + "]");
  std::vector<RTCBuildPrimitive> primitives;
  primitives.reserve(mesh.triangleCount());
  for (uint32_t tri = 0; tri < mesh.triangleCount(); ++tri) {
    if (mesh.degenerate[tri]) continue;   // never hit; our build keeps them, Embree's drops them
    glm::vec3 lower = mesh.vertex(tri, 0), upper = lower;
    for (int corner = 1; corner < 3; ++corner) {
      lower = glm::min(lower, mesh.vertex(tri, corner));
      upper = glm::max(upper, mesh.vertex(tri, corner));
    }
    primitives.push_back({lower.x, lower.y, lower.z, 0, upper.x, upper.y, upper.z, tri});
  }
  bvh_detail::WideBvh out;
  out.kernel = bvh_detail::bestWideKernel();
  if (primitives.empty()) return out;

  RTCBVH bvh = rtcNewBVH(device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = config.spatialSplits ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = kWideWidth;
  args.maxDepth = 64;
  args.sahBlockSize = config.sahBlockSize;
  args.minLeafSize = config.minLeafSize;
  args.maxLeafSize = config.maxLeafSize;
  args.traversalCost = config.traversalCost;
  args.intersectionCost = 1.0f;
  args.bvh = bvh;
  args.primitives = primitives.data();
  args.primitiveCount = primitives.size();
  const size_t count = primitives.size();
  if (config.spatialSplits) {
    primitives.resize(count + static_cast<size_t>(config.splitBudget * static_cast<float>(count)));
    args.primitives = primitives.data();
    args.splitPrimitive = splitTriangle;
    args.userPtr = const_cast<bvh_detail::TriangleMesh*>(&mesh);
  }
  args.primitiveCount = count;
  args.primitiveArrayCapacity = primitives.size();
  args.createNode = createNode;
  args.setNodeChildren = setNodeChildren;
  args.setNodeBounds = setNodeBounds;
  args.createLeaf = createLeaf;
  const auto* root = static_cast<const BuiltNode*>(rtcBuildBVH(&args));
  try {
    if (!root) throw std::runtime_error("Embree tree: rtcBuildBVH failed");
    out.nodes.emplace_back();
    Converter converter(mesh, out);
    if (root->leaf) {
      // A single leaf: one node whose only child is that leaf.
      BuiltInner top;
      top.count = 1;
      top.children[0] = root;
      for (const RTCBuildPrimitive& p : primitives) {
        top.bounds[0].extend(glm::vec3(p.lower_x, p.lower_y, p.lower_z));
        top.bounds[0].extend(glm::vec3(p.upper_x, p.upper_y, p.upper_z));
      }
      converter.fill(0, top);
    } else {
      converter.fill(0, *static_cast<const BuiltInner*>(root));
    }
  } catch (...) {
    rtcReleaseBVH(bvh);
    throw;
  }
  rtcReleaseBVH(bvh);
  return out;
}

}  // namespace pa::bench
