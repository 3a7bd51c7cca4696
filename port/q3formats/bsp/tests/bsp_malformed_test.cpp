// Hostile input: every malformed file must throw FormatError naming the file and field.
#include <gtest/gtest.h>

#include <climits>
#include <functional>
#include <random>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/common/format_error.h"

namespace q3 {
namespace {

/// Expects parseBsp to throw FormatError whose message names the file and contains `field`.
void expectRejected(const std::vector<std::byte>& bytes, const std::string& field) {
  try {
    parseBsp(bytes, "bad.bsp");
    ADD_FAILURE() << "accepted a file that should fail on " << field;
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), "bad.bsp");
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

void expectRejected(const std::function<void(testing::BspWriter&)>& corrupt, const std::string& field) {
  auto w = testing::sampleMap();
  corrupt(w);
  expectRejected(w.build(), field);
}

TEST(BspMalformed, HeaderProblems) {
  expectRejected(std::vector<std::byte>{}, "header");
  expectRejected(std::vector<std::byte>(100), "header");
  auto bytes = testing::sampleMap().build();
  bytes[0] = std::byte{'V'};
  expectRejected(bytes, "magic");
  expectRejected([](auto& w) { w.version = 47; }, "version");
}

TEST(BspMalformed, EveryLumpWithAPartialElement) {
  // The lightmaps lump (14) is the exception the engine makes: a partial page is dropped
  // (BspParse.PartialLightmapPageIsDroppedWithOneWarning).
  for (int lump = 1; lump < 14; ++lump) {
    SCOPED_TRACE(bspLumpName(static_cast<BspLump>(lump)));
    auto w = testing::sampleMap();
    auto bytes = w.build();
    int32_t offset, length;
    std::memcpy(&offset, bytes.data() + 8 + lump * 8, 4);
    std::memcpy(&length, bytes.data() + 12 + lump * 8, 4);
    std::vector<std::byte> raw(bytes.begin() + offset, bytes.begin() + offset + length);
    raw.push_back(std::byte{0});
    w.rawLumps[lump] = raw;
    expectRejected(w.build(), "not a multiple");
  }
}

TEST(BspMalformed, EveryLumpOutsideTheFileOrNegative) {
  const int32_t fileSize = static_cast<int32_t>(testing::sampleMap().build().size());
  for (int lump = 0; lump < 17; ++lump) {
    SCOPED_TRACE(bspLumpName(static_cast<BspLump>(lump)));
    const std::string field = std::string("lump table ") + bspLumpName(static_cast<BspLump>(lump));
    expectRejected([&](auto& w) { w.lumpOverride[lump] = {fileSize - 4, 72 * 10}; }, field);
    expectRejected([&](auto& w) { w.lumpOverride[lump] = {-8, 0}; }, field);
    expectRejected([&](auto& w) { w.lumpOverride[lump] = {0, -72}; }, field);
    expectRejected([&](auto& w) { w.lumpOverride[lump] = {INT_MAX - 8, 72 * 100}; }, field);
  }
}

TEST(BspMalformed, EveryTruncationOfAValidFileIsRejectedOrParsesCleanly) {
  const auto bytes = testing::sampleMap().build();
  for (size_t size = 0; size < bytes.size(); ++size) {
    const std::span<const std::byte> prefix(bytes.data(), size);
    try {
      parseBsp(prefix, "cut.bsp");
      // Only the alignment padding after the last lump may be dropped.
      EXPECT_GE(size, bytes.size() - 3);
    } catch (const FormatError& e) {
      EXPECT_EQ(e.file(), "cut.bsp");
    }
  }
}

TEST(BspMalformed, OutOfRangeReferences) {
  using W = testing::BspWriter;
  const std::vector<std::pair<std::function<void(W&)>, std::string>> cases = {
      {[](W& w) { w.surfaces[0].shader = 2; }, "shader 2 outside [0, 2)"},
      {[](W& w) { w.surfaces[0].shader = -1; }, "shader -1"},
      {[](W& w) { w.surfaces[0].firstVert = 20; }, "vertices range"},
      {[](W& w) { w.surfaces[0].numVerts = -4; }, "vertices range"},
      {[](W& w) { w.surfaces[0].firstIndex = -1; }, "indexes range"},
      {[](W& w) { w.surfaces[0].numIndexes = 5; }, "not a multiple of 3"},
      {[](W& w) { w.drawIndexes[2] = 4; }, "vertex index 4"},
      {[](W& w) { w.drawIndexes[2] = -1; }, "vertex index -1"},
      {[](W& w) { w.surfaces[0].type = static_cast<SurfaceType>(7); }, "unknown surface type 7"},
      {[](W& w) { w.surfaces[1].patchWidth = 4; }, "patch size"},
      {[](W& w) { w.surfaces[1].patchWidth = 1; }, "patch size"},
      {[](W& w) { w.surfaces[1].patchWidth = 33; w.surfaces[1].patchHeight = 1; }, "patch size"},
      {[](W& w) { w.surfaces[1].patchHeight = 5; }, "does not match"},
      {[](W& w) { w.nodes[0].children[0] = 0; }, "does not follow its parent"},
      {[](W& w) { w.nodes[0].children[1] = -3; }, "child leaf 2"},
      {[](W& w) { w.nodes[0].plane = 2; }, "plane 2"},
      {[](W& w) { w.leafs[0].numLeafSurfaces = 3; }, "leaf surfaces range"},
      {[](W& w) { w.leafs[0].firstLeafBrush = -1; }, "leaf brushes range"},
      {[](W& w) { w.leafs[0].cluster = 1; }, "cluster 1"},
      {[](W& w) { w.leafs[0].area = -2; }, "area -2"},
      {[](W& w) { w.leafSurfaces[1] = 3; }, "surface 3"},
      {[](W& w) { w.leafBrushes[0] = 1; }, "brush 1"},
      {[](W& w) { w.models[1].numSurfaces = 2; }, "surfaces range"},
      {[](W& w) { w.models[0].firstBrush = 1; }, "brushes range"},
      {[](W& w) { w.models.clear(); }, "no world model"},
      {[](W& w) { w.brushes[0].numSides = 3; }, "sides range"},
      {[](W& w) { w.brushes[0].shader = 9; }, "shader 9"},
      {[](W& w) { w.brushSides[0].plane = -1; }, "plane -1"},
      {[](W& w) { w.fogs[0].brush = 1; }, "brush 1"},
      {[](W& w) { w.fogs[0].visibleSide = 2; }, "visible side 2"},
      {[](W& w) { w.visibility = {1, 0, 0, 0, 1, 0, 0, 0}; }, "exceed the lump"},
      {[](W& w) { w.visibility = {0xff, 0xff, 0xff, 0xff, 1, 0, 0, 0, 0}; }, "negative"},
      {[](W& w) { w.visibility = {9, 0, 0, 0, 1, 0, 0, 0, 0}; }, "cannot hold"},
      {[](W& w) { w.visibility = {1, 0}; }, "cannot hold the 8-byte header"},
      {[](W& w) { w.drawVerts[3].position.y = std::numeric_limits<float>::infinity(); }, "non-finite"},
      {[](W& w) { w.planes[0].dist = std::numeric_limits<float>::quiet_NaN(); }, "non-finite"},
  };
  for (const auto& [corrupt, field] : cases) {
    SCOPED_TRACE(field);
    expectRejected(corrupt, field);
  }
}

/// Random corruption of a valid map: every outcome is a parsed map or a FormatError,
/// and parsed maps must tessellate (or hit the budget) and yield in-range indices.
TEST(BspMalformed, RandomCorruptionNeverCrashes) {
  const auto original = testing::sampleMap().build();
  std::mt19937 rng(1234);
  int parsed = 0;
  for (int iteration = 0; iteration < 4000; ++iteration) {
    auto bytes = original;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] = static_cast<std::byte>(rng());
    try {
      const BspFile bsp = parseBsp(bytes, "random.bsp");
      TessellationOptions options;
      options.maxTotalVertices = 1 << 20;
      for (const auto& mesh : tessellateSurfaces(bsp, options))
        for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertices.size());
      const auto entities = parseEntities(bsp.entities, bsp.fileName);
      readLights(entities);
      readSpawnCameras(entities);
      ++parsed;
    } catch (const FormatError&) {
    }
  }
  EXPECT_GT(parsed, 100);  // many corruptions hit unchecked payload (colours, flags)
}

}  // namespace
}  // namespace q3
