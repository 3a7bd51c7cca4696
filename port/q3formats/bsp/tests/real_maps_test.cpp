// Every map of the installed OpenArena archives parses, tessellates and has spawn points.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/light_grid.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tools/pk3_maps.h"

namespace q3 {
namespace {

constexpr const char* kBaseoa = "/usr/share/games/openarena/baseoa";

TEST(RealMaps, EveryOpenArenaMapParsesAndTessellates) {
  if (!std::filesystem::exists(kBaseoa)) GTEST_SKIP() << kBaseoa << " not installed";
  tools::Pk3Reader pk3("q3_bsp_tests");
  size_t maps = 0, stitchedCracks = 0, looseCracks = 0, tJunctions = 0;
  for (const auto& archive : tools::openArenaMapArchives(kBaseoa)) {
    pk3.mount(archive);
    for (const auto& path : pk3.listMaps()) {
      SCOPED_TRACE(archive + ":" + path);
      const auto bytes = pk3.read(path);
      BspFile bsp;
      ASSERT_NO_THROW(bsp = parseBsp(bytes, path));
      std::vector<SurfaceMesh> meshes;
      ASSERT_NO_THROW(meshes = tessellateSurfaces(bsp));
      size_t triangles = 0, worldTriangles = 0;
      for (const auto& m : meshes) {
        triangles += m.indices.size() / 3;
        if (m.model == 0) worldTriangles += m.indices.size() / 3;
        ASSERT_GE(m.model, 0);
        ASSERT_LT(static_cast<size_t>(m.model), bsp.models.size());
        for (uint32_t i : m.indices) ASSERT_LT(i, m.vertices.size());
        for (const auto& v : m.vertices) {
          ASSERT_TRUE(std::isfinite(v.position.x) && std::isfinite(v.position.y) && std::isfinite(v.position.z));
          const float len = glm::length(v.normal);
          ASSERT_TRUE(len == 0 || std::abs(len - 1) < 1e-3f);
        }
      }
      EXPECT_GT(worldTriangles, 500u);   // a playable arena
      EXPECT_LT(triangles, 2'000'000u);  // and not a runaway tessellation
      const auto entities = parseEntities(bsp.entities, path);
      EXPECT_TRUE(findWorldspawn(entities).has_value());
      EXPECT_GE(readSpawnCameras(entities).size(), 1u);
      if (bsp.lightGrid.valid) {
        const auto& world = bsp.models[0];
        EXPECT_TRUE(std::isfinite(sampleLightGrid(bsp.lightGrid, 0.5f * (world.mins + world.maxs)).ambient.x));
      }
      const auto seams = measurePatchSeams(meshes);
      EXPECT_EQ(seams.cracks, 0u);  // every patch boundary shared with another is cut identically
      stitchedCracks += seams.cracks;
      tJunctions += seams.tJunctions;
      TessellationOptions loose;
      loose.stitchPatches = false;
      looseCracks += measurePatchSeams(tessellateSurfaces(bsp, loose)).cracks;
      ++maps;
    }
  }
  EXPECT_GE(maps, 40u);
  EXPECT_EQ(stitchedCracks, 0u);
  EXPECT_GT(looseCracks, 0u);
  // Left (measured 70; 900 without seam closing): vertices of trim patches laid over a closed
  // pillar, on the pillar's seam line (a boundary by index, not by position: nothing can open
  // there), vertices closer than the 0.1 tolerance to a pinched patch corner, and two identical
  // degenerate patches folding onto their own edge.
  EXPECT_LE(tJunctions, 80u);
  std::printf("[ info ] %zu maps; patch seam cracks: %zu stitched, %zu unstitched; T-junctions %zu\n", maps,
              stitchedCracks, looseCracks, tJunctions);
}

}  // namespace
}  // namespace q3
