// libFuzzer harness: parse + tessellate + entities + light grid must only ever throw FormatError.
#include <cstddef>
#include <cstdint>
#include <span>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/light_grid.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/common/format_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    const q3::BspFile bsp = q3::parseBsp(bytes, "fuzz.bsp");
    q3::TessellationOptions options;
    options.maxTotalVertices = 1 << 20;  // keep each run small; the budget check itself is under test
    const auto meshes = q3::tessellateSurfaces(bsp, options);
    for (const auto& mesh : meshes)
      for (uint32_t index : mesh.indices)
        if (index >= mesh.vertices.size()) __builtin_trap();
    q3::measurePatchSeams(meshes);
    q3::sampleLightGrid(bsp.lightGrid, bsp.models[0].mins);
    q3::sampleLightGrid(bsp.lightGrid, 0.5f * (bsp.models[0].mins + bsp.models[0].maxs));
    for (int32_t c = -1; c <= bsp.visibility.numClusters; ++c) bsp.visibility.clusterVisible(c, 0);
    const auto entities = q3::parseEntities(bsp.entities, bsp.fileName);
    q3::readWorldspawn(entities);
    q3::readLights(entities);
    q3::readSpawnCameras(entities);
  } catch (const q3::FormatError&) {
  }
  // The entity parser also sees raw text, so its grammar is explored directly.
  try {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    q3::readLights(q3::parseEntities(text, "fuzz.ent"));
  } catch (const q3::FormatError&) {
  }
  return 0;
}
