// Binary -> 8-wide conversion and triangle packing.
#include "renderer/bvh/wide_bvh.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pa::bvh_detail {
namespace {

class Collapser {
 public:
  Collapser(const BinaryBvh& binary, const TriangleMesh& mesh, WideBvh& out)
      : binary_(binary), mesh_(mesh), out_(out) {}

  void run() {
    out_.nodes.reserve(binary_.nodeCount / 4 + 1);
    out_.packs.reserve(binary_.primIndices.size() / 2 + 1);
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
    WideNode node;
    for (int side = 0; side < 2; ++side)
      for (int axis = 0; axis < 3; ++axis)
        std::fill_n(node.bounds[side][axis], kWideWidth,
                    side == 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
    std::fill_n(node.child, kWideWidth, 0u);
    for (uint32_t i = 0; i < count; ++i) {
      const BinaryNode& c = binary_.nodes[children[i]];
      for (int axis = 0; axis < 3; ++axis) {
        node.bounds[0][axis][i] = c.bounds.min[axis];
        node.bounds[1][axis][i] = c.bounds.max[axis];
      }
      if (c.isLeaf()) {
        node.child[i] = makeLeaf(c);
      } else {
        node.child[i] = static_cast<uint32_t>(out_.nodes.size());
        out_.nodes.emplace_back();
      }
    }
    out_.nodes[wide] = node;
    for (uint32_t i = 0; i < count; ++i)
      if (!binary_.nodes[children[i]].isLeaf()) fillNode(node.child[i], children[i]);
  }

  uint32_t makeLeaf(const BinaryNode& leaf) {
    const auto first = static_cast<uint32_t>(out_.packs.size());
    const uint32_t packCount = (leaf.count + kPackWidth - 1) / kPackWidth;
    if (packCount > 16 || first + packCount > kFirstPackMask)
      throw std::invalid_argument("BVH leaf too large for the wide layout");
    for (uint32_t p = 0; p < packCount; ++p) {
      TrianglePack pack{};
      for (uint32_t lane = 0; lane < kPackWidth; ++lane) {
        const uint32_t k = p * kPackWidth + lane;
        if (k >= leaf.count) {
          // Padding repeats the first triangle's vertices so the math stays finite.
          for (int vtx = 0; vtx < 3; ++vtx)
            for (int axis = 0; axis < 3; ++axis) pack.v[vtx][axis][lane] = pack.v[vtx][axis][0];
          pack.prim[lane] = kInvalidId;
          continue;
        }
        const uint32_t tri = binary_.primIndices[leaf.first + k];
        for (int vtx = 0; vtx < 3; ++vtx) {
          const glm::vec3 p3 = mesh_.vertex(tri, vtx);
          for (int axis = 0; axis < 3; ++axis) pack.v[vtx][axis][lane] = p3[axis];
        }
        pack.prim[lane] = tri;
        if (!mesh_.degenerate[tri]) pack.validBits |= 1u << lane;
        if (mesh_.isMasked(tri)) pack.maskedBits |= 1u << lane;
      }
      out_.packs.push_back(pack);
    }
    return kLeafBit | ((packCount - 1) << kPackCountShift) | first;
  }

  const BinaryBvh& binary_;
  const TriangleMesh& mesh_;
  WideBvh& out_;
};

}  // namespace

WideBvh collapseToWide(const BinaryBvh& binary, const TriangleMesh& mesh) {
  WideBvh out;
  if (binary.empty()) return out;
  Collapser(binary, mesh, out).run();
  return out;
}

}  // namespace pa::bvh_detail
