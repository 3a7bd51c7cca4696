#pragma once
// PatchTessellator: Bezier patch surfaces of a BspFile as triangles. The same subdivision is
// used along a whole row/column of 3x3 pieces so neighbouring pieces share their edges.
#include <cstddef>

#include "port/q3formats/world/world_source.h"

namespace q3 {

struct BspFile;

/// Tessellates patch surfaces to a tolerance in Quake units (the engine's r_subdivisions).
class PatchTessellator {
 public:
  PatchTessellator(const BspFile& bsp, float tolerance) : bsp_(bsp), tolerance_(tolerance > 0.5f ? tolerance : 0.5f) {}
  /// Appends the triangles of surface `surfaceIndex` (a patch) to `out` (counter-clockwise).
  /// Malformed control grids (even or < 3 sizes) leave `out` empty.
  void tessellate(size_t surfaceIndex, SourceSurface& out) const;

 private:
  const BspFile& bsp_;
  float tolerance_;
};

}  // namespace q3
