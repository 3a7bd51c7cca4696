#pragma once
// BSP surfaces -> triangle lists: planar faces, triangle soups and crack-free Bezier patches.
#include <cstddef>
#include <vector>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/surface_mesh.h"

namespace q3 {

/// Tessellation quality and hostile-input budgets.
struct TessellationOptions {
  float maxError = 4.0f;             ///< max distance surface <-> triangles, world units (r_subdivisions)
  int maxSegmentsPerSpan = 64;       ///< cap per 3x3 piece and direction (power of two)
  size_t maxTotalVertices = 1u << 22;  ///< budget for all output (real maps: < 120k); over it: FormatError
  bool stitchPatches = true;         ///< equalise subdivision along boundaries shared by patches
  float weldDistance = 0.01f;        ///< with stitching: patch control points this close become one
  float seamTolerance = 0.1f;        ///< with stitching: boundary vertices this close to another patch's
                                     ///< boundary curve are shared (closePatchSeams); 0 = off
};

/// One mesh per drawable surface, in surface order; flares and empty surfaces are skipped.
/// With stitchPatches, patch boundaries that follow one curve share every vertex along it
/// (patch_seams.h), and patch triangles stay within maxError + seamTolerance of the surface.
/// Throws FormatError if the output would exceed options.maxTotalVertices and
/// std::invalid_argument for nonsensical options.
std::vector<SurfaceMesh> tessellateSurfaces(const BspFile& bsp, const TessellationOptions& options = {});

/// Seam diagnostics over patch meshes of the same model. A seam vertex is a boundary vertex of
/// one patch lying beside the interior of another patch's boundary edge that runs the same way
/// (the two boundaries follow one curve but were cut differently).
struct PatchSeamStats {
  size_t boundaryEdges = 0;  ///< patch edges used by one triangle of their own mesh (vertices compared
                             ///< by position: a closed cylinder's seam is no boundary)
  size_t tJunctions = 0;     ///< seam vertices on the other edge (distance <= tolerance)
  size_t cracks = 0;  ///< seam vertices off the other edge (tolerance < distance <= gapLimit) between
                      ///< two vertices that both patches share: the same curve cut differently
};
/// Measures T-junctions and cracks between patch boundaries.
PatchSeamStats measurePatchSeams(const std::vector<SurfaceMesh>& meshes, float tolerance = 0.01f,
                                 float gapLimit = 4.0f);

}  // namespace q3
