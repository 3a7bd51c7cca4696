// Binary -> 8-wide conversion and triangle packing.
#include "renderer/bvh/wide_bvh.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pa::bvh_detail {
namespace {

class Collapser {
 public:
  Collapser(const BinaryBvh& binary, const TriangleMesh& mesh, WideBvh& out)
      : binary_(binary), mesh_(mesh), out_(out) {}

  void run() {
    packLeaves();
    out_.nodes.clear();
    out_.nodes.reserve(binary_.nodeCount / 4 + 1);
    out_.nodes.emplace_back();
    fillNode(0, 0);
  }

 private:
  /// Fills wide node `wide` with the (up to 8) descendants of binary node `root`.
  void fillNode(uint32_t wide, uint32_t root) {
    uint32_t children[kWideWidth];
    uint32_t count = 0;
    if (binary_.nodes[root].isLeaf()) {
      children[count++] = root;
    } else {
      children[count++] = binary_.nodes[root].left;
      children[count++] = binary_.nodes[root].right;
      // Open the inner child with the largest surface area until 8 children.
      while (count < kWideWidth) {
        int best = -1;
        float bestArea = -1.0f;
        for (uint32_t i = 0; i < count; ++i) {
          const BinaryNode& n = binary_.nodes[children[i]];
          if (!n.isLeaf() && n.bounds.halfArea() > bestArea) {
            bestArea = n.bounds.halfArea();
            best = static_cast<int>(i);
          }
        }
        if (best < 0) break;
        const BinaryNode& opened = binary_.nodes[children[best]];
        children[best] = opened.left;
        children[count++] = opened.right;
      }
    }
    // Largest box first: any-hit rays visit the children in lane order, and a large box is the
    // likelier occluder.
    std::stable_sort(children, children + count, [&](uint32_t a, uint32_t b) {
      return binary_.nodes[a].bounds.halfArea() > binary_.nodes[b].bounds.halfArea();
    });
    WideNode node = makeEmptyWideNode();
    for (uint32_t i = 0; i < count; ++i) {
      const BinaryNode& c = binary_.nodes[children[i]];
      uint32_t reference = leafRef_[children[i]];
      if (!c.isLeaf()) {
        reference = static_cast<uint32_t>(out_.nodes.size());
        out_.nodes.emplace_back();
      }
      setWideChild(node, i, c.bounds, reference);
    }
    out_.nodes[wide] = node;
    for (uint32_t i = 0; i < count; ++i)
      if (!binary_.nodes[children[i]].isLeaf()) fillNode(node.child[i], children[i]);
  }

  /// Packs every leaf's triangles (in parallel), leaves in depth-first order, and records each
  /// binary leaf's wide leaf reference.
  void packLeaves() {
    std::vector<uint32_t> leaves;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
      const BinaryNode& n = binary_.nodes[stack.back()];
      const uint32_t index = stack.back();
      stack.pop_back();
      if (n.isLeaf()) {
        leaves.push_back(index);
      } else {
        stack.push_back(n.right);
        stack.push_back(n.left);
      }
    }
    std::vector<uint32_t> firstPack(leaves.size() + 1, 0);
    for (size_t i = 0; i < leaves.size(); ++i) {
      const uint32_t packs = (binary_.nodes[leaves[i]].count + kPackWidth - 1) / kPackWidth;
      if (packs > 16) throw std::invalid_argument("BVH leaf too large for the wide layout");
      firstPack[i + 1] = firstPack[i] + packs;
    }
    if (firstPack.back() > kFirstPackMask) throw std::invalid_argument("too many triangles for the wide layout");
    out_.packs.resize(firstPack.back());
    leafRef_.assign(binary_.nodes.size(), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        const BinaryNode& leaf = binary_.nodes[leaves[i]];
        const uint32_t first = firstPack[i], count = firstPack[i + 1] - first;
        for (uint32_t p = 0; p < count; ++p) out_.packs[first + p] = makePack(leaf, p);
        leafRef_[leaves[i]] = kLeafBit | ((count - 1) << kPackCountShift) | first;
      }
    });
  }

  TrianglePack makePack(const BinaryNode& leaf, uint32_t p) const {
    const uint32_t first = p * kPackWidth;
    return makeTrianglePack(mesh_, std::span(binary_.primIndices).subspan(leaf.first + first,
                                                                          std::min(kPackWidth, leaf.count - first)));
  }

  const BinaryBvh& binary_;
  const TriangleMesh& mesh_;
  WideBvh& out_;
  std::vector<uint32_t> leafRef_;   // binary leaf node -> wide leaf reference
};

}  // namespace

WideNode makeEmptyWideNode() {
  WideNode node;
  for (int side = 0; side < 2; ++side)
    for (int axis = 0; axis < 3; ++axis)
      std::fill_n(node.bounds[side][axis], kWideWidth,
                  side == 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
  std::fill_n(node.child, kWideWidth, 0u);
  return node;
}

void setWideChild(WideNode& node, uint32_t slot, const Bounds& box, uint32_t child) {
  for (int axis = 0; axis < 3; ++axis) {
    node.bounds[0][axis][slot] = box.min[axis];
    node.bounds[1][axis][slot] = box.max[axis];
  }
  node.child[slot] = child;
}

TrianglePack makeTrianglePack(const TriangleMesh& mesh, std::span<const uint32_t> tris) {
  if (tris.empty() || tris.size() > kPackWidth) throw std::invalid_argument("a triangle pack holds 1 to 8 triangles");
  TrianglePack pack{};
  for (uint32_t lane = 0; lane < kPackWidth; ++lane) {
    if (lane >= tris.size()) {
      // Padding repeats the first triangle's vertices so the math stays finite.
      for (int vtx = 0; vtx < 3; ++vtx)
        for (int axis = 0; axis < 3; ++axis) pack.v[vtx][axis][lane] = pack.v[vtx][axis][0];
      pack.prim[lane] = kInvalidId;
      continue;
    }
    const uint32_t tri = tris[lane];
    for (int vtx = 0; vtx < 3; ++vtx) {
      const glm::vec3 p3 = mesh.vertex(tri, vtx);
      for (int axis = 0; axis < 3; ++axis) pack.v[vtx][axis][lane] = p3[axis];
    }
    pack.prim[lane] = tri;
    if (!mesh.degenerate[tri]) pack.validBits |= 1u << lane;
    if (mesh.isMasked(tri)) pack.maskedBits |= 1u << lane;
  }
  return pack;
}

WideBvh collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh) {
  WideBvh out;
  collapseToWide(binary, mesh, out);
  return out;
}

void collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh, WideBvh& out) {
  if (binary.empty()) {
    out = WideBvh{};
    return;
  }
  Collapser(binary, mesh, out).run();
  out.kernel = bestWideKernel();
}

}  // namespace pa::bvh_detail
