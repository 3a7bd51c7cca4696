#include "port/engine_glue/world.h"

#include <algorithm>
#include <cstring>
#include <span>
#include <utility>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/light_grid.h"
#include "port/q3formats/bsp/tessellate.h"
#include "port/q3formats/world/world_scene.h"

namespace glue {
namespace {

/// r_mapOverBrightBits (2) minus tr.overbrightBits (0: no hardware gamma, as in a window).
constexpr int kMapOverbrightShift = 2;
/// The engine's MAX_TOKEN_CHARS less the terminating NUL.
constexpr size_t kMaxTokenLength = 1023;

q3::Tokenizer entityTokenizer(const q3::BspFile& bsp) {
  q3::Tokenizer::Options options;
  options.maxTokenLength = kMaxTokenLength;
  return q3::Tokenizer(bsp.entities, bsp.fileName, options);
}

}  // namespace

World::World(const std::vector<uint8_t>& bytes, const std::string& name,
             std::shared_ptr<const q3::ShaderLibrary> shaders)
    : bsp_(q3::parseBsp(std::as_bytes(std::span(bytes)), name)),
      surfaces_(q3::tessellateSurfaces(bsp_, q3::worldTessellation())),
      shaders_(std::move(shaders)),
      entityTokens_(entityTokenizer(bsp_)),
      shiftedGrid_(q3::shiftLightGridColors(bsp_.lightGrid, kMapOverbrightShift)) {
  // Decals land on the triangles the tracer draws (the scene is built from surfaces_), turned
  // back to Quake's clockwise winding.
  markSurfaces_.resize(bsp_.surfaces.size());
  for (const q3::SurfaceMesh& mesh : surfaces_) {
    if (mesh.model != 0 || mesh.surfaceIndex >= bsp_.surfaces.size()) continue;   // movers take no marks
    const q3::BspSurface& surface = bsp_.surfaces[mesh.surfaceIndex];
    const q3::BspShader& shader = bsp_.shaders[static_cast<size_t>(surface.shader)];
    if ((shader.surfaceFlags & (q3::kSurfNoImpact | q3::kSurfNoMarks)) || (shader.contentFlags & q3::kContentsFog))
      continue;
    MarkSurface& mark = markSurfaces_[mesh.surfaceIndex];
    switch (surface.type) {
      case q3::SurfaceType::Planar: mark.kind = MarkKind::Face; break;
      case q3::SurfaceType::Patch: mark.kind = MarkKind::Patch; break;
      case q3::SurfaceType::TriangleSoup: mark.kind = MarkKind::Soup; continue;
      default: continue;
    }
    if (mark.kind == MarkKind::Face) {
      mark.planeNormal = surface.lightmapVecs[2];
      mark.planeDist = glm::dot(mark.planeNormal, bsp_.drawVerts[static_cast<size_t>(surface.firstVert)].position);
    }
    mark.firstCorner = static_cast<uint32_t>(markCorners_.size());
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      for (const size_t corner : {i, i + 2, i + 1})
        markCorners_.push_back(mesh.vertices[mesh.indices[corner]].position);
    }
    mark.numCorners = static_cast<uint32_t>(markCorners_.size()) - mark.firstCorner;
  }
}

bool World::nextEntityToken(char* buffer, int size) {
  const std::optional<q3::Token> token = entityTokens_.next();
  if (buffer != nullptr && size > 0) {
    const std::string_view text = token ? std::string_view(token->text) : std::string_view();
    const size_t length = std::min(text.size(), static_cast<size_t>(size) - 1);
    std::memcpy(buffer, text.data(), length);
    buffer[length] = '\0';
  }
  if (!token) entityTokens_.reset({});   // the engine rewinds for the next reader
  return token.has_value();
}

}  // namespace glue
