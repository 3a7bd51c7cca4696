// Known-answer tests: a map written by BspWriter decodes to the same values.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/common/format_error.h"

namespace q3 {
namespace {

TEST(BspParse, DecodesEveryLumpOfTheSampleMap) {
  const auto bytes = testing::sampleMap().build();
  const BspFile bsp = parseBsp(bytes, "sample.bsp");
  EXPECT_EQ(bsp.fileName, "sample.bsp");
  EXPECT_TRUE(bsp.entities.starts_with("{\n\"classname\" \"worldspawn\""));
  ASSERT_EQ(bsp.shaders.size(), 2u);
  EXPECT_EQ(bsp.shaders[1].name, "textures/test/fog");
  EXPECT_EQ(bsp.shaders[1].contentFlags, 0x40);
  ASSERT_EQ(bsp.planes.size(), 2u);
  EXPECT_EQ(bsp.planes[1].normal, glm::vec3(0, 0, -1));
  EXPECT_EQ(bsp.planes[1].dist, 64.0f);
  ASSERT_EQ(bsp.nodes.size(), 1u);
  EXPECT_EQ(bsp.nodes[0].children[0], -1);
  EXPECT_EQ(bsp.nodes[0].maxs, glm::ivec3(256, 256, 64));
  ASSERT_EQ(bsp.leafs.size(), 1u);
  EXPECT_EQ(bsp.leafs[0].numLeafSurfaces, 2);
  EXPECT_EQ(bsp.leafSurfaces, (std::vector<int32_t>{0, 1}));
  EXPECT_EQ(bsp.leafBrushes, (std::vector<int32_t>{0}));
  ASSERT_EQ(bsp.models.size(), 2u);
  EXPECT_EQ(bsp.models[1].firstSurface, 2);
  EXPECT_EQ(bsp.models[0].maxs, glm::vec3(256, 256, 64));
  ASSERT_EQ(bsp.brushes.size(), 1u);
  EXPECT_EQ(bsp.brushes[0].numSides, 2);
  EXPECT_EQ(bsp.brushSides[1].plane, 1);
  ASSERT_EQ(bsp.drawVerts.size(), 4u + 15u + 4u);
  EXPECT_EQ(bsp.drawVerts[5].position, glm::vec3(64, 0, 64));
  EXPECT_EQ(bsp.drawVerts[5].color, (std::array<uint8_t, 4>{200, 100, 50, 255}));
  EXPECT_EQ(bsp.drawVerts[1].st, glm::vec2(1, 0));
  EXPECT_EQ(bsp.drawIndexes.size(), 12u);
  ASSERT_EQ(bsp.fogs.size(), 1u);
  EXPECT_EQ(bsp.fogs[0].shaderName, "textures/test/fog");
  EXPECT_EQ(bsp.fogs[0].visibleSide, 1);
  ASSERT_EQ(bsp.surfaces.size(), 3u);
  EXPECT_EQ(bsp.surfaces[1].type, SurfaceType::Patch);
  EXPECT_EQ(bsp.surfaces[1].patchWidth, 5);
  EXPECT_EQ(bsp.surfaces[1].fog, 0);
  EXPECT_EQ(bsp.surfaces[0].lightmap, 0);
  EXPECT_EQ(bsp.surfaces[0].lightmapVecs[2], glm::vec3(0, 0, 1));
  ASSERT_EQ(bsp.numLightmaps(), 1u);
  EXPECT_EQ(bsp.lightmapPage(0)[0], 255);
  EXPECT_EQ(bsp.lightmapPage(0)[1], 0);
  EXPECT_THROW(bsp.lightmapPage(1), std::out_of_range);
  EXPECT_TRUE(bsp.lightGrid.valid);
  EXPECT_EQ(bsp.lightGrid.gridSize, glm::vec3(128, 128, 256));
  EXPECT_EQ(bsp.lightGrid.dims, glm::ivec3(3, 3, 1));
  EXPECT_EQ(bsp.lightGrid.origin, glm::vec3(0, 0, 0));
  EXPECT_EQ(bsp.visibility.numClusters, 1);
  EXPECT_TRUE(bsp.visibility.clusterVisible(0, 0));
  EXPECT_TRUE(bsp.warnings.empty());
  EXPECT_EQ(bsp.modelOfSurface(1), 0);
  EXPECT_EQ(bsp.modelOfSurface(2), 1);
}

TEST(BspParse, VisibilityBitsAreReadPerCluster) {
  auto w = testing::sampleMap();
  w.visibility = {3, 0, 0, 0, 1, 0, 0, 0, 0b101, 0b010, 0b100};
  const BspFile bsp = parseBsp(w.build(), "vis.bsp");
  EXPECT_TRUE(bsp.visibility.clusterVisible(0, 2));
  EXPECT_FALSE(bsp.visibility.clusterVisible(0, 1));
  EXPECT_TRUE(bsp.visibility.clusterVisible(1, 1));
  EXPECT_FALSE(bsp.visibility.clusterVisible(2, 0));
  EXPECT_TRUE(bsp.visibility.clusterVisible(-1, 0));  // outside the level: no culling
}

TEST(BspParse, ToleratesShippedOddities) {
  auto w = testing::sampleMap();
  w.drawVerts[0].lightmap.x = std::numeric_limits<float>::quiet_NaN();  // q3map2 vertex-lit faces
  w.fogs.clear();                                                       // surface 1 keeps fog 0
  const BspFile bsp = parseBsp(w.build(), "odd.bsp");
  EXPECT_EQ(bsp.drawVerts[0].lightmap.x, 0.0f);
  EXPECT_EQ(bsp.surfaces[1].fog, -1);
  EXPECT_EQ(bsp.warnings.size(), 2u);
}

TEST(BspParse, LoadsWhatTheEngineLoadsWithExternalOrMissingLightmaps) {
  // q3map2 -external: an empty lump, lightmap numbers counting the lm_NNNN.tga files beside it.
  auto w = testing::sampleMap();
  w.lightmaps.clear();
  w.surfaces[0].lightmap = 3;
  w.surfaces[1].lightmap = -7;   // below LIGHTMAP_2D: the engine warns and lights by vertex
  const BspFile bsp = parseBsp(w.build(), "external.bsp");
  EXPECT_EQ(bsp.numLightmaps(), 0u);
  EXPECT_EQ(bsp.surfaces[0].lightmap, 3);   // kept as written: the scene builder decides
  EXPECT_EQ(bsp.surfaces[1].lightmap, -7);
  EXPECT_TRUE(bsp.warnings.empty());
}

TEST(BspParse, PartialLightmapPageIsDroppedWithOneWarning) {
  auto w = testing::sampleMap();
  w.lightmaps.resize(w.lightmaps.size() + 1000, 7);   // the engine reads whole pages only
  const BspFile bsp = parseBsp(w.build(), "partial.bsp");
  EXPECT_EQ(bsp.numLightmaps(), 1u);
  EXPECT_EQ(bsp.lightmaps.size(), size_t(kLightmapSize) * kLightmapSize * 3);
  ASSERT_EQ(bsp.warnings.size(), 1u);
  EXPECT_NE(bsp.warnings[0].find("1000 bytes"), std::string::npos);
}

TEST(BspParse, LightmapPageOfIsTheOneRuleForLightmapNumbers) {
  EXPECT_EQ(lightmapPageOf(0, 2), 0);
  EXPECT_EQ(lightmapPageOf(1, 2), 1);
  EXPECT_EQ(lightmapPageOf(2, 2), -1);            // past the last page: vertex light
  EXPECT_EQ(lightmapPageOf(0, 0), -1);            // external lightmaps not found
  EXPECT_EQ(lightmapPageOf(kLightmapByVertex, 2), -1);
  EXPECT_EQ(lightmapPageOf(kLightmapWhiteImage, 2), -1);
  EXPECT_EQ(lightmapPageOf(INT32_MIN, 2), -1);
  EXPECT_EQ(lightmapPageOf(INT32_MAX, size_t(1) << 40), INT32_MAX);
}

TEST(BspParse, LightGridSizeMismatchIsAWarningNotAnError) {
  auto w = testing::sampleMap();
  w.lightGrid.resize(8 * 5);
  const BspFile bsp = parseBsp(w.build(), "grid.bsp");
  EXPECT_FALSE(bsp.lightGrid.valid);
  ASSERT_EQ(bsp.warnings.size(), 1u);
  EXPECT_NE(bsp.warnings[0].find("light grid"), std::string::npos);
}

TEST(Tessellate, PlanarFacesAreCounterClockwiseAndKeepAttributes) {
  const BspFile bsp = parseBsp(testing::sampleMap().build(), "sample.bsp");
  TessellationOptions copyOnly;
  copyOnly.seamTolerance = 0;  // the wave patch touches the quad's edges: seam closing would split it
  const auto meshes = tessellateSurfaces(bsp, copyOnly);
  ASSERT_EQ(meshes.size(), 3u);
  const auto& quad = meshes[0];
  EXPECT_EQ(quad.type, SurfaceType::Planar);
  EXPECT_EQ(quad.lightmap, 0);
  EXPECT_EQ(quad.model, 0);
  ASSERT_EQ(quad.indices.size(), 6u);
  EXPECT_EQ(quad.vertices.size(), 4u);
  for (size_t t = 0; t < quad.indices.size(); t += 3) {
    const auto& a = quad.vertices[quad.indices[t]].position;
    const auto& b = quad.vertices[quad.indices[t + 1]].position;
    const auto& c = quad.vertices[quad.indices[t + 2]].position;
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), glm::vec3(0, 0, 1)), 0);
  }
  EXPECT_EQ(meshes[1].type, SurfaceType::Patch);
  EXPECT_EQ(meshes[1].fog, 0);
  EXPECT_EQ(meshes[2].model, 1);  // the door "*1"
  EXPECT_EQ(meshes[2].surfaceIndex, 2u);
}

TEST(Tessellate, FlaresAreSkipped) {
  auto w = testing::sampleMap();
  BspSurface flare;
  flare.type = SurfaceType::Flare;
  flare.firstVert = 9999;  // flares carry no geometry: ranges are not used
  w.surfaces.push_back(flare);
  const BspFile bsp = parseBsp(w.build(), "flare.bsp");
  EXPECT_EQ(bsp.surfaces.size(), 4u);
  EXPECT_EQ(tessellateSurfaces(bsp).size(), 3u);
}

TEST(Tessellate, VertexBudgetThrowsFormatError) {
  const BspFile bsp = parseBsp(testing::sampleMap().build(), "sample.bsp");
  TessellationOptions options;
  options.maxTotalVertices = 10;
  EXPECT_THROW(tessellateSurfaces(bsp, options), FormatError);
  options = {};
  options.maxError = 0;
  EXPECT_THROW(tessellateSurfaces(bsp, options), std::invalid_argument);
}

}  // namespace
}  // namespace q3
