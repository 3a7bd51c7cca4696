#pragma once
// Triangle pre-splitting before the binned SAH build, after the idea of Karras & Aila 2013 ("Fast
// Parallel Construction of High-Quality Bounding Volume Hierarchies", early split clipping): the
// triangles whose boxes fit them worst (long, thin, diagonal) get several references, each a box
// around the part of the triangle on one side of planes of a global power-of-two grid over the
// mesh's box (so splits of neighbouring triangles line up, and a coarse plane, which the top of the
// tree is likely to split on, is used before a fine one). A triangle may then sit in several
// leaves; every layout still reports it with its own (unsplit) vertices.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/bvh/triangle_mesh.h"
#include "renderer/core/bounds.h"

namespace pa::bvh_detail {

/// A reference to (part of) a triangle: a box containing that part, and the triangle index.
/// 32 bytes, laid out as min, index, max, unused (the builder loads each half as one register).
struct SplitRef {
  glm::vec3 min;
  uint32_t tri;
  glm::vec3 max;
  uint32_t unused;
};
static_assert(sizeof(SplitRef) == 32);

/// Arrays of presplitTriangles, kept between builds of a Blas.
struct PresplitScratch {
  std::vector<float> priority;        ///< Per triangle.
  std::vector<uint32_t> splits;       ///< Per triangle: planned splits, then references written.
  std::vector<uint32_t> firstSlot;    ///< Per triangle (+1): where its references start in slots.
  std::vector<SplitRef> slots;        ///< splits + 1 slots per triangle.
  std::vector<SplitRef> refs;         ///< The result (== slots when no split was dropped).
  /// Frees all arrays.
  void release();
};

/// Conservative box of the part of triangle (a, b, c) inside cell: contains every point of the
/// triangle in the closed box `cell` (exactly: the arithmetic is in double with an error bound,
/// rounded outwards to float) and lies inside cell and the triangle's box. Empty when the
/// triangle misses the cell.
Bounds clippedTriangleBounds(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const Bounds& cell);

/// References for all triangles of mesh: one per triangle, plus up to floor(budget * count)
/// more for the triangles whose boxes fit them worst; a triangle's references are consecutive,
/// triangles in index order. The union of a triangle's boxes contains the triangle; each box
/// lies inside the triangle's box. Degenerate triangles are never split. Deterministic (the
/// result does not depend on the thread count). Returns a view of scratch.refs.
std::span<const SplitRef> presplitTriangles(const TriangleMesh& mesh, float budget, PresplitScratch& scratch);

}  // namespace pa::bvh_detail
