#pragma once
// Closing the seams between tessellated patches whose boundaries follow one curve but are cut
// at different points: patches that meet without identical control points, one patch edge
// spanning two neighbours, a patch edge ending in the middle of another's (T-junctions).
//
// Equal segment counts (matchSharedPatchEdges) already make patches that share a boundary's
// three control points agree vertex for vertex. Everything else is closed here, on the meshes:
//  1. boundary vertices (of edges used by one triangle, by position) closer than `tolerance`
//     to one another are welded onto one position (same model only);
//  2. every boundary vertex V of a patch that lies on another boundary edge's *curve* (not its
//     chord: the edge is a chord of the exact boundary curve, and V of a patch cut elsewhere sits
//     on the curve up to maxError away from the chord) within `tolerance`, strictly between its
//     ends, is inserted into that edge: the edge's triangle is split (a fan from its opposite
//     corner, or around a new interior surface point when several of its edges get vertices).
// Afterwards both sides of a shared curve carry the union of both cuts: the same vertices at
// bit-identical positions, so their edges coincide and no crack or T-junction remains.
// Planar faces, if given, are fixed geometry: patch vertices weld onto their boundary vertices
// (step 1) and patch boundary vertices on their straight edges are inserted into them (step 2,
// attributes interpolated linearly); face vertices are not inserted into patches.
//
// Error bound: new vertices lie within `tolerance` of the patch's own surface (their attributes
// are the patch's own at the found parameters; their position is the neighbour's exactly), and
// every new triangle lies inside an old one in the parameter domain, so the distance between
// surface and triangles stays <= maxError + tolerance.
#include <cstddef>
#include <span>

#include "port/q3formats/bsp/patch.h"
#include "port/q3formats/bsp/surface_mesh.h"

namespace q3 {

/// One patch mesh straight out of tessellatePatch (its vertices are exactly the grid of
/// `subdivision`, starting at index 0), with the control grid it came from. Entries that do not
/// fit together (null, sizes that disagree) are left untouched.
struct TessellatedPatch {
  const PatchControlGrid* grid = nullptr;
  const PatchSubdivision* subdivision = nullptr;
  SurfaceMesh* mesh = nullptr;
};

/// What closePatchSeams changed.
struct PatchSeamRepair {
  size_t weldedVertices = 0;     ///< boundary vertices moved onto a neighbour within tolerance
  size_t insertedVertices = 0;   ///< neighbour vertices inserted into boundary edges
  size_t splitTriangles = 0;     ///< triangles replaced by a fan
  size_t addedTriangles = 0;     ///< triangles added by the splits (droppedTriangles not subtracted)
  size_t droppedTriangles = 0;   ///< triangles with two corners made equal (welding, sliver closing)
};

/// Welds and inserts boundary vertices so that patches of the same model whose boundaries
/// follow one curve (within `tolerance`, world units) share every vertex along it.
/// Boundaries farther than 16 units from their chord (beyond any sane error bound) are skipped.
/// Planar faces in `faces` (null entries skipped) take part as fixed geometry: patch boundary
/// vertices within `tolerance` snap onto their boundary vertices, and patch boundary vertices
/// lying on their (straight) boundary edges are inserted into them, attributes interpolated
/// linearly. Face vertices are not inserted into patch edges.
PatchSeamRepair closePatchSeams(std::span<const TessellatedPatch> patches, float tolerance,
                                std::span<SurfaceMesh* const> faces = {});

}  // namespace q3
