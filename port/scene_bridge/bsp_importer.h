#pragma once
// pa-render's importer for Quake III maps (.bsp), registered with the CLI when linked.
//   pa-render /usr/share/games/openarena/baseoa/maps/oa_dm1.bsp -o shot.png
// The map is looked up inside the game folder's .pk3 archives when it is not a loose file:
// GAMEDIR/maps/NAME.bsp names map NAME of game folder GAMEDIR. A bare NAME.bsp (or a loose
// .bsp elsewhere) uses the game folder of $PA_GAME_DIR, else /usr/share/games/openarena/baseoa.
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "port/q3formats/world/world_scene.h"
#include "renderer/cli/scene_importer.h"

namespace pa::bridge {

/// Game folder used when the path does not name one.
inline constexpr const char* kDefaultGameDir = "/usr/share/games/openarena/baseoa";

/// Where a .bsp path points: the game folder and the map's game path (or a loose file).
struct MapLocation {
  std::filesystem::path gameDir;
  std::string mapPath;                 ///< "maps/NAME.bsp" inside the game folder, or empty.
  std::filesystem::path looseFile;     ///< A .bsp on disk outside the game folder, or empty.
};

/// Splits a command-line path into game folder and map (see the header comment).
/// `envGameDir` is $PA_GAME_DIR (nullptr when unset).
MapLocation locateMap(const std::filesystem::path& path, const char* envGameDir);

/// The map at `where` built, with its lights recovered (port/light_recovery): the scene
/// BspImporter::load uploads. `problems`, when given, receives the game folder's problems.
q3::WorldScene loadMapScene(const MapLocation& where, std::vector<std::string>* problems = nullptr);

/// Quake III .bsp -> pa::Renderer through loadMapScene and uploadWorld.
class BspImporter : public cli::SceneImporter {
 public:
  std::string_view formatName() const override { return "Quake III map (IBSP 46)"; }
  std::span<const std::string_view> extensions() const override;
  cli::ImportedScene load(const std::filesystem::path& path, Renderer& renderer,
                          const cli::ImportOptions& options) const override;
};

}  // namespace pa::bridge
