#pragma once
// The editable scene behind pa::Renderer's setters: validated copies of everything the user
// hands in, with stable ids. commit() turns it into an immutable RenderScene (building and
// refitting BLASes, the TLAS and the light tables).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "renderer/scene/media/fog_volumes.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/textures/texture.h"
#include "renderer/scene/world/mesh_geometry.h"
#include "renderer/scene/world/render_scene.h"
#include "renderer/scene/world/seen_changes.h"

namespace pa {

/// Editable scene state; every setter validates and throws SceneError.
class SceneStore {
 public:
  /// Adds a mesh (copied, validated).
  MeshId addMesh(const MeshDesc& mesh);
  /// Replaces a mesh's data at the next commit.
  void updateMesh(MeshId id, const MeshDesc& mesh);
  /// Removes a mesh at the next commit.
  void removeMesh(MeshId id);
  /// Gives mesh id at least the memory mesh example holds (its arrays, the copy its updates go
  /// to and its BVH's), so that updates up to example's size and shape allocate nothing.
  void reserveMeshLike(MeshId id, MeshId example);
  /// Adds an instance.
  InstanceId addInstance(const InstanceDesc& instance);
  /// Replaces an instance.
  void setInstance(InstanceId id, const InstanceDesc& instance);
  /// Removes an instance.
  void removeInstance(InstanceId id);
  /// Adds a texture.
  TextureId addTexture(const TextureDesc& texture);
  /// Replaces a texture.
  void updateTexture(TextureId id, const TextureDesc& texture);
  /// Adds a material.
  MaterialId addMaterial(const MaterialDesc& material);
  /// Replaces a material.
  void setMaterial(MaterialId id, const MaterialDesc& material);
  /// Adds an analytic light.
  LightId addLight(const LightDesc& light);
  /// Replaces a light.
  void setLight(LightId id, const LightDesc& light);
  /// Removes a light.
  void removeLight(LightId id);
  /// Sets the environment.
  void setSky(const SkyDesc& sky);
  /// Replaces the portals (normals are normalised).
  void setPortals(std::span<const PortalDesc> portals);
  /// Replaces the fog volumes (validated, planes normalised).
  void setFogVolumes(std::span<const FogVolumeDesc> volumes);
  /// Replaces the stock dynamic lights (non-finite or out-of-range values throw).
  void setStockDynamicLights(std::span<const StockDynamicLight> lights);

  /// True when something changed since the last successful commit.
  bool dirty() const { return dirty_; }
  /// True when the last commit changed only camera-only overlays (cameraOnlyOverlay instances and
  /// meshes no other instance uses): what every other ray sees, and every pixel they cover, stayed.
  bool lastCommitOnlyCameraOverlays() const { return lastCommitOnlyCameraOverlays_; }
  /// What the last commit changed that camera rays see (seen_changes.h).
  const SeenChanges& lastCommitSeenChanges() const { return lastSeen_; }
  /// How meshes' BVHs are built from the next commit on (RendererConfig::bvh).
  void setBvhConfig(const BvhBuildConfig& config) { bvhConfig_ = config; }
  /// Validates cross references, builds acceleration structures and light tables into a new
  /// RenderScene. Run inside the renderer's task arena. Throws SceneError (leaving the
  /// store unchanged) when an instance uses a removed mesh or an id is out of range.
  RenderScene commit();
  /// The same, into scene (this store's previous commit, or empty), reusing its memory, but
  /// without the lights (scene.lights empty, no emissive lookup) until attachLights().
  void commit(RenderScene& scene);
  /// Gives scene (this store's last commit) its light sampler: lights, emissive triangles of
  /// the world instances and sky windows. Once per commit; integrators that sample lights need it.
  void attachLights(RenderScene& scene);
  /// Gives scene (this store's last commit) the maps Direct and Path use to share light samples,
  /// both traced from the same ~256k surface points (made once, only when a map is traced): where
  /// sun and sky reach (cached while the scene bounds, suns, sky and sky windows stay), and which
  /// lamps the surfaces of each region cannot see (lights/lamp_visibility.h; cached while the
  /// scene bounds and most of its lamps stay; nothing when switched off, setLampVisibility). Only
  /// renders that need them pay for them.
  void attachVisibilityMaps(RenderScene& scene);
  /// Whether attachVisibilityMaps gives scenes a lamp visibility map (RendererConfig::lampVisibility).
  void setLampVisibility(bool enabled) { lampVisibilityEnabled_ = enabled; }

