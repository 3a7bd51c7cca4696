// buildWorldScene: BspFile (and its tessellation) -> SourceWorld (plain) -> assembleWorldScene.
#include <cmath>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/common/format_error.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/world/world_external_lightmaps.h"
#include "port/q3formats/world/world_source.h"

namespace q3 {
namespace {

/// Bounds of a fog brush from its axial sides (q3map writes the six axial planes of every brush).
WorldBounds fogBrushBounds(const BspFile& bsp, int32_t brushIndex) {
  WorldBounds bounds;
  if (brushIndex < 0 || size_t(brushIndex) >= bsp.brushes.size()) return bounds;
  const BspBrush& brush = bsp.brushes[size_t(brushIndex)];
  glm::vec3 mins(-3.0e38f), maxs(3.0e38f);
  for (int32_t s = 0; s < brush.numSides; ++s) {
    size_t sideIndex = size_t(brush.firstSide) + size_t(s);
    if (sideIndex >= bsp.brushSides.size()) break;
    int32_t planeIndex = bsp.brushSides[sideIndex].plane;
    if (planeIndex < 0 || size_t(planeIndex) >= bsp.planes.size()) continue;
    const BspPlane& plane = bsp.planes[size_t(planeIndex)];
    for (int axis = 0; axis < 3; ++axis) {
      if (plane.normal[axis] == 1.0f) maxs[axis] = std::min(maxs[axis], plane.dist);
      if (plane.normal[axis] == -1.0f) mins[axis] = std::max(mins[axis], -plane.dist);
    }
  }
  if (mins.x <= maxs.x && mins.y <= maxs.y && mins.z <= maxs.z && maxs.x < 1.0e38f && mins.x > -1.0e38f) {
    bounds.extend(mins);
    bounds.extend(maxs);
  }
  return bounds;
}

/// Side planes of a fog brush (outward normals, as q3map writes brush sides); out-of-range
/// side or plane indices are skipped (the builder validates what is left).
std::vector<glm::vec4> fogBrushPlanes(const BspFile& bsp, int32_t brushIndex) {
  std::vector<glm::vec4> planes;
  if (brushIndex < 0 || size_t(brushIndex) >= bsp.brushes.size()) return planes;
  const BspBrush& brush = bsp.brushes[size_t(brushIndex)];
  for (int32_t s = 0; s < brush.numSides; ++s) {
    const size_t sideIndex = size_t(brush.firstSide) + size_t(s);
    if (brush.firstSide < 0 || sideIndex >= bsp.brushSides.size()) break;
    const int32_t planeIndex = bsp.brushSides[sideIndex].plane;
    if (planeIndex < 0 || size_t(planeIndex) >= bsp.planes.size()) continue;
    const BspPlane& plane = bsp.planes[size_t(planeIndex)];
    planes.emplace_back(plane.normal, plane.dist);
  }
  return planes;
}

}  // namespace

WorldScene buildWorldScene(const BspFile& bsp, const ShaderLibrary& shaders, const FileLoader& loadFile,
                           const WorldBuildOptions& options) {
  return buildWorldScene(bsp, tessellateSurfaces(bsp, worldTessellation(options)), shaders, loadFile, options);
}

WorldScene buildWorldScene(const BspFile& bsp, std::span<const SurfaceMesh> surfaces, const ShaderLibrary& shaders,
                           const FileLoader& loadFile, const WorldBuildOptions& options) {
  SourceWorld source;
  source.mapName = bsp.fileName;
  for (const BspShader& s : bsp.shaders) source.shaders.push_back({s.name, s.surfaceFlags, s.contentFlags});
  for (const BspModel& m : bsp.models) {
    WorldBounds b;
    b.extend(m.mins);
    b.extend(m.maxs);
    source.modelBounds.push_back(b);
  }

  // Planar faces, soups and crack-free patches, counter-clockwise (port/q3formats/bsp/tessellate.h).
  for (const SurfaceMesh& mesh : surfaces) {
    if (mesh.model < 0) continue;   // listed by no model: never drawn by the engine
    SourceSurface out;
    out.shader = uint32_t(mesh.shader);
    out.lightmap = mesh.lightmap;
    out.model = uint32_t(mesh.model);
    const size_t n = mesh.vertices.size();
    out.positions.reserve(n);
    for (const MeshVertex& v : mesh.vertices) {
      out.positions.push_back(v.position);
      out.normals.push_back(v.normal);
      out.uvs.push_back(v.uv);
      out.lightmapUvs.push_back(v.lightmapUv);
      out.colors.push_back(glm::vec4(v.color[0], v.color[1], v.color[2], v.color[3]) / 255.0f);
    }
    out.indices = mesh.indices;
    source.surfaces.push_back(std::move(out));
  }

  std::vector<std::string> entityWarnings;
  try {
    for (Entity& e : parseEntities(bsp.entities, bsp.fileName)) source.entities.push_back(std::move(e.keys));
  } catch (const FormatError& e) {
    entityWarnings.push_back(std::string(e.what()) + ": entities ignored (no lights, no cameras)");
  }

  for (size_t page = 0; page < bsp.numLightmaps(); ++page) {
    auto bytes = bsp.lightmapPage(page);
    auto& rgb = source.lightmaps.emplace_back();
    std::copy(bytes.begin(), bytes.begin() + std::min(bytes.size(), rgb.size()), rgb.begin());
  }

  source.externalLightmapFolder = externalLightmapFolder(bsp.fileName);

  for (const BspFog& fog : bsp.fogs)
    source.fogs.push_back({fog.shaderName, fogBrushBounds(bsp, fog.brush), fogBrushPlanes(bsp, fog.brush)});

  if (bsp.lightGrid.valid) {
    WorldLightGrid& grid = source.lightGrid;
    grid.origin = bsp.lightGrid.origin;
    grid.cellSize = bsp.lightGrid.gridSize;
    grid.counts = {bsp.lightGrid.dims.x, bsp.lightGrid.dims.y, bsp.lightGrid.dims.z};
    grid.samples.resize(bsp.lightGrid.raw.size() / 8);
    for (size_t s = 0; s < grid.samples.size(); ++s)
      std::copy_n(bsp.lightGrid.raw.begin() + ptrdiff_t(s * 8), 8, grid.samples[s].begin());
  }

  WorldScene scene = assembleWorldScene(source, shaders, loadFile, options);
  scene.warnings.insert(scene.warnings.begin(), entityWarnings.begin(), entityWarnings.end());
  scene.warnings.insert(scene.warnings.begin(), bsp.warnings.begin(), bsp.warnings.end());
  return scene;
}

}  // namespace q3
