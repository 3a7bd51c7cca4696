#include "renderer/scene/world/scene_store.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "renderer/scene/integrator/display_composite.h"
#include "renderer/scene/lights/stock_dlights.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/sampling/warp.h"

namespace pa {

namespace {

bool finite(float x) { return std::isfinite(x); }
template <int N>
bool finite(const glm::vec<N, float>& v) {
  for (int i = 0; i < N; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

void requireFinite(bool ok, const CallContext& what, const char* field) {
  if (!ok) throw SceneError(what + ": " + field + " is not finite");
}

void requireNonNegative(const glm::vec3& v, const CallContext& what, const char* field) {
  requireFinite(finite(v), what, field);
  if (v.x < 0.0f || v.y < 0.0f || v.z < 0.0f) throw SceneError(what + ": " + field + " is negative");
}

glm::mat3 linearPart(const glm::mat4x3& m) { return glm::mat3(m[0], m[1], m[2]); }

}  // namespace

// ---------------------------------------------------------------- validation helpers

void SceneStore::validateMaterial(const MaterialDesc& m, const CallContext& what) const {
  auto checkTexture = [&](TextureId id, const char* field) {
    if (id != kNoId && id >= textures_.size()) {
      throw SceneError(what + ": " + field + " = " + std::to_string(id) + " is not a texture (" +
                       std::to_string(textures_.size()) + " textures)");
    }
  };
  checkTexture(m.baseTexture, "baseTexture");
  checkTexture(m.emissiveTexture, "emissiveTexture");
  checkTexture(m.coverTexture, "coverTexture");
  for (int c = 0; c < 3; ++c) requireFinite(finite(m.coverUvTransform[c]), what, "coverUvTransform");
  requireFinite(finite(m.coverAlphaCutoff), what, "coverAlphaCutoff");
  const StockLook& stock = m.stock;
  checkTexture(stock.lightmapTexture, "stock.lightmapTexture");
  checkTexture(stock.shineTexture, "stock.shineTexture");
  requireNonNegative(stock.shineColor, what, "stock.shineColor");
  for (int c = 0; c < 3; ++c) requireFinite(finite(stock.shineUvTransform[c]), what, "stock.shineUvTransform");
  if (stock.shineTexCoords != TexCoordSource::Mesh && stock.shineTexCoords != TexCoordSource::ReflectionSphere)
    throw SceneError(what + ": stock.shineTexCoords = " + std::to_string(unsigned(stock.shineTexCoords)) + " is not a TexCoordSource");
  if (unsigned(stock.shineBlend) > unsigned(LayerBlend::Modulate2x))
    throw SceneError(what + ": stock.shineBlend = " + std::to_string(unsigned(stock.shineBlend)) + " is not a LayerBlend");
  if (unsigned(stock.layerBlend) > unsigned(LayerBlend::Factors))
    throw SceneError(what + ": stock.layerBlend = " + std::to_string(unsigned(stock.layerBlend)) + " is not a LayerBlend");
  if (unsigned(stock.layerSrcFactor) > unsigned(BlendFactor::OneMinusSrcAlpha) ||
      unsigned(stock.layerDstFactor) > unsigned(BlendFactor::OneMinusSrcAlpha))
    throw SceneError(what + ": a layer blend factor is not a BlendFactor");
  requireFinite(finite(m.baseColor), what, "baseColor");
  requireNonNegative(m.emission, what, "emission");
  requireFinite(finite(m.seenEmission), what, "seenEmission");
  requireFinite(finite(m.alphaCutoff), what, "alphaCutoff");
  requireFinite(finite(m.opacity), what, "opacity");
  requireFinite(finite(m.specular), what, "specular");
  requireFinite(finite(m.roughness), what, "roughness");
  for (int c = 0; c < 3; ++c) requireFinite(finite(m.uvTransform[c]), what, "uvTransform");
  for (int c = 0; c < 3; ++c) requireFinite(finite(m.emissiveUvTransform[c]), what, "emissiveUvTransform");
  const UvWobble& w = m.uvWobble;
  requireFinite(std::isfinite(w.amplitude) && std::isfinite(w.phase) && finite(w.axisU) && finite(w.axisV) &&
                    finite(w.linear[0]) && finite(w.linear[1]),
                what, "uvWobble");
  if (m.baseTexCoords != TexCoordSource::Mesh && m.baseTexCoords != TexCoordSource::ReflectionSphere)
    throw SceneError(what + ": baseTexCoords = " + std::to_string(unsigned(m.baseTexCoords)) + " is not a TexCoordSource");
}

LightDesc SceneStore::validateLight(const LightDesc& in, const CallContext& what) const {
  LightDesc l = in;
  requireFinite(finite(l.position), what, "position");
  requireFinite(finite(l.direction), what, "direction");
  requireNonNegative(l.color, what, "color");
  requireFinite(finite(l.intensity), what, "intensity");
  if (l.intensity < 0.0f) throw SceneError(what + ": intensity is negative");
  requireFinite(finite(l.radius) && finite(l.range) && finite(l.angularRadius), what, "radius/range/angularRadius");
  if (l.radius < 0.0f || l.range < 0.0f) throw SceneError(what + ": radius and range must be >= 0");
  if (l.falloff == Falloff::Linear && !(l.range > 0.0f) && l.type != LightType::Directional) {
    throw SceneError(what + ": Linear falloff needs range > 0");
  }
  if (l.type != LightType::Point) {
    const float len = glm::length(l.direction);
    if (!(len > 0.0f)) throw SceneError(what + ": direction is zero");
    l.direction /= len;
  }
  if (l.type == LightType::Spot) {
    requireFinite(finite(l.cosInnerAngle) && finite(l.cosOuterAngle), what, "cosInnerAngle/cosOuterAngle");
    if (l.cosInnerAngle < l.cosOuterAngle || l.cosInnerAngle > 1.0f || l.cosOuterAngle < -1.0f) {
      throw SceneError(what + ": spot needs -1 <= cosOuterAngle <= cosInnerAngle <= 1");
    }
  }
  if (l.type == LightType::Directional && (l.angularRadius < 0.0f || l.angularRadius >= 1.5f)) {
    throw SceneError(what + ": angularRadius must be in [0, 1.5) radians");
  }
  return l;
}

void SceneStore::validateInstance(const InstanceDesc& d, const CallContext& what) const {
  if (d.mesh >= meshes_.size() || meshes_[d.mesh].removed) {
    throw SceneError(what + ": mesh " + std::to_string(d.mesh) + " does not exist");
  }
  for (int c = 0; c < 4; ++c) requireFinite(finite(d.objectToWorld[c]), what, "objectToWorld");
  const float det = glm::determinant(linearPart(d.objectToWorld));
  if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) throw SceneError(what + ": objectToWorld is singular");
  requireFinite(finite(d.tint), what, "tint");
}

SceneStore::MeshSlot& SceneStore::liveMesh(MeshId id, const char* call) {
  if (id >= meshes_.size() || meshes_[id].removed) {
    throw SceneError(std::string(call) + ": mesh " + std::to_string(id) + " does not exist");
  }
  return meshes_[id];
}

// ---------------------------------------------------------------- setters

MeshId SceneStore::addMesh(const MeshDesc& mesh) {
  const auto id = static_cast<MeshId>(meshes_.size());
  MeshSlot slot;
  slot.pending = MeshGeometry::fromDesc(mesh, {"addMesh", "mesh", id});
  slot.hasPending = true;
  meshes_.push_back(std::move(slot));
  dirty_ = worldDirty_ = true;
  return id;
}

void SceneStore::updateMesh(MeshId id, const MeshDesc& mesh) {
  MeshSlot& slot = liveMesh(id, "updateMesh");
  MeshGeometry::validate(mesh, {"updateMesh", "mesh", id});
  const MeshGeometry* current = slot.hasPending ? &slot.pending : slot.record ? &slot.record->geometry : nullptr;
  if (current != nullptr && current->holds(mesh)) return;   // the same data: nothing changes
  slot.pending.assign(mesh);   // into the memory the last commit swapped out
  slot.hasPending = true;
  touchedMeshes_.push_back(id);   // whether it changes the world is decided at commit
  dirty_ = true;
}

void SceneStore::removeMesh(MeshId id) {
  MeshSlot& slot = liveMesh(id, "removeMesh");
  slot.removed = true;
  slot.hasPending = false;
  pendingSeen_.everything = true;
  dirty_ = worldDirty_ = true;
}

void SceneStore::reserveMeshLike(MeshId id, MeshId example) {
  MeshSlot& slot = liveMesh(id, "reserveMeshLike");
  const MeshSlot& model = liveMesh(example, "reserveMeshLike");
  if (id == example) return;
  if (!slot.record) slot.record = std::make_unique<MeshRecord>();   // as the next commit would
  MeshRecord& record = *slot.record;
  slot.pending.reserveLike(model.pending);
  if (model.record) {
    slot.pending.reserveLike(model.record->geometry);
    record.geometry.reserveLike(model.record->geometry);
    if (model.record->rules.capacity() > record.rules.capacity())
      record.rules.reserve(model.record->rules.capacity());
    record.blas.reserveLike(model.record->blas);
  }
  record.geometry.reserveLike(model.pending);
  // The colours' display copy (encoded at commit) takes as many as either colour array holds.
  const size_t colors = std::max(record.geometry.colors.capacity(), slot.pending.colors.capacity());
  if (colors > record.displayColors.capacity()) record.displayColors.reserve(colors);
}

InstanceId SceneStore::addInstance(const InstanceDesc& instance) {
  const auto id = static_cast<InstanceId>(instances_.size());
  validateInstance(instance, {"addInstance", "instance", id});
  instances_.emplace_back(instance);
  pendingSeen_.markInstance(id);
  dirty_ = worldDirty_ = true;
  return id;
}

void SceneStore::setInstance(InstanceId id, const InstanceDesc& instance) {
  if (id >= instances_.size() || !instances_[id]) {
    throw SceneError("setInstance: instance " + std::to_string(id) + " does not exist");
  }
  validateInstance(instance, {"setInstance", "instance", id});
  if (*instances_[id] == instance) return;
  if (!cameraOnlyOverlay(*instances_[id]) || !cameraOnlyOverlay(instance)) worldDirty_ = true;
  pendingSeen_.markInstance(id);
  instances_[id] = instance;
  dirty_ = true;
}

void SceneStore::removeInstance(InstanceId id) {
  if (id >= instances_.size() || !instances_[id]) {
    throw SceneError("removeInstance: instance " + std::to_string(id) + " does not exist");
  }
  instances_[id].reset();
  pendingSeen_.markInstance(id);
  dirty_ = worldDirty_ = true;
}

TextureId SceneStore::addTexture(const TextureDesc& texture) {
  const auto id = static_cast<TextureId>(textures_.size());
  const std::string what = CallContext{"addTexture", "texture", id}.str();
  textures_.push_back(std::make_shared<const Texture>(Texture::fromDesc(texture, what.c_str())));
  dirty_ = worldDirty_ = true;
  return id;
}

void SceneStore::updateTexture(TextureId id, const TextureDesc& texture) {
  if (id >= textures_.size()) {
    throw SceneError("updateTexture: texture " + std::to_string(id) + " does not exist");
  }
  const std::string what = CallContext{"updateTexture", "texture", id}.str();
  textures_[id] = std::make_shared<const Texture>(Texture::fromDesc(texture, what.c_str()));
  pendingSeen_.everything = true;
  dirty_ = worldDirty_ = true;
}

MaterialId SceneStore::addMaterial(const MaterialDesc& material) {
  const auto id = static_cast<MaterialId>(materials_.size());
  validateMaterial(material, {"addMaterial", "material", id});
  materials_.push_back(material);
  dirty_ = worldDirty_ = true;
  return id;
}

void SceneStore::setMaterial(MaterialId id, const MaterialDesc& material) {
  if (id >= materials_.size()) {
    throw SceneError("setMaterial: material " + std::to_string(id) + " does not exist");
  }
  validateMaterial(material, {"setMaterial", "material", id});
  if (materials_[id] == material) return;   // the same material: nothing changes
  materials_[id] = material;
  pendingSeen_.markMaterial(id);
  dirty_ = worldDirty_ = true;
}

LightId SceneStore::addLight(const LightDesc& light) {
  const auto id = static_cast<LightId>(lights_.size());
  lights_.emplace_back(validateLight(light, {"addLight", "light", id}));
  dirty_ = worldDirty_ = true;
  return id;
}

void SceneStore::setLight(LightId id, const LightDesc& light) {
  if (id >= lights_.size() || !lights_[id]) {
    throw SceneError("setLight: light " + std::to_string(id) + " does not exist");
  }
  const LightDesc valid = validateLight(light, {"setLight", "light", id});
  if (*lights_[id] == valid) return;   // the same light: nothing changes
  lights_[id] = valid;
  dirty_ = worldDirty_ = true;
}

void SceneStore::removeLight(LightId id) {
  if (id >= lights_.size() || !lights_[id]) {
    throw SceneError("removeLight: light " + std::to_string(id) + " does not exist");
  }
  lights_[id].reset();
  dirty_ = worldDirty_ = true;
}

void SceneStore::setSky(const SkyDesc& sky) {
  for (size_t i = 0; i < sky.faces.size(); ++i) {
    if (sky.faces[i] != kNoId && sky.faces[i] >= textures_.size()) {
      throw SceneError("setSky: faces[" + std::to_string(i) + "] = " + std::to_string(sky.faces[i]) +
                       " is not a texture");
    }
  }
  requireNonNegative(sky.color, CallContext{"setSky"}, "color");
  if (!std::isfinite(sky.intensity) || sky.intensity < 0.0f) {
    throw SceneError("setSky: intensity must be finite and >= 0");
  }
  if (!std::isfinite(sky.lightingScale) || sky.lightingScale < 0.0f) {
    throw SceneError("setSky: lightingScale must be finite and >= 0");
  }
  requireNonNegative(sky.ambientRadiance, CallContext{"setSky"}, "ambientRadiance");
  requireNonNegative(sky.minimumRadiance, CallContext{"setSky"}, "minimumRadiance");
  sky_ = sky;
  pendingSeen_.sky = true;
  dirty_ = worldDirty_ = true;
}

void SceneStore::setPortals(std::span<const PortalDesc> portals) {
  std::vector<PortalDesc>& valid = portalScratch_;   // memory kept: the glue sets them every frame
  valid.clear();
  for (size_t i = 0; i < portals.size(); ++i) {
    const CallContext what{"setPortals", "portal", static_cast<uint32_t>(i)};
    PortalDesc p = portals[i];
    requireFinite(finite(p.normal) && std::isfinite(p.distance), what, "plane");
    for (int c = 0; c < 4; ++c) requireFinite(finite(p.transform[c]), what, "transform");
    const float length = glm::length(p.normal);
    if (!(length > 1e-6f)) throw SceneError(what + ": normal has zero length");
    p.normal /= length;
    p.distance /= length;
    const float det = glm::determinant(glm::mat3(p.transform));
    if (!(std::fabs(det) > 1e-6f)) throw SceneError(what + ": transform is not invertible");
    valid.push_back(p);
  }
  if (valid == portals_) return;   // the same portals: nothing changes
  portals_.swap(valid);
  pendingSeen_.portals = true;
  dirty_ = worldDirty_ = true;
}

void SceneStore::setFogVolumes(std::span<const FogVolumeDesc> volumes) {
  if (volumes.size() > kMaxFogVolumes)
    throw SceneError("setFogVolumes: " + std::to_string(volumes.size()) + " volumes (at most " +
                     std::to_string(kMaxFogVolumes) + ")");
  std::vector<FogVolume> valid;
  valid.reserve(volumes.size());
  for (size_t i = 0; i < volumes.size(); ++i)
    valid.push_back(makeFogVolume(volumes[i], "setFogVolumes: volume " + std::to_string(i)));
  fogs_ = std::move(valid);
  pendingSeen_.everything = true;
  dirty_ = worldDirty_ = true;
}

void SceneStore::setStockDynamicLights(std::span<const StockDynamicLight> lights) {
  if (lights.size() > kMaxStockDynamicLights)
    throw SceneError("setStockDynamicLights: " + std::to_string(lights.size()) + " lights (at most " +
                     std::to_string(kMaxStockDynamicLights) + ")");
  for (size_t i = 0; i < lights.size(); ++i) {
    const CallContext what{"setStockDynamicLights", "light", static_cast<uint32_t>(i)};
    requireFinite(finite(lights[i].origin) && std::isfinite(lights[i].radius) && finite(lights[i].color), what,
                  "origin, radius and colour");
  }
  if (std::equal(lights.begin(), lights.end(), stockDlights_.begin(), stockDlights_.end())) return;
  stockDlights_.assign(lights.begin(), lights.end());
  pendingSeen_.everything = true;
  dirty_ = worldDirty_ = true;
}

// ---------------------------------------------------------------- commit

void SceneStore::validateReferences() const {
  const size_t materialCount = materials_.size();
  for (size_t i = 0; i < instances_.size(); ++i) {
    if (!instances_[i]) continue;
    const InstanceDesc& d = *instances_[i];
    if (d.mesh >= meshes_.size() || meshes_[d.mesh].removed) {
      throw SceneError("commit: instance " + std::to_string(i) + " uses mesh " + std::to_string(d.mesh) +
                       ", which was removed");
    }
    if (d.materialOverride != kNoId && d.materialOverride >= materialCount) {
      throw SceneError("commit: instance " + std::to_string(i) + " materialOverride = " +
                       std::to_string(d.materialOverride) + " is not a material (" + std::to_string(materialCount) +
                       " materials)");
    }
  }
  for (size_t id = 0; id < meshes_.size(); ++id) {
    const MeshSlot& slot = meshes_[id];
    if (slot.removed) continue;
    const MeshGeometry* g = slot.hasPending ? &slot.pending : (slot.record ? &slot.record->geometry : nullptr);
    if (g == nullptr) continue;
    for (size_t t = 0; t < g->materials.size(); ++t) {
      const MaterialId m = g->materials[t];
      if (m != kNoId && m >= materialCount) {
        throw SceneError("commit: mesh " + std::to_string(id) + " materials[" + std::to_string(t) + "] = " +
                         std::to_string(m) + " is not a material (" + std::to_string(materialCount) + " materials)");
      }
    }
  }
}

void SceneStore::buildMeshes(const std::vector<MaterialRecord>& materials) {
  // A triangle's rule must hold for every instance of its mesh: where the mesh's own material
  // and the instances' override materials disagree, the callback decides (Filtered).
  const auto agree = [](HitRule a, HitRule b) { return a == b ? a : HitRule::Filtered; };
  std::vector<std::optional<HitRule>>& overrideRule = overrideRuleScratch_;
  overrideRule.assign(meshes_.size(), std::nullopt);
  for (const auto& inst : instances_) {
    if (!inst || inst->materialOverride == kNoId) continue;
    const HitRule rule = materials[inst->materialOverride].rule;
    std::optional<HitRule>& meshRule = overrideRule[inst->mesh];
    meshRule = meshRule ? agree(*meshRule, rule) : rule;
  }
  std::vector<MeshJob>& jobs = meshJobs_;
  jobs.clear();
  for (size_t id = 0; id < meshes_.size(); ++id) {
    MeshSlot& slot = meshes_[id];
    if (slot.removed) {
      slot.record.reset();
      continue;
    }
    if (!slot.record) slot.record = std::make_unique<MeshRecord>();
    MeshRecord& rec = *slot.record;
    bool geometryChanged = false;
    bool canRefit = false;
    if (slot.hasPending) {
      MeshGeometry& next = slot.pending;
      const bool sameTopology = rec.built && next.positions.size() == rec.geometry.positions.size() &&
                                next.indices == rec.geometry.indices;
      canRefit = sameTopology && next.dynamic;
      if (next.positions != rec.geometry.positions) rec.positionsStamp = ++meshStamps_;
      if (!sameTopology) rec.topologyStamp = rec.positionsStamp = ++meshStamps_;
      std::swap(rec.geometry, next);   // the old arrays take the next update (no allocation)
      slot.hasPending = false;
      geometryChanged = true;
    }
    const MeshGeometry& g = rec.geometry;
    auto ruleOf = [&](uint32_t t) -> HitRule {
      const MaterialId m = g.materialOf(t);
      const HitRule own = m != kNoId ? materials[m].rule : HitRule::Opaque;   // the default: grey, two-sided
      return overrideRule[id] ? agree(own, *overrideRule[id]) : own;
    };
    bool flagsChanged = rec.rules.size() != g.triangleCount();
    for (uint32_t t = 0; t < g.triangleCount() && !flagsChanged; ++t) flagsChanged = rec.rules[t] != ruleOf(t);
    if (flagsChanged) {
      rec.rules.resize(g.triangleCount());
      for (uint32_t t = 0; t < g.triangleCount(); ++t) rec.rules[t] = ruleOf(t);
    }
    if (!rec.built || flagsChanged || (geometryChanged && !canRefit)) {
      jobs.push_back({&rec, false});
    } else if (geometryChanged) {
      jobs.push_back({&rec, true});
    }
  }
  tbb::parallel_for(size_t{0}, jobs.size(), [&](size_t i) {
    MeshRecord& rec = *jobs[i].record;
    // As large as the colours' own arrays have been: grows (allocates) only when they did.
    rec.displayColors.reserve(rec.geometry.colors.capacity());
    encodeColors(rec.geometry.colors, rec.displayColors);
    if (jobs[i].refit) {
      rec.blas.refit(rec.geometry.positions);
    } else {
      rec.blas.build({rec.geometry.positions, rec.geometry.indices, rec.rules}, bvhConfig_);
    }
    rec.built = true;
  });
}

bool SceneStore::meshTouched(MeshId id) const {
  return std::find(touchedMeshes_.begin(), touchedMeshes_.end(), id) != touchedMeshes_.end();
}

bool SceneStore::changesOnlyCameraOverlays() const {
  if (worldDirty_) return false;
  for (const auto& instance : instances_) {
    if (!instance || cameraOnlyOverlay(*instance)) continue;
    if (meshTouched(instance->mesh)) return false;
  }
  return true;
}

RenderScene SceneStore::commit() {
  RenderScene scene;
  commit(scene);
  attachLights(scene);
  return scene;
}

void SceneStore::commit(RenderScene& scene) {
  validateReferences();
  lastCommitOnlyCameraOverlays_ = changesOnlyCameraOverlays();
  // The vectors are refilled, keeping their memory.
  scene.textures = textures_;
  scene.materials.clear();
  scene.world.clear();
  scene.overlay.clear();
  scene.emissiveLookup.clear();
  auto texturePtr = [&](TextureId id) { return id == kNoId ? nullptr : scene.textures[id].get(); };
  auto makeRecord = [&](const MaterialDesc& d) {
    MaterialRecord r;
    r.desc = d;
    r.desc.specular = std::clamp(d.specular, 0.0f, 1.0f);
    r.desc.roughness = std::clamp(d.roughness, 0.0f, 1.0f);
    r.desc.opacity = std::clamp(d.opacity, 0.0f, 1.0f);
    r.base = texturePtr(d.baseTexture);
    r.emissive = texturePtr(d.emissiveTexture);
    r.lightmap = texturePtr(d.stock.lightmapTexture);
    r.shine = texturePtr(d.stock.shineTexture);
    r.cover = texturePtr(d.coverTexture);
    r.rule = materialHitRule(d);
    for (const RayKind kind : {RayKind::Camera, RayKind::Bounce, RayKind::Shadow})
      r.filter[static_cast<size_t>(kind)] = materialFilterRule(d, kind);
    r.emits = d.emission.x > 0.0f || d.emission.y > 0.0f || d.emission.z > 0.0f;
    r.seenApart = d.seenEmission.x >= 0.0f && d.seenEmission.y >= 0.0f && d.seenEmission.z >= 0.0f;
    return r;
  };
  scene.materials.reserve(materials_.size());
  for (const MaterialDesc& d : materials_) scene.materials.push_back(makeRecord(d));
  MaterialDesc grey;
  grey.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  scene.defaultMaterial = makeRecord(grey);

  buildMeshes(scene.materials);

  std::vector<TlasInstance>& worldInputs = worldTlasInputs_;
  std::vector<TlasInstance>& overlayInputs = overlayTlasInputs_;
  worldInputs.clear();
  overlayInputs.clear();
  for (size_t id = 0; id < instances_.size(); ++id) {
    if (!instances_[id]) continue;
    const InstanceDesc& d = *instances_[id];
    const MeshRecord* mesh = meshes_[d.mesh].record.get();
    if (mesh == nullptr || mesh->geometry.triangleCount() == 0) continue;
    RenderInstance ri;
    ri.mesh = mesh;
    ri.objectToWorld = d.objectToWorld;
    ri.normalToWorld = glm::transpose(glm::inverse(linearPart(d.objectToWorld)));
    ri.tint = d.tint;
    ri.materialOverride = d.materialOverride;
    ri.mask = d.mask;
    ri.id = static_cast<InstanceId>(id);
    (d.drawOnTop ? scene.overlay : scene.world).push_back(ri);
    (d.drawOnTop ? overlayInputs : worldInputs).push_back({&mesh->blas, d.objectToWorld, d.mask});
  }
  scene.worldTlas.build(worldInputs);
  scene.overlayTlas.build(overlayInputs);
  scene.bounds = worldInputs.empty() ? Bounds{} : scene.worldTlas.bounds();

  scene.portals = portals_;
  scene.fogs = fogs_;
  scene.stockDlights = stockDlights_;   // copied into the scene's memory: no allocation once it is large enough
  // The same sky but for its picture (moving clouds) keeps its sampling distribution.
  if (scene.sky.sameButPicture(sky_, scene.textures))
    scene.sky.setPicture(sky_.picture);
  else
    scene.sky = Sky(sky_, scene.textures);
  // The lights are gathered when a render needs them (attachLights): the Lightmap integrator
  // never samples lights, and its frames skip the pass over every world triangle. Until then
  // the emissive lookup is empty (cleared above) and scene.lights keeps its memory.
  lightsAttached_ = false;
  if (!touchedMeshes_.empty()) {   // instances of an updated mesh show the change
    for (size_t i = 0; i < instances_.size(); ++i)
      if (instances_[i] && meshTouched(instances_[i]->mesh)) pendingSeen_.markInstance(static_cast<InstanceId>(i));
  }
  std::swap(lastSeen_, pendingSeen_);
  pendingSeen_.clear();
  dirty_ = worldDirty_ = false;
  touchedMeshes_.clear();
}

void SceneStore::attachLights(RenderScene& scene) {
  if (lightsAttached_) return;
  scene.emissiveLookup.clear();
  // Emissive triangles of world instances become area lights; sky windows bound how much sun
  // and sky light enters (their area-weighted normals go to the light sampler).
  std::vector<EmissiveTriangle>& emissive = emissiveScratch_;
  emissive.clear();
  std::vector<glm::vec3>& skyWindows = skyWindows_;
  skyWindows.clear();
  for (RenderInstance& inst : scene.world) {
    const MeshGeometry& g = inst.mesh->geometry;
    const uint32_t offset = static_cast<uint32_t>(scene.emissiveLookup.size());
    bool any = false;
    for (uint32_t t = 0; t < g.triangleCount(); ++t) {
      const MaterialRecord& m = scene.materialOf(inst, t);
      if (m.desc.sky) {
        const auto corner = [&](uint32_t k) {
          return glm::vec3(inst.objectToWorld * glm::vec4(g.positions[g.indices[3 * t + k]], 1.0f));
        };
        const glm::vec3 areaNormal = 0.5f * glm::cross(corner(1) - corner(0), corner(2) - corner(0));
        if (std::isfinite(glm::dot(areaNormal, areaNormal))) skyWindows.push_back(areaNormal);
        continue;
      }
      // Sky windows show the sky, additive surfaces add on camera/bounce rays: neither is a light.
      // No ray sees a mask-0 instance (a mover the game did not add this frame, the world in a
      // view without it), so its emitters are no lights either. It stays in the TLAS and its sky
      // windows count, as the world's do in a HUD model view: the sun/sky visibility map keyed
      // on them is then found in the cache instead of traced anew for every such frame.
      if (!m.emits || m.desc.sky || m.desc.alphaMode == AlphaMode::Additive || inst.mask == 0) continue;
      if (!any) {
        scene.emissiveLookup.resize(size_t{offset} + g.triangleCount(), kNoId);
        inst.emissiveOffset = offset;
        any = true;
      }
      const uint32_t i0 = g.indices[3 * t], i1 = g.indices[3 * t + 1], i2 = g.indices[3 * t + 2];
      EmissiveTriangle tri;
      tri.p0 = inst.objectToWorld * glm::vec4(g.positions[i0], 1.0f);
      const glm::vec3 p1 = inst.objectToWorld * glm::vec4(g.positions[i1], 1.0f);
      const glm::vec3 p2 = inst.objectToWorld * glm::vec4(g.positions[i2], 1.0f);
      tri.e1 = p1 - tri.p0;
      tri.e2 = p2 - tri.p0;
      const glm::vec3 cross = glm::cross(tri.e1, tri.e2);
      const float len = glm::length(cross);
      if (!(len > 0.0f) || !std::isfinite(len)) continue;   // zero-area triangles emit nothing
      tri.normal = cross / len;
      tri.area = 0.5f * len;
      if (!g.uvs.empty()) {
        const glm::mat3x2& uvt = m.desc.emissiveOwnUv ? m.desc.emissiveUvTransform : m.desc.uvTransform;
        tri.uv0 = uvt * glm::vec3(g.uvs[i0], 1.0f);
        tri.uv1 = uvt * glm::vec3(g.uvs[i1], 1.0f);
        tri.uv2 = uvt * glm::vec3(g.uvs[i2], 1.0f);
        if (m.desc.uvWobble.amplitude != 0.0f && !m.desc.emissiveOwnUv) {
          tri.uv0 += m.desc.uvWobble.offsetAt(g.positions[i0]);
          tri.uv1 += m.desc.uvWobble.offsetAt(g.positions[i1]);
          tri.uv2 += m.desc.uvWobble.offsetAt(g.positions[i2]);
        }
      } else {
        tri.uv0 = tri.uv1 = tri.uv2 =
            (m.desc.emissiveOwnUv ? m.desc.emissiveUvTransform : m.desc.uvTransform) * glm::vec3(0.0f, 0.0f, 1.0f);
      }
      tri.emission = m.desc.emission;
      tri.texture = m.emissive;
      tri.twoSided = m.desc.twoSided;
      tri.hittable = m.desc.visible && !m.desc.sky && (inst.mask & kMaskBounce) != 0;
      scene.emissiveLookup[size_t{offset} + t] = static_cast<uint32_t>(emissive.size());
      emissive.push_back(tri);
    }
  }

  std::vector<LightDesc>& lights = lightScratch_;
  lights.clear();
  for (const auto& l : lights_) {
    if (l) lights.push_back(*l);
  }
  scene.lights.rebuild(lights, emissive, scene.sky, scene.bounds, skyWindows);
  lightsAttached_ = true;
}

namespace {

/// ~256k points spread by area over what rays can shade in the scene's world instances, with
/// their front normals: what the light visibility maps are traced from.
std::vector<SurfacePoint> shadedSurfacePoints(const RenderScene& scene) {
  constexpr double kPoints = 262144.0;
  const auto forEachTriangle = [&scene](const auto& visit) {
    for (const RenderInstance& inst : scene.world) {
      const MeshGeometry& g = inst.mesh->geometry;
      for (uint32_t t = 0; t < g.triangleCount(); ++t) {
        // Only what rays can shade: not sky windows, hidden or additive surfaces.
        const MaterialDesc& m = scene.materialOf(inst, t).desc;
        if (m.sky || !m.visible || m.alphaMode == AlphaMode::Additive) continue;
        const auto corner = [&](uint32_t k) {
          return glm::vec3(inst.objectToWorld * glm::vec4(g.positions[g.indices[3 * t + k]], 1.0f));
        };
        const glm::vec3 p0 = corner(0), e1 = corner(1) - p0, e2 = corner(2) - p0;
        const glm::vec3 n = glm::cross(e1, e2);
        const float twiceArea = glm::length(n);
        if (twiceArea > 0.0f && std::isfinite(twiceArea)) visit(p0, e1, e2, n / twiceArea, 0.5 * twiceArea);
      }
    }
  };
  double area = 0.0;
  forEachTriangle([&](const glm::vec3&, const glm::vec3&, const glm::vec3&, const glm::vec3&, double a) { area += a; });
  std::vector<SurfacePoint> points;
  uint32_t index = 0;
  forEachTriangle([&](const glm::vec3& p0, const glm::vec3& e1, const glm::vec3& e2, const glm::vec3& n, double a) {
    uint32_t h = sampling::hash32(index++);
    // Expected a / area x kPoints points: the whole part and one more with the fraction's odds.
    const double expected = a / area * kPoints;
    size_t count = size_t(expected);
    if (sampling::toUnitFloat(h) < expected - double(count)) ++count;
    for (size_t k = 0; k < count; ++k) {
      const float u0 = sampling::toUnitFloat(h = sampling::hash32(h + 1u));
      const float u1 = sampling::toUnitFloat(h = sampling::hash32(h + 2u));
      const glm::vec2 b = sampling::uniformTriangle({u0, u1});
      points.push_back({p0 + b.x * e1 + b.y * e2, n});
    }
  });
  return points;
}

}  // namespace

void SceneStore::attachVisibilityMaps(RenderScene& scene) {
  // The surface points both maps are traced from, made once and only when a map is traced.
  std::optional<std::vector<SurfacePoint>> points;
  const SurfacePoints surfacePoints = [&points, &scene] {
    if (!points) points = shadedSurfacePoints(scene);
    return *points;
  };
  attachEnvironmentVisibility(scene, surfacePoints);
  attachLampVisibility(scene, surfacePoints);
}

void SceneStore::attachEnvironmentVisibility(RenderScene& scene, const SurfacePoints& surfacePoints) {
  if (!scene.lights.mixesEnvironmentAndLocal()) return;
  const auto escapes = [&scene](const glm::vec3& origin, const glm::vec3& dir) {
    Ray ray;
    ray.origin = origin;
    ray.dir = dir;
    ray.tmax = std::numeric_limits<float>::infinity();
    TraceRequest request;
    request.kind = RayKind::Shadow;
    request.towardEnvironment = true;
    return !scene.occluded(ray, request);
  };
  scene.lights.sunDirections(sunScratch_);
  scene.lights.setEnvironmentVisibility(environmentVisibility_.get(
      scene.bounds, sunScratch_, !scene.sky.black(), skyWindows_, surfacePoints, escapes));
}

void SceneStore::attachLampVisibility(RenderScene& scene, const SurfacePoints& surfacePoints) {
  if (!lampVisibilityEnabled_) return;
  scene.lights.localLamps(lampScratch_);
  if (lampScratch_.empty()) return;
  const auto reaches = [&scene](const glm::vec3& from, const glm::vec3& to) {
    Ray ray;
    ray.origin = from;
    ray.dir = to - from;
    ray.tmax = 1.0f;
    TraceRequest request;
    request.kind = RayKind::Shadow;
    return !scene.occluded(ray, request);
  };
  scene.lights.setLampVisibility(lampVisibility_.get(scene.bounds, lampScratch_, surfacePoints, reaches));
}

}  // namespace pa
