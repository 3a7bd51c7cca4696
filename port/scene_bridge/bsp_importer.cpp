// BspImporter: map location, scene build, light recovery and upload, cameras at spawn points.
#include "port/scene_bridge/bsp_importer.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <glm/trigonometric.hpp>

#include "port/light_recovery/recover_lights.h"
#include "port/q3formats/world/world_game.h"
#include "port/scene_bridge/scene_bridge.h"

namespace pa::bridge {
namespace {

constexpr float kQuakeFovYDegrees = 73.74f;   // fov_x 90 on a 4:3 screen

std::vector<std::byte> readLooseFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error(path.string() + ": cannot open");
  std::vector<char> chars((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(chars.size());
  std::memcpy(bytes.data(), chars.data(), chars.size());
  return bytes;
}

// Registers the importer with pa-render when this object file is linked in (OBJECT library).
const bool kRegistered = [] {
  cli::registerSceneImporter(std::make_unique<BspImporter>());
  return true;
}();

}  // namespace

MapLocation locateMap(const std::filesystem::path& path, const char* envGameDir) {
  MapLocation where;
  const std::filesystem::path parent = path.parent_path();
  if (parent.filename() == "maps" && !parent.parent_path().empty() && !std::filesystem::exists(path)) {
    where.gameDir = parent.parent_path();
    where.mapPath = "maps/" + path.filename().string();
    return where;
  }
  where.gameDir = envGameDir && *envGameDir ? std::filesystem::path(envGameDir) : std::filesystem::path(kDefaultGameDir);
  if (parent.filename() == "maps" && !std::filesystem::exists(path) && parent.parent_path().empty()) {
    where.mapPath = "maps/" + path.filename().string();
  } else if (std::filesystem::exists(path)) {
    where.looseFile = path;
  } else {
    where.mapPath = q3::mapGamePath(path.filename().string());
  }
  return where;
}

q3::WorldScene loadMapScene(const MapLocation& where, std::vector<std::string>* problems) {
  q3::GameWorlds game(where.gameDir);
  q3::WorldScene scene = where.looseFile.empty() ? game.load(where.mapPath)
                                                 : game.build(readLooseFile(where.looseFile), where.looseFile.string());
  recovery::applyRecoveredLights(scene, recovery::recoverLights(scene));
  if (problems) *problems = game.problems();
  return scene;
}

std::span<const std::string_view> BspImporter::extensions() const {
  static constexpr std::array<std::string_view, 1> kExtensions = {".bsp"};
  return kExtensions;
}

cli::ImportedScene BspImporter::load(const std::filesystem::path& path, Renderer& renderer,
                                     const cli::ImportOptions& options) const {
  (void)kRegistered;
  const MapLocation where = locateMap(path, std::getenv("PA_GAME_DIR"));
  std::vector<std::string> problems;
  const q3::WorldScene scene = loadMapScene(where, &problems);
  UploadOptions upload;
  upload.lightScale = options.lightScale;
  const WorldHandles handles = uploadWorld(scene, renderer, upload);
  showSkyAndFog(handles, renderer);

  cli::ImportedScene out;
  out.worldUp = glm::vec3(0.0f, 0.0f, 1.0f);
  out.triangles = handles.triangles;
  out.lights = handles.lights.size();
  out.warnings = std::move(problems);
  out.warnings.insert(out.warnings.end(), scene.warnings.begin(), scene.warnings.end());
  if (!scene.models.empty() && !scene.models[0].bounds.empty()) {
    out.boundsMin = scene.models[0].bounds.mins;
    out.boundsMax = scene.models[0].bounds.maxs;
  }
  for (const q3::WorldCamera& spawn : scene.cameras) {
    cli::ImportedCamera camera;
    camera.name = spawn.name;
    camera.origin = spawn.eye;
    camera.forward = spawn.forward;
    camera.left = spawn.left;
    camera.up = spawn.up;
    camera.yfovRadians = glm::radians(kQuakeFovYDegrees);
    camera.aspectRatio = 4.0f / 3.0f;
    out.cameras.push_back(camera);
  }
  return out;
}

}  // namespace pa::bridge
