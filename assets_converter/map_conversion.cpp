// Game folder loading and single-map conversion.
#include "assets_converter/map_conversion.h"

#include <algorithm>
#include <chrono>
#include <fstream>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::converter {

GameData::GameData(const std::filesystem::path& gameDir) : files(gameDir) {
  std::vector<std::string> scripts = q3::scriptsInPriorityOrder(files.listFiles("scripts", ".shader"));
  for (const std::string& script : scripts) {
    auto bytes = files.readFile(script);
    if (!bytes) continue;
    std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    shaders.addScript(text, script);
  }
  scriptErrors = shaders.errors();
}

std::vector<std::string> listMaps(const q3::GameFileSystem& files) {
  std::vector<std::string> maps = files.listFiles("maps", ".bsp");
  std::sort(maps.begin(), maps.end());
  return maps;
}

std::string mapPath(const std::string& name) {
  std::string path = name;
  if (path.rfind("maps/", 0) != 0) path = "maps/" + path;
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".bsp") != 0) path += ".bsp";
  return path;
}

MapResult convertMap(const GameData& game, const std::string& map, const std::filesystem::path& outDir,
                     const ExportOptions& options) {
  MapResult result;
  result.map = mapPath(map);
  const auto start = std::chrono::steady_clock::now();
  try {
    auto bytes = game.files.readFile(result.map);
    if (!bytes) {
      result.error = result.map + ": not found in the game folder";
      return result;
    }
    q3::BspFile bsp = q3::parseBsp(*bytes, result.map);
    q3::FileLoader loader = [&game](std::string_view path) { return game.files.readFile(path); };
    q3::WorldScene scene = q3::buildWorldScene(bsp, game.shaders, loader);
    result.warnings = scene.warnings;
    std::vector<std::byte> glb = exportGlb(scene, options, &result.stats);

    std::filesystem::create_directories(outDir);
    std::string stem = std::filesystem::path(result.map).stem().string();
    std::filesystem::path out = outDir / (stem + ".glb");
    std::ofstream file(out, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
    file.close();
    if (!file) {
      result.error = out.string() + ": write failed";
    } else {
      result.output = out;
    }
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace pa::converter
