#include "port/engine_glue/world_deforms.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "port/q3formats/shader/shader_library.h"
#include "renderer/core/srgb.h"

namespace glue {
namespace {

constexpr float kNoiseScale = 0.98f;          // deformVertexes normal samples the noise at 0.98 x position
constexpr float kNoiseAxisOffset = 100.0f;    // ... and at +100 / +200 for the second and third axes
constexpr float kSpreadForZeroDiv = 100.0f;   // the stock parser's spread when wave's div is 0

bool isVertexDeform(q3::DeformKind kind) {
  return kind == q3::DeformKind::Wave || kind == q3::DeformKind::Normal || kind == q3::DeformKind::Bulge ||
         kind == q3::DeformKind::Move;
}

bool isSprite(q3::DeformKind kind) {
  return kind == q3::DeformKind::AutoSprite || kind == q3::DeformKind::AutoSprite2;
}

/// A smooth noise in [-1, 1] of a position and a time (sums of sines at incommensurate
/// frequencies): the normal deform's wobble, deterministic across frames and threads.
float smoothNoise(const glm::vec3& p, float t) {
  const float a = std::sin(0.071f * p.x + 0.113f * p.y + 1.37f * t);
  const float b = std::sin(0.097f * p.y - 0.059f * p.z + 2.11f * t + 1.3f);
  const float c = std::sin(0.083f * p.z + 0.047f * p.x - 1.73f * t + 2.9f);
  return (a + b + c) / 3.0f;
}

bool finiteVec(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::vector<q3::Deform> vertexDeforms(const q3::ShaderDef& shader) {
  std::vector<q3::Deform> out;
  for (const q3::Deform& d : shader.deforms) {
    if (isSprite(d.kind)) return {};
    if (isVertexDeform(d.kind)) out.push_back(d);
  }
  return out;
}

void deformVertices(std::span<const q3::Deform> deforms, double seconds, std::span<glm::vec3> positions,
                    std::span<glm::vec3> normals, std::span<const glm::vec2> uvs) {
  const size_t n = std::min({positions.size(), normals.size(), uvs.size()});
  for (const q3::Deform& d : deforms) {
    switch (d.kind) {
      case q3::DeformKind::Wave: {
        if (d.wave.frequency == 0.0f) {
          const float scale = d.wave.evaluate(seconds);
          for (size_t i = 0; i < n; ++i) positions[i] += normals[i] * scale;
          break;
        }
        const float spread = d.spread != 0.0f ? 1.0f / d.spread : kSpreadForZeroDiv;
        for (size_t i = 0; i < n; ++i) {
          q3::WaveForm wave = d.wave;
          wave.phase += (positions[i].x + positions[i].y + positions[i].z) * spread;
          positions[i] += normals[i] * wave.evaluate(seconds);
        }
        break;
      }
      case q3::DeformKind::Bulge: {
        const float width = d.params[0], height = d.params[1], speed = d.params[2];
        const double now = seconds * speed;
        for (size_t i = 0; i < n; ++i)
          positions[i] += normals[i] * (height * float(std::sin(double(uvs[i].x) * width + now)));
        break;
      }
      case q3::DeformKind::Move: {
        const glm::vec3 offset = glm::vec3(d.params[0], d.params[1], d.params[2]) * d.wave.evaluate(seconds);
        for (size_t i = 0; i < n; ++i) positions[i] += offset;
        break;
      }
      case q3::DeformKind::Normal: {
        const float amplitude = d.params[0];
        const float t = float(seconds * d.params[1]);
        for (size_t i = 0; i < n; ++i) {
          const glm::vec3 p = positions[i] * kNoiseScale;
          glm::vec3 bent = normals[i] + amplitude * glm::vec3(smoothNoise(p, t), smoothNoise(p + kNoiseAxisOffset, t),
                                                              smoothNoise(p + 2.0f * kNoiseAxisOffset, t));
          const float length = glm::length(bent);
          if (length > 1e-6f && std::isfinite(length)) normals[i] = bent / length;
        }
        break;
      }
      default: break;
    }
  }
  for (size_t i = 0; i < n; ++i)   // hostile numbers (huge amplitudes) must not reach the BVH
    if (!finiteVec(positions[i])) positions[i] = glm::vec3(0.0f);
}

void deformBatch(GeometryBatch& batch, double seconds,
                 const std::function<const std::vector<q3::Deform>*(q3abi::qhandle_t)>& deformsOf) {
  const size_t vertices = batch.positions.size();
  if (batch.normals.size() != vertices || batch.uvs.size() != vertices) return;
  GeometryBatch::Scratch& scratch = batch.scratch;
  std::vector<uint8_t>& done = scratch.doneFlags(vertices);
  std::vector<uint32_t>& chosen = scratch.vertices;
  // Shaders handled so far (a batch has few): each is looked up once, its vertices all gathered
  // at its first triangle.
  std::vector<uint32_t>& handled = scratch.shaders;
  handled.clear();
  for (size_t t = 0; t < batch.triangleShaders.size() && 3 * t + 2 < batch.indices.size(); ++t) {
    const q3abi::qhandle_t shader = batch.triangleShaders[t];
    if (std::find(handled.begin(), handled.end(), static_cast<uint32_t>(shader)) != handled.end()) continue;
    handled.push_back(static_cast<uint32_t>(shader));
    const std::vector<q3::Deform>* deforms = deformsOf(shader);
    if (deforms == nullptr || deforms->empty()) continue;
    // Gather this shader's untouched vertices from here on, then deform them in one go.
    chosen.clear();
    for (size_t u = t; u < batch.triangleShaders.size() && 3 * u + 2 < batch.indices.size(); ++u) {
      if (batch.triangleShaders[u] != shader) continue;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = batch.indices[3 * u + k];
        if (v < vertices && !done[v]) {
          done[v] = 1;
          chosen.push_back(v);
        }
      }
    }
    std::vector<glm::vec3>& p = scratch.positions;
    std::vector<glm::vec3>& nrm = scratch.normals;
    std::vector<glm::vec2>& uv = scratch.uvs;
    p.resize(chosen.size());
    nrm.resize(chosen.size());
    uv.resize(chosen.size());
    for (size_t i = 0; i < chosen.size(); ++i) {
      p[i] = batch.positions[chosen[i]];
      nrm[i] = batch.normals[chosen[i]];
      uv[i] = batch.uvs[chosen[i]];
    }
    deformVertices(*deforms, seconds, p, nrm, uv);
    for (size_t i = 0; i < chosen.size(); ++i) {
      batch.positions[chosen[i]] = p[i];
      batch.normals[chosen[i]] = nrm[i];
    }
  }
}

void ShaderDeforms::reset(std::shared_ptr<const q3::ShaderLibrary> library) {
  library_ = std::move(library);
  cache_.clear();
}

const std::vector<q3::Deform>* ShaderDeforms::find(const std::string& shaderName) {
  if (library_ == nullptr) return nullptr;
  auto found = cache_.find(shaderName);
  if (found == cache_.end()) {
    const q3::ShaderDef* def = library_->find(shaderName);
    found = cache_.emplace(shaderName, def != nullptr ? vertexDeforms(*def) : std::vector<q3::Deform>{}).first;
  }
  return found->second.empty() ? nullptr : &found->second;
}

size_t WorldDeforms::extract(q3::WorldScene& scene, const q3::ShaderLibrary& library) {
  models_.clear();
  deformedAt_ = -1.0;
  size_t taken = 0;
  for (size_t model = 0; model < scene.models.size(); ++model) {
    ModelMesh group;
    group.model = static_cast<uint32_t>(model);
    for (q3::WorldMesh& mesh : scene.models[model].meshes) {
      if (mesh.material >= scene.materials.size() || mesh.indices.empty()) continue;
      const q3::WorldMaterial& m = scene.materials[mesh.material];
      const q3::ShaderDef* shader = m.fromScript ? library.find(m.shaderName) : nullptr;
      if (shader == nullptr) continue;
      std::vector<q3::Deform> deforms = vertexDeforms(*shader);
      const size_t n = mesh.positions.size();
      if (deforms.empty() || mesh.normals.size() != n || mesh.uvs.size() != n || mesh.lightmapUvs.size() != n ||
          mesh.colors.size() != n)
        continue;
      Piece piece;
      piece.deforms = std::move(deforms);
      piece.mesh = mesh;
      mesh.indices.clear();   // the static world mesh leaves these triangles out
      group.pieces.push_back(std::move(piece));
      ++taken;
    }
    if (!group.pieces.empty()) models_.push_back(std::move(group));
  }
  return taken;
}

void WorldDeforms::bind(const q3::WorldScene& scene, const pa::bridge::WorldHandles& handles) {
  for (ModelMesh& group : models_) {
    group.positions.clear();
    group.normals.clear();
    group.uvs.clear();
    group.lightmapUvs.clear();
    group.colors.clear();
    group.indices.clear();
    group.materials.clear();
    for (Piece& piece : group.pieces) {
      const q3::WorldMesh& mesh = piece.mesh;
      const auto material = handles.materials.find({mesh.material, mesh.lightmap});
      if (material == handles.materials.end()) continue;
      const auto proxy = handles.lightProxies.find(mesh.material);
      // Vertex colours as the bridge makes them: baked light on vertex-lit surfaces, else white.
      const bool vertexLight = scene.materials[mesh.material].vertexLit || mesh.lightmap < 0;
      piece.firstVertex = static_cast<uint32_t>(group.positions.size());
      group.positions.insert(group.positions.end(), mesh.positions.begin(), mesh.positions.end());
      group.normals.insert(group.normals.end(), mesh.normals.begin(), mesh.normals.end());
      group.uvs.insert(group.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
      group.lightmapUvs.insert(group.lightmapUvs.end(), mesh.lightmapUvs.begin(), mesh.lightmapUvs.end());
      for (const glm::vec4& c : mesh.colors)
        group.colors.push_back(vertexLight ? glm::vec4(pa::srgbToLinearClamped(c.r), pa::srgbToLinearClamped(c.g), pa::srgbToLinearClamped(c.b), c.a)
                                           : glm::vec4(1.0f, 1.0f, 1.0f, c.a));
      const uint32_t n = static_cast<uint32_t>(mesh.positions.size());
      for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
        if (a >= n || b >= n || c >= n) continue;
        group.indices.insert(group.indices.end(), {piece.firstVertex + a, piece.firstVertex + b, piece.firstVertex + c});
        group.materials.push_back(material->second);
        if (proxy != handles.lightProxies.end()) {   // the invisible emitter twin, as the bridge adds it
          group.indices.insert(group.indices.end(),
                               {piece.firstVertex + a, piece.firstVertex + b, piece.firstVertex + c});
          group.materials.push_back(proxy->second);
        }
      }
    }
  }
  deformedAt_ = -1.0;
}

void WorldDeforms::update(double seconds, const Placement& placement, pa::Renderer& renderer) {
  const bool redeform = seconds != deformedAt_;
  for (ModelMesh& group : models_) {
    if (group.indices.empty()) continue;
    if (redeform || group.mesh == pa::kNoId) {
      for (const Piece& piece : group.pieces) {
        const size_t n = piece.mesh.positions.size();
        const std::span<glm::vec3> positions(group.positions.data() + piece.firstVertex, n);
        const std::span<glm::vec3> normals(group.normals.data() + piece.firstVertex, n);
        std::copy(piece.mesh.positions.begin(), piece.mesh.positions.end(), positions.begin());
        std::copy(piece.mesh.normals.begin(), piece.mesh.normals.end(), normals.begin());
        deformVertices(piece.deforms, seconds, positions, normals, piece.mesh.uvs);
      }
      const pa::MeshDesc mesh = pa::meshDescOf(group, group.materials, true);
      if (group.mesh == pa::kNoId) group.mesh = renderer.addMesh(mesh);
      else renderer.updateMesh(group.mesh, mesh);
    }
    pa::InstanceDesc instance;
    instance.mesh = group.mesh;
    if (const glm::mat4x3* where = placement(group.model)) instance.objectToWorld = *where;
    else instance.mask = 0;   // a mover the game did not add, or a view without the world
    if (group.instance == pa::kNoId) group.instance = renderer.addInstance(instance);
    else renderer.setInstance(group.instance, instance);
  }
  deformedAt_ = seconds;
}

size_t WorldDeforms::triangles() const {
  size_t total = 0;
  for (const ModelMesh& group : models_)
    for (const Piece& piece : group.pieces) total += piece.mesh.indices.size() / 3;
  return total;
}

}  // namespace glue
