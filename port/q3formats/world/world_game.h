#pragma once
// A game folder opened for map loading: its archives and every shader script, read once and
// shared by all maps (the converter's batch mode, pa-render's .bsp importer).
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"
#include "port/q3formats/world/world_scene.h"

namespace q3 {

/// A game folder with its shader scripts loaded in the engine's priority order.
class GameWorlds {
 public:
  /// Opens `gameDir` (e.g. /usr/share/games/openarena/baseoa). Throws std::runtime_error if it
  /// is not a readable folder; unreadable archives and broken scripts are listed in problems().
  explicit GameWorlds(const std::filesystem::path& gameDir);

  /// Every map of the game: "maps/NAME.bsp" paths, sorted.
  std::vector<std::string> maps() const;
  /// Reads, parses and builds one map ("oa_dm1", "oa_dm1.bsp" or "maps/oa_dm1.bsp").
  /// Throws std::runtime_error if the map is missing, FormatError if it is malformed.
  WorldScene load(const std::string& map, const WorldBuildOptions& options = {}) const;
  /// Builds a map from .bsp bytes read elsewhere (a loose file), with this game's textures.
  WorldScene build(std::span<const std::byte> bspBytes, const std::string& name,
                   const WorldBuildOptions& options = {}) const;

  /// The archives and loose files.
  const GameFileSystem& files() const { return files_; }
  /// The shader scripts.
  const ShaderLibrary& shaders() const { return shaders_; }
  /// Archives that could not be mounted and scripts the engine would ignore.
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  GameFileSystem files_;
  ShaderLibrary shaders_;
  std::vector<std::string> problems_;
};

/// "oa_dm1", "oa_dm1.bsp" or "maps/oa_dm1.bsp" -> "maps/oa_dm1.bsp".
std::string mapGamePath(const std::string& name);

}  // namespace q3
