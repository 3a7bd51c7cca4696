// Single-map conversion: game folder -> WorldScene with its recovered lights -> .glb file.
#include "assets_converter/map_conversion.h"

#include <chrono>
#include <ctime>
#include <fstream>

#include "port/light_recovery/recover_lights.h"

namespace pa::converter {

MapResult convertMap(const q3::GameWorlds& game, const std::string& map, const std::filesystem::path& outDir,
                     const ExportOptions& options) {
  MapResult result;
  result.map = q3::mapGamePath(map);
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpuStart = std::clock();
  try {
    q3::WorldScene scene = game.load(result.map);
    if (options.lights) pa::recovery::applyRecoveredLights(scene, pa::recovery::recoverLights(scene));   // the lights the game renders
    result.warnings = scene.warnings;
    std::vector<std::byte> glb = exportGlb(scene, options, &result.stats);

    std::filesystem::create_directories(outDir);
    std::filesystem::path out = outDir / (std::filesystem::path(result.map).stem().string() + ".glb");
    std::ofstream file(out, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
    file.close();
    if (!file)
      result.error = out.string() + ": write failed";
    else
      result.output = out;
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
  return result;
}

}  // namespace pa::converter
