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
  size_t maxTotalVertices = 1u << 25;  ///< budget for all output; exceeding it throws FormatError
  bool stitchPatches = true;         ///< equalise subdivision along boundaries shared by patches
};

/// One mesh per drawable surface, in surface order; flares and empty surfaces are skipped.
/// Throws FormatError if the output would exceed options.maxTotalVertices and
/// std::invalid_argument for nonsensical options.
std::vector<SurfaceMesh> tessellateSurfaces(const BspFile& bsp, const TessellationOptions& options = {});

/// Crack diagnostics over patch meshes of the same model.
struct PatchSeamStats {
  size_t boundaryEdges = 0;  ///< patch edges used by one triangle of their own mesh
  size_t tJunctions = 0;     ///< patch boundary vertices strictly inside another patch's boundary edge
};
/// Finds T-junctions between patch boundaries (vertices within `tolerance` of an edge interior).
PatchSeamStats measurePatchSeams(const std::vector<SurfaceMesh>& meshes, float tolerance = 0.01f);

}  // namespace q3
