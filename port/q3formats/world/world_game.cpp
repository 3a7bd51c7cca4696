// GameWorlds: game folder + shader scripts -> WorldScene per map.
#include "port/q3formats/world/world_game.h"

#include <algorithm>
#include <stdexcept>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3 {

GameWorlds::GameWorlds(const std::filesystem::path& gameDir) : files_(gameDir) {
  problems_ = files_.mountErrors();
  for (const std::string& script : scriptsInPriorityOrder(files_.listFiles("scripts", ".shader"))) {
    auto bytes = files_.readFile(script);
    if (!bytes) continue;
    shaders_.addScript(std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()), script);
  }
  for (const std::string& error : shaders_.errors()) problems_.push_back("shader script ignored: " + error);
}

std::vector<std::string> GameWorlds::maps() const {
  std::vector<std::string> maps = files_.listFiles("maps", ".bsp");
  std::sort(maps.begin(), maps.end());
  return maps;
}

WorldScene GameWorlds::load(const std::string& map, const WorldBuildOptions& options) const {
  const std::string path = mapGamePath(map);
  auto bytes = files_.readFile(path);
  if (!bytes) throw std::runtime_error(path + ": not found in the game folder");
  return build(*bytes, path, options);
}

WorldScene GameWorlds::build(std::span<const std::byte> bspBytes, const std::string& name,
                             const WorldBuildOptions& options) const {
  BspFile bsp = parseBsp(bspBytes, name);
  FileLoader loader = [this](std::string_view file) { return files_.readFile(file); };
  return buildWorldScene(bsp, shaders_, loader, options);
}

std::string mapGamePath(const std::string& name) {
  std::string path = name;
  if (path.rfind("maps/", 0) != 0) path = "maps/" + path;
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".bsp") != 0) path += ".bsp";
  return path;
}

}  // namespace q3
