#pragma once
// The conversion of one map of a game folder to a .glb file.
#include <filesystem>
#include <string>
#include <vector>

#include "assets_converter/gltf_export.h"
#include "port/q3formats/world/world_game.h"

namespace pa::converter {

/// Outcome of one map's conversion.
struct MapResult {
  std::string map;                    ///< "maps/oa_dm1.bsp"
  std::filesystem::path output;       ///< Written file (empty on failure).
  ExportStats stats;
  std::vector<std::string> warnings;  ///< Content problems found while building the scene.
  double seconds = 0.0;               ///< Wall time: read + parse + build + export + write.
  double cpuSeconds = 0.0;            ///< Process CPU time of the same span (single-threaded work).
  std::string error;                  ///< Non-empty when the map could not be converted.
};

/// Reads, parses and converts one map, writing OUTDIR/NAME.glb. Never throws: a malformed
/// map or an I/O failure is reported in MapResult::error.
MapResult convertMap(const q3::GameWorlds& game, const std::string& map, const std::filesystem::path& outDir,
                     const ExportOptions& options);

}  // namespace pa::converter