 private:
  /// The surface points the visibility maps are traced from.
  using SurfacePoints = std::function<std::vector<SurfacePoint>()>;
  void attachEnvironmentVisibility(RenderScene& scene, const SurfacePoints& surfacePoints);
  void attachLampVisibility(RenderScene& scene, const SurfacePoints& surfacePoints);

  BvhBuildConfig bvhConfig_{};
  struct MeshSlot {
    std::unique_ptr<MeshRecord> record;        ///< Committed data (null before the first commit).
    MeshGeometry pending;                      ///< Data for the next commit when hasPending (memory kept).
    bool hasPending = false;
    bool removed = false;                      ///< removeMesh() was called.
  };

  void validateReferences() const;
  void validateMaterial(const MaterialDesc& m, const CallContext& what) const;
  LightDesc validateLight(const LightDesc& l, const CallContext& what) const;
  void validateInstance(const InstanceDesc& d, const CallContext& what) const;
  MeshSlot& liveMesh(MeshId id, const char* call);
  void buildMeshes(const std::vector<MaterialRecord>& materials);
  bool changesOnlyCameraOverlays() const;
  bool meshTouched(MeshId id) const;   ///< updateMesh() changed mesh id since the last commit.

  std::vector<MeshSlot> meshes_;
  std::vector<std::optional<InstanceDesc>> instances_;
  std::vector<std::shared_ptr<const Texture>> textures_;
  std::vector<MaterialDesc> materials_;
  std::vector<std::optional<LightDesc>> lights_;
  SkyDesc sky_;
  std::vector<PortalDesc> portals_;
  std::vector<PortalDesc> portalScratch_;          ///< setPortals()' validated copy (memory kept).
  std::vector<FogVolume> fogs_;
  std::vector<StockDynamicLight> stockDlights_;   ///< Memory kept: the glue sets them every frame.
  EnvironmentVisibilityCache environmentVisibility_;   ///< Where sun and sky reach (lights/).
  std::vector<glm::vec3> skyWindows_;                  ///< The last commit's sky windows (area x normal).
  std::vector<glm::vec3> sunScratch_;                  ///< attachEnvironmentVisibility's sun directions (memory kept).
  LampVisibilityCache lampVisibility_;                 ///< Which lamps each region cannot see (lights/).
  std::vector<LightDesc> lampScratch_;                 ///< attachLampVisibility's lamps (memory kept).
  bool lampVisibilityEnabled_ = true;
  bool dirty_ = true;
  bool worldDirty_ = true;                   ///< A change since the last commit beyond camera-only overlays.
  std::vector<MeshId> touchedMeshes_;        ///< Meshes updated since the last commit.
  uint64_t meshStamps_ = 0;                  ///< The last MeshRecord position/topology stamp handed out.
  /// A mesh's BVH work at commit: a build, or a refit of the same topology.
  struct MeshJob {
    MeshRecord* record;
    bool refit;
  };
  std::vector<MeshJob> meshJobs_;                ///< buildMeshes' list (memory kept between commits).
  /// buildMeshes' per mesh: the hit rule all override materials of its instances agree on
  /// (HitRule::Filtered where they differ), or no value where no instance overrides.
  std::vector<std::optional<HitRule>> overrideRuleScratch_;
  std::vector<TlasInstance> worldTlasInputs_;      ///< commit()'s TLAS inputs (memory kept).
  std::vector<TlasInstance> overlayTlasInputs_;
  std::vector<LightDesc> lightScratch_;            ///< attachLights()' live lights (memory kept).
  bool lightsAttached_ = false;                    ///< The last commit has its lights.
  std::vector<EmissiveTriangle> emissiveScratch_;  ///< attachLights()' emissive triangles (memory kept).
  bool lastCommitOnlyCameraOverlays_ = false;
  SeenChanges pendingSeen_;                        ///< Seen edits since the last commit.
  SeenChanges lastSeen_;                           ///< The last commit's seen edits.
};

}  // namespace pa
