#pragma once
// q3::SourceWorld: the parts of a parsed map the scene builder needs, already tessellated and
// bounds-checked, in plain form. buildWorldScene() fills it from a BspFile; tests fill it by
// hand, so the scene assembly is testable without a .bsp file.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/q3formats/world/world_scene.h"

namespace q3 {

/// One entry of the BSP shader lump.
struct SourceShader {
  std::string name;
  int32_t surfaceFlags = 0;
  int32_t contentFlags = 0;
};

/// One drawable BSP surface as triangles (planar faces, soups, tessellated patches).
struct SourceSurface {
  uint32_t shader = 0;          ///< Index into SourceWorld::shaders.
  int32_t lightmap = -1;        ///< Lightmap number as stored (lightmapPageOf decides its use).
  uint32_t model = 0;           ///< Owning BSP model (0 = world).
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec2> lightmapUvs;
  std::vector<glm::vec4> colors;   ///< Vertex colour bytes / 255.
  std::vector<uint32_t> indices;   ///< Counter-clockwise seen from the front (glTF winding; .bsp files store clockwise).
};

/// One entity: its key/value pairs in file order.
using SourceEntity = std::vector<std::pair<std::string, std::string>>;

/// One fog lump entry with the bounds of its brush.
struct SourceFog {
  std::string shaderName;
  WorldBounds bounds;
  std::vector<glm::vec4> planes;   ///< The brush's side planes as stored (xyz normal, w distance).
};

/// What the scene builder consumes.
struct SourceWorld {
  std::string mapName;
  std::vector<SourceShader> shaders;
  std::vector<SourceSurface> surfaces;
  std::vector<WorldBounds> modelBounds;             ///< One per BSP model.
  std::vector<SourceEntity> entities;
  std::vector<std::array<uint8_t, 128 * 128 * 3>> lightmaps;   ///< Internal lightmaps, RGB.
  /// Where external lightmaps lie ("maps/<map>", see world_external_lightmaps.h): read, numbered
  /// from lm_0000, when there are no internal lightmaps and a surface has a lightmap number.
  std::string externalLightmapFolder;
  std::vector<SourceFog> fogs;
  WorldLightGrid lightGrid;
};

/// Assembles the scene: materials from the shader library (implicit shader when missing),
/// textures through loadFile (fallback + warning when missing), lightmaps (internal, else
/// external), meshes grouped per model by (material, lightmap), lights/sky/sun/cameras/fogs.
/// A surface whose lightmap number selects no lightmap is drawn vertex-lit, with one warning
/// per map; a shader that names its own lightmap image (q3map2) uses that image.
WorldScene assembleWorldScene(const SourceWorld& source, const ShaderLibrary& shaders, const FileLoader& loadFile,
                              const WorldBuildOptions& options = {});

/// Lights and cameras from the entity list (light, spot via target, spawn points, intermission)
/// and the first worldspawn's ambient light keys (scene.ambientLight / minimumLight).
/// Appends to scene.lights / scene.cameras, problems to scene.warnings.
void addEntityLightsAndCameras(const std::vector<SourceEntity>& entities, WorldScene& scene);

}  // namespace q3
