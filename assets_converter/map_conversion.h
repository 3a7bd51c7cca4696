#pragma once
// One game folder opened for conversion (archives + every shader script), and the
// conversion of one map of it to a .glb file.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "assets_converter/gltf_export.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace pa::converter {

/// A game folder with its shader scripts loaded in the engine's priority order.
struct GameData {
  explicit GameData(const std::filesystem::path& gameDir);
  q3::GameFileSystem files;
  q3::ShaderLibrary shaders;
  std::vector<std::string> scriptErrors;   ///< Scripts the engine would ignore, with the reason.
};

/// Every map of the game: "maps/NAME.bsp" paths, sorted.
std::vector<std::string> listMaps(const q3::GameFileSystem& files);

/// "oa_dm1", "oa_dm1.bsp" or "maps/oa_dm1.bsp" -> "maps/oa_dm1.bsp".
std::string mapPath(const std::string& name);

/// Outcome of one map's conversion.
struct MapResult {
  std::string map;                    ///< "maps/oa_dm1.bsp"
  std::filesystem::path output;       ///< Written file (empty on failure).
  ExportStats stats;
  std::vector<std::string> warnings;  ///< Content problems found while building the scene.
  double seconds = 0.0;               ///< Wall time: read + parse + build + export + write.
  std::string error;                  ///< Non-empty when the map could not be converted.
};

/// Reads, parses and converts one map, writing OUTDIR/NAME.glb. Never throws: a malformed
/// map or an I/O failure is reported in MapResult::error.
MapResult convertMap(const GameData& game, const std::string& map, const std::filesystem::path& outDir,
                     const ExportOptions& options);

}  // namespace pa::converter
