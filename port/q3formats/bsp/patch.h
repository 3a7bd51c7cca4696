#pragma once
// Bezier patches: error-bounded, crack-free tessellation of 3x3 biquadratic pieces.
//
// A patch of W x H control points (odd, row-major, u along a row) has (W-1)/2 x (H-1)/2
// biquadratic pieces. Each span column i (all pieces with the same u range) gets uSegments[i]
// segments and each span row j gets vSegments[j], powers of two, so the grid stays regular.
// The counts come from a rigorous bound on the distance between the surface and the two
// triangles of each grid cell. Patches sharing a boundary curve (same three control points,
// either direction) are given the same count on it, and because the parameters are dyadic and
// evaluation is symmetric, both produce bit-identical vertices along it: no cracks, no T-junctions.
#include <span>
#include <vector>

#include "port/q3formats/bsp/surface_mesh.h"

namespace q3 {

/// A patch's control points (row-major, `width` per row).
struct PatchControlGrid {
  int width = 0, height = 0;
  std::span<const BspDrawVert> points;

  /// Number of biquadratic pieces along u.
  int spansU() const { return (width - 1) / 2; }
  /// Number of biquadratic pieces along v.
  int spansV() const { return (height - 1) / 2; }
  /// Control point at column x, row y.
  const BspDrawVert& at(int x, int y) const { return points[static_cast<size_t>(y) * width + x]; }
};

/// Segments per span column (u) and per span row (v); each a power of two >= 1.
struct PatchSubdivision {
  std::vector<int> uSegments;
  std::vector<int> vSegments;
};

/// Upper bound of the distance between the surface and its triangulation for one piece
/// (span column i, span row j) cut into nu x nv cells of two triangles.
float patchPieceErrorBound(const PatchControlGrid& grid, int i, int j, int nu, int nv);

/// The fewest segments (powers of two, at most maxSegmentsPerSpan) keeping every piece's
/// error bound <= maxError. With the cap reached the bound may exceed maxError.
PatchSubdivision requiredSubdivision(const PatchControlGrid& grid, float maxError, int maxSegmentsPerSpan);

/// Raises segment counts so that every boundary curve shared by several patches (or by two
/// boundaries of one patch) is cut identically everywhere. Sizes of both spans must match.
void matchSharedPatchEdges(std::span<const PatchControlGrid> grids, std::span<PatchSubdivision> subdivisions);

/// Surface point at patch parameters u in [0, spansU], v in [0, spansV].
glm::vec3 evaluatePatchPosition(const PatchControlGrid& grid, float u, float v);

/// Every attribute of the surface at (u, v): position, uv, lightmap uv, colour, and the unit
/// analytic normal S_u x S_v, not yet oriented like the file's normals (zero where it vanishes).
/// `storedNormal`, if given, receives the interpolated file normal (not normalised).
MeshVertex evaluatePatchVertex(const PatchControlGrid& grid, float u, float v, glm::vec3* storedNormal = nullptr);

/// Patch parameters (span index + fraction) of the grid lines tessellatePatch cuts along one
/// direction: its vertex (column c, row r) is at (patchGridParameters(u)[c], patchGridParameters(v)[r]).
std::vector<float> patchGridParameters(const std::vector<int>& segments);

/// Appends the patch's grid vertices (row-major, see patchGridParameters) and triangles (CCW seen
/// from the front) to `mesh`. Normals are analytic, oriented like the stored control normals.
/// Triangles with two coincident corners (collapsed rows or columns) are left out.
void tessellatePatch(const PatchControlGrid& grid, const PatchSubdivision& subdivision, SurfaceMesh& mesh);

/// Number of vertices tessellatePatch will produce.
size_t patchVertexCount(const PatchSubdivision& subdivision);

}  // namespace q3
