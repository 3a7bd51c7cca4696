#include "port/engine_glue/world_sprites.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "port/q3formats/shader/shader_library.h"

namespace glue {
namespace {

bool hasAutosprite(const q3::ShaderDef& shader) {
  return std::any_of(shader.deforms.begin(), shader.deforms.end(),
                     [](const q3::Deform& d) { return d.kind == q3::DeformKind::AutoSprite; });
}

}  // namespace

std::vector<uint32_t> WorldSprites::prepare(const q3::WorldScene& scene, const q3::ShaderLibrary& library) {
  kinds_.clear();
  quads_.clear();
  std::vector<uint32_t> materials;
  std::unordered_map<uint32_t, uint32_t> kindOfMaterial;
  for (size_t model = 0; model < scene.models.size(); ++model) {
    for (const q3::WorldMesh& mesh : scene.models[model].meshes) {
      if (mesh.material >= scene.materials.size() || mesh.positions.size() < 4) continue;
      const q3::WorldMaterial& m = scene.materials[mesh.material];
      const q3::ShaderDef* shader = m.fromScript ? library.find(m.shaderName) : nullptr;
      if (shader == nullptr || !hasAutosprite(*shader) || shader->stages.empty()) continue;
      auto found = kindOfMaterial.find(mesh.material);
      if (found == kindOfMaterial.end()) {
        Kind kind;
        kind.shaderName = m.shaderName;
        for (const q3::Deform& d : shader->deforms)
          if (d.kind == q3::DeformKind::Move) kind.moves.push_back(d);
        found = kindOfMaterial.emplace(mesh.material, uint32_t(kinds_.size())).first;
        kinds_.push_back(std::move(kind));
        materials.push_back(mesh.material);
      }
      // The world builder keeps each surface's vertices together: four per quad.
      for (size_t v = 0; v + 3 < mesh.positions.size(); v += 4) {
        Quad quad;
        quad.centre = 0.25f * (mesh.positions[v] + mesh.positions[v + 1] + mesh.positions[v + 2] + mesh.positions[v + 3]);
        quad.radius = glm::length(mesh.positions[v] - quad.centre) * 0.707f;
        quad.kind = found->second;
        quad.model = static_cast<uint32_t>(model);
        if (std::isfinite(quad.radius) && quad.radius > 0.0f) quads_.push_back(quad);
      }
    }
  }
  return materials;
}

void WorldSprites::append(double seconds, const Viewer& viewer,
                          const std::function<q3abi::qhandle_t(const std::string&)>& handleOf,
                          const Placement& placement, GeometryBatch& out) const {
  // The stage's colour waves and tcMods are the material's (shader_animation.h moves it to the
  // shader time): the quads carry white and the stamp's 0..1 uvs.
  struct KindNow {
    q3abi::qhandle_t handle = 0;
    glm::vec3 offset{0.0f};
  };
  std::vector<KindNow> now(kinds_.size());
  for (size_t k = 0; k < kinds_.size(); ++k) {
    const Kind& kind = kinds_[k];
    KindNow& n = now[k];
    n.handle = handleOf(kind.shaderName);
    for (const q3::Deform& move : kind.moves)
      n.offset += glm::vec3(move.params[0], move.params[1], move.params[2]) * move.wave.evaluate(seconds);
  }
  for (const Quad& quad : quads_) {
    const KindNow& n = now[quad.kind];
    if (n.handle == 0) continue;
    glm::vec3 centre = quad.centre;
    if (quad.model != 0) {
      const glm::mat4x3* toWorld = placement ? placement(quad.model) : nullptr;
      if (toWorld == nullptr) continue;   // the mover is not drawn this view
      centre = *toWorld * glm::vec4(centre, 1.0f);
    }
    const glm::vec3 mid = centre + n.offset;
    const glm::vec3 left = viewer.left * quad.radius, up = viewer.up * quad.radius;
    out.addQuad(mid + left + up, mid - left + up, mid - left - up, mid + left - up, glm::vec4(1.0f), n.handle);
  }
}

}  // namespace glue
