#pragma once
// World surfaces whose shader has deformVertexes autosprite (particle-studio smoke and flames,
// fireballs): the stock renderer re-stamps every four vertices as a quad facing the viewer each
// frame, moved by deformVertexes move (tr_shade_calc.c AutospriteDeform, RB_CalcMoveVertexes;
// tr_surface.c RB_AddQuadStampExt), white, with the stamp's 0..1 texture coordinates: the
// stage's rgbGen / alphaGen waves and tcMods are its material's, moved to the shader time like
// every effect's (shader_animation.h), so the quads must not carry them too. The static copy in
// the traced world mesh would be a flat card in a fixed direction, so the glue hides it and
// draws these quads with the view's effects instead.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/mat4x3.hpp>
#include <glm/vec3.hpp>

#include "port/engine_glue/entity_geometry.h"
#include "port/q3formats/shader/shader_types.h"
#include "port/q3formats/world/world_scene.h"

namespace q3 {
class ShaderLibrary;
}

namespace glue {

/// The autosprite quads of a map's world model.
class WorldSprites {
 public:
  /// Collects, from the world and its brush models, the meshes whose material's shader has
  /// deformVertexes autosprite, four vertices per quad. Returns the world material indices
  /// concerned.
  std::vector<uint32_t> prepare(const q3::WorldScene& scene, const q3::ShaderLibrary& library);
  /// Where brush model `model` is this view (model space to world), nullptr when not drawn.
  using Placement = std::function<const glm::mat4x3*(uint32_t model)>;
  /// Appends the quads at shader time `seconds`, facing `viewer`; `handleOf(shaderName)` gives
  /// the shader handle that draws a material (0 leaves the sprite out); quads of brush models
  /// follow `placement` (the world, model 0, is never moved).
  void append(double seconds, const Viewer& viewer,
              const std::function<q3abi::qhandle_t(const std::string&)>& handleOf, const Placement& placement,
              GeometryBatch& out) const;
  /// Number of quads.
  size_t size() const { return quads_.size(); }
  /// Calls f(shaderName) once for each shader the quads are drawn with.
  template <typename F>
  void forEachShader(F&& f) const {
    for (const Kind& kind : kinds_) f(kind.shaderName);
  }

 private:
  struct Kind {
    std::string shaderName;
    std::vector<q3::Deform> moves;   ///< deformVertexes move lines.
  };
  struct Quad {
    glm::vec3 centre{0.0f};
    float radius = 0.0f;
    uint32_t kind = 0;
    uint32_t model = 0;   ///< 0 = world, else a brush model ("*N").
  };
  std::vector<Kind> kinds_;
  std::vector<Quad> quads_;
};

}  // namespace glue
