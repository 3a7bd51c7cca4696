#pragma once
// deformVertexes wave / normal / bulge / move, as the stock renderer applies them to a surface's
// vertices each frame (tr_shade_calc.c RB_DeformTessGeometry: lava and water swell, flags and
// banners ripple, platforms bob). World and brush-model surfaces with such shaders leave the
// static traced world mesh and become one dynamic mesh per model, deformed at each view's
// shader time and refitted by the tracer; MD3 surfaces are deformed in their batch
// (deformBatch). Autosprite deforms belong to world_sprites.h / entity_geometry.h.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/mat4x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/engine_glue/entity_geometry.h"
#include "port/q3formats/shader/shader_types.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace q3 {
class ShaderLibrary;
}

namespace glue {

/// The deforms of a shader this file evaluates (wave, normal, bulge, move), in script order;
/// empty for shaders without them and for autosprite shaders (moved with their sprites).
std::vector<q3::Deform> vertexDeforms(const q3::ShaderDef& shader);

/// Applies `deforms` in order at shader time `seconds` (model space). positions and normals
/// (one per vertex) change in place; uvs are the base texture coordinates (bulge reads s).
/// wave: p += n * wave(phase + (x + y + z) * spread), spread = 1 / div (100 when div is 0; no
/// per-vertex phase when the frequency is 0); bulge: p += n * height * sin(s * width + t * speed);
/// move: p += vector * wave(t); normal: n += amplitude * noise(0.98 p, t * frequency) per axis,
/// renormalised (a smooth noise of our own, not the stock random table).
void deformVertices(std::span<const q3::Deform> deforms, double seconds, std::span<glm::vec3> positions,
                    std::span<glm::vec3> normals, std::span<const glm::vec2> uvs);

/// Deforms the vertices of an entity's batch whose triangles use a shader with vertex
/// deforms; `deformsOf(handle)` gives them (nullptr or empty: none). Each vertex once.
void deformBatch(GeometryBatch& batch, double seconds,
                 const std::function<const std::vector<q3::Deform>*(q3abi::qhandle_t)>& deformsOf);

/// Vertex deforms of shaders by name, looked up once in the map's shader library.
class ShaderDeforms {
 public:
  /// Keeps the library the names are looked up in (the module's scripts in priority order).
  void reset(std::shared_ptr<const q3::ShaderLibrary> library);
  /// The vertex deforms of a shader name (nullptr when it has none or is unknown).
  const std::vector<q3::Deform>* find(const std::string& shaderName);

 private:
  std::shared_ptr<const q3::ShaderLibrary> library_;
  std::unordered_map<std::string, std::vector<q3::Deform>> cache_;
};

/// The world's deformed surfaces as dynamic meshes.
class WorldDeforms {
 public:
  /// Moves the triangles of the meshes (world and brush models) whose shader has vertex
  /// deforms out of `scene`: their index lists are emptied, so uploadWorld still makes their
  /// materials but leaves the triangles to this class. Returns the number of meshes taken.
  size_t extract(q3::WorldScene& scene, const q3::ShaderLibrary& library);
  /// After uploadWorld: the renderer materials of the taken meshes (and their light proxies),
  /// vertex colours as the bridge makes them.
  void bind(const q3::WorldScene& scene, const pa::bridge::WorldHandles& handles);
  /// Where model `model` (0 = the world) is this view (model space to world), nullptr when not drawn.
  using Placement = std::function<const glm::mat4x3*(uint32_t model)>;
  /// Deforms at shader time `seconds` and uploads (dynamic meshes, refitted), each model at its
  /// placement; nothing is re-deformed while the time stays the same.
  void update(double seconds, const Placement& placement, pa::Renderer& renderer);
  /// Number of triangles taken.
  size_t triangles() const;

 private:
  struct Piece {
    std::vector<q3::Deform> deforms;
    q3::WorldMesh mesh;          ///< Undeformed, model space, with its triangles.
    uint32_t firstVertex = 0;    ///< Where its vertices start in the model's arrays.
  };
  struct ModelMesh {
    uint32_t model = 0;
    std::vector<Piece> pieces;
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs, lightmapUvs;
    std::vector<glm::vec4> colors;
    std::vector<uint32_t> indices;
    std::vector<pa::MaterialId> materials;
    pa::MeshId mesh = pa::kNoId;
    pa::InstanceId instance = pa::kNoId;
  };
  std::vector<ModelMesh> models_;
  double deformedAt_ = -1.0;
};

}  // namespace glue
