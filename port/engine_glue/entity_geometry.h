#pragma once
// Geometry of what the game adds to a scene, built on the CPU each view: sprites, beams, rail
// cores and rings, lightning bolts and polygons become camera-facing triangles in world space;
// an MD3 entity becomes its interpolated frame in model space. Triangles carry the shader
// handle that draws them (resolved to renderer materials by the caller).
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/engine_glue/ioq3_abi.h"

namespace q3 {
struct Md3Model;
}

namespace glue {

struct ScenePoly;

/// Triangles with per-vertex attributes and one shader handle per triangle.
struct GeometryBatch {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> colors;       ///< Linear RGBA multipliers.
  std::vector<uint32_t> indices;
  std::vector<q3abi::qhandle_t> triangleShaders;
  std::vector<uint32_t> triangleLayers;   ///< Shader layer per triangle (0 = first stage); may be empty.
  /// Per triangle: the entity's shaderTime (seconds the shader clock is behind the view's); may
  /// be shorter than the triangle count (the rest: 0).
  std::vector<float> triangleShaderTimes;

  /// Working memory of the passes over a batch (appendMd3, deformBatch, the stock-look colour
  /// passes): kept with the batch so that a frame's passes allocate nothing once it has grown.
  struct Scratch {
    std::vector<uint8_t> vertexDone;                     ///< Per vertex: already handled.
    std::vector<uint32_t> vertices;                      ///< Gathered vertex indices.
    std::vector<uint32_t> shaders;                       ///< Shader handles already handled.
    std::vector<glm::vec3> positions, normals;           ///< Gathered (or lerped MD3) vertices.
    std::vector<glm::vec2> uvs;
    std::vector<std::array<float, 3>> md3Positions, md3Normals;   ///< An MD3 surface at the entity's frame.
    /// Zeroed per-vertex flags for `count` vertices.
    std::vector<uint8_t>& doneFlags(size_t count) {
      vertexDone.assign(count, 0);
      return vertexDone;
    }
  };
  Scratch scratch;   ///< Not part of the batch's content: clear() leaves it.

  /// Forgets everything (keeps capacity).
  void clear();
  /// Number of triangles.
  size_t triangles() const { return indices.size() / 3; }
  /// Adds a quad (a, b, c, d in order around it) with uvs (0,0) (1,0) (1,1) (0,1) by default.
  void addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d,
               const glm::vec4& color, q3abi::qhandle_t shader,
               const glm::vec2& uv0 = {0, 0}, const glm::vec2& uv1 = {1, 1});
};

/// The viewer, for camera-facing effects.
struct Viewer {
  glm::vec3 origin{0.0f};
  glm::vec3 left{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
};

/// Linear RGBA of an entity's shaderRGBA bytes (sRGB-encoded colours).
glm::vec4 entityColor(const q3abi::refEntity_t& entity);

/// Appends the camera-facing geometry of a non-model entity (sprite, beam, rail core/rings,
/// lightning). Returns false for kinds that have no geometry (portal surfaces, models).
bool appendEffect(const q3abi::refEntity_t& entity, const Viewer& viewer, GeometryBatch& out);

/// How far a decal polygon (a shader with polygonOffset: impact marks) is moved towards the
/// viewer, as a fraction of its distance: the stock renderer's depth offset. Marks lie in the
/// plane of the wall they mark; without it the wall and the mark meet the camera ray at the same
/// distance and rounding decides which one shows, pixel by pixel.
inline constexpr float kDecalLift = 1e-3f;

/// Appends polygons (triangle fans) added with AddPolyToScene. The corners of polygons whose
/// shader `isDecal` names move towards `viewer` by kDecalLift of their distance (which leaves
/// where they appear from there unchanged).
void appendPolys(const std::vector<ScenePoly>& polys, const std::vector<q3abi::polyVert_t>& verts,
                 const Viewer& viewer, const std::function<bool(int32_t shader)>& isDecal, GeometryBatch& out);

/// The viewer's left and up directions in an entity's model space (deformVertexes autosprite).
struct SpriteAxes {
  glm::vec3 left{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
};

/// The viewer's axes in the model space of an entity (its axes may carry scale).
SpriteAxes spriteAxesFor(const q3abi::refEntity_t& entity, const Viewer& viewer);

/// Appends an MD3 entity's frame (model space) with one shader per surface. Surfaces whose
/// `autosprite` flag is set are turned, four vertices at a time, into quads facing the viewer
/// (same centre, radius |corner - centre| / sqrt 2, texture 0..1), as the stock renderer's
/// deformVertexes autosprite does.
void appendMd3(const q3::Md3Model& model, const q3abi::refEntity_t& entity,
               const std::vector<q3abi::qhandle_t>& surfaceShaders, GeometryBatch& out,
               const std::vector<bool>& autosprite = {}, const SpriteAxes& axes = {});

}  // namespace glue
