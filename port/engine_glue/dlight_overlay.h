#pragma once
// Dynamic lights on the world as the stock opengl1 renderer draws them in the lightmap look:
// each light re-draws the world triangles it reaches with a 16x16 falloff blob projected along Z
// (texture coordinate 0.5 + (light - vertex).xy / radius, full strength within radius / 2 in
// height) blended as dst * (1 + light) (tr_shade.c ProjectDlightTexture, GLS_SRCBLEND_DST_COLOR
// | GLS_DSTBLEND_ONE; tr_image.c R_CreateDlightImage). The overlay is a copy of the lit
// triangles drawn as a pa::LayerBlend::MultiplyAdd layer (dst * (1 + src) in display values, as
// the lightmap preset composes layers) whose vertex colours are the product of (1 + light) over
// the lights, minus 1, as linear light.
// Triangles are subdivided near the light so per-vertex falloff follows the blob.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "port/q3formats/world/world_scene.h"

namespace glue {

struct DynamicLight;

/// The stock falloff blob at texture coordinates (s, t) in [0, 1]^2 (bilinear, clamped), 0..1.
float stockDlightBlob(glm::vec2 st);

/// What one light adds at a world point with unit normal `normal`: colour x blob x height
/// modulation, per channel in [0, 1] (0 behind the surface or out of reach).
glm::vec3 stockDlightAt(const DynamicLight& light, const glm::vec3& position, const glm::vec3& normal);

/// Overlay triangles: positions, uvs of the world texture, vertex colours (linear) and the
/// world material of each triangle.
struct DlightOverlay {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> colors;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> triangleMaterials;   ///< Index into WorldScene::materials.
  /// Forgets everything (keeps capacity).
  void clear();
};

/// The lit world triangles of a map, prepared once per map.
class DlightOverlayBuilder {
 public:
  /// Keeps the opaque, visible, lightmapped or vertex-lit triangles of the world model (model 0).
  void prepare(const q3::WorldScene& scene);
  /// Appends the overlay of `lights` to `out` (nothing when no light reaches a triangle).
  void build(std::span<const DynamicLight> lights, DlightOverlay& out);
  /// Number of prepared triangles.
  size_t triangles() const { return triangles_.size(); }
  /// The world materials of the prepared triangles, each once, ascending.
  std::vector<uint32_t> materials() const;

 private:
  struct Vertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};
  };
  struct Triangle {
    Vertex v[3];
    glm::vec3 mins{0.0f}, maxs{0.0f};
    uint32_t material = 0;
  };
  void emit(const Triangle& t, std::span<const DynamicLight> lights, int depth, DlightOverlay& out) const;

  std::vector<Triangle> triangles_;
  std::vector<DynamicLight> reaching_;   ///< build's working list (kept: play allocates nothing).
};

}  // namespace glue
