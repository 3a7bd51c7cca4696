#pragma once
// The committed, immutable scene that render() reads from many threads: resolved materials,
// placed instances with their TLAS, lights and sky, plus the ray queries that apply material
// rules (alpha mask, stochastic blend, additive, nodraw, sky, one-sided, shadow casting)
// through the BVH's HitFilter.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x3.hpp>

#include "renderer/bvh/bvh.h"
#include "renderer/core/ray.h"
#include "renderer/scene/lights/light_sampler.h"
#include "renderer/scene/lights/sky.h"
#include "renderer/scene/media/fog_volumes.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/textures/texture.h"
#include "renderer/scene/world/mesh_geometry.h"

namespace pa {

/// Which rays a query traces (selects the instance mask and material rules).
enum class RayKind : uint8_t { Camera, Bounce, Shadow };

/// What the HitFilter callback does with a candidate hit on a material (materialFilterRule).
enum class FilterAction : uint8_t {
  Accept,     ///< The hit stands.
  Reject,     ///< Not seen by this kind of ray.
  Sky,        ///< A sky window: stops every ray but a shadow ray towards the environment.
  Mask,       ///< Alpha test against the cutoff.
  Blend,      ///< Stochastic transparency.
  Additive,   ///< A see-through layer: recorded as a candidate, never stops the ray.
};

/// A material's FilterAction for one kind of ray, and whether the back face is skipped first
/// (one-sided surfaces seen by camera and bounce rays).
struct FilterRule {
  FilterAction action = FilterAction::Accept;
  bool cullBack = false;
};

/// A material with its textures resolved and its traversal behaviour precomputed.
struct MaterialRecord {
  MaterialDesc desc;
  const Texture* base = nullptr;
  const Texture* emissive = nullptr;
  const Texture* lightmap = nullptr;
  const Texture* shine = nullptr;   ///< StockLook::shineTexture.
  const Texture* cover = nullptr;   ///< MaterialDesc::coverTexture.
  HitRule rule = HitRule::Opaque;   ///< How the BVH treats hits on it (materialHitRule).
  /// What the HitFilter callback does with its hits, by RayKind (materialFilterRule).
  std::array<FilterRule, 3> filter{};
  bool emits = false;      ///< Non-zero emission (collected as area light).
  /// Camera rays see seenEmission in place of emission (MaterialDesc::seenEmission >= 0).
  bool seenApart = false;
};

/// How the BVH treats hits on a material: Opaque for an opaque, visible, two-sided,
/// shadow-casting, non-sky surface; OneSided for the same but one-sided (camera and bounce rays
/// skip its back face in the kernels: HitFilter::cull); Filtered (the HitFilter callback) for
/// anything else.
HitRule materialHitRule(const MaterialDesc& m);

/// The HitFilter callback's rule for hits of `kind` rays on material `m`: the sky first; hidden
/// from the kind (shadow rays: no shadow or additive; others: invisible); opaque two-sided
/// surfaces (and every opaque one for shadow rays) accepted; the back face of one-sided
/// non-additive surfaces skipped by camera and bounce rays; then by alpha mode.
FilterRule materialFilterRule(const MaterialDesc& m, RayKind kind);

/// A placed mesh as seen by rays.
struct RenderInstance {
  const MeshRecord* mesh = nullptr;
  glm::mat4x3 objectToWorld{1.0f};
  glm::mat3 normalToWorld{1.0f};   ///< Inverse transpose of the linear part.
  glm::vec4 tint{1.0f};
  MaterialId materialOverride = kNoId;
  uint32_t mask = kMaskAll;
  InstanceId id = kNoId;
  uint32_t emissiveOffset = kNoId;   ///< Into RenderScene::emissiveLookup (one entry per triangle).
};



/// Additive surfaces crossed by a ray (they add colour and never stop rays). The hit filter
/// records each additive triangle the traversal meets as a candidate; once the ray's closest
/// hit is known, the query works out the layers of the candidates in front of it (entries).
struct AdditiveHits {
  static constexpr uint32_t kCapacity = 32;
  /// Candidates held while the ray is traversed; beyond it the nearest are kept (ties in drawing
  /// order). Each one's layer has room among the entries.
  static constexpr uint32_t kCandidateCapacity = 32;
  struct Entry {
    float t;
    uint32_t instance;
    uint32_t prim;
    glm::vec3 color;      ///< Colour added: linear, or display values (displayValues).
    glm::vec3 transmit;   ///< Display-value multiplier of what is behind (StockLook::layerBlend).
  };
  /// An additive triangle met by the traversal, its layer not yet worked out.
  struct Candidate {
    float t;
    uint32_t instance;
    uint32_t prim;
    float u, v;
    bool overlay;   ///< On a drawOnTop instance (RenderScene::overlay).
  };
  /// Set by whoever traces the ray: the layers are worked out in display values, as a stock
  /// framebuffer blends them (the Lightmap preset's DisplayComposite): textures filtered as
  /// stored, multiplied by display-value vertex colours and factors, and `color` the display
  /// value added. Else (the traced presets) `color` is the linear radiance added.
  bool displayValues = false;
  uint32_t count = 0;
  /// First `count` are valid; once a query returns, in drawing order: by t, coincident ones by
  /// instance, then the later primitive first (a shader's later stage is the nearer layer).
  std::array<Entry, kCapacity> entries;
  uint32_t candidateCount = 0;
  /// First `candidateCount` are valid; a triangle the traversal reports twice may be held twice
  /// (the layers are worked out once per triangle).
  std::array<Candidate, kCandidateCapacity> candidates;
  /// Sum of the colours of entries closer than t (linear colours: not displayValues).
  glm::vec3 sumBefore(float t) const;
  /// Product of the `transmit` multipliers (display values) of entries closer than t.
  glm::vec3 transmitBefore(float t) const;
  /// The order layers are drawn in: by distance, coincident ones (a shader's stages drawn as
  /// copies of one triangle, later stages on later primitives) in stage order (the later nearer).
  static bool drawnBefore(const Entry& a, const Entry& b) {
    if (a.t != b.t) return a.t < b.t;
    if (a.instance != b.instance) return a.instance < b.instance;
    return a.prim > b.prim;
  }
};

/// Options of one ray query.
struct TraceRequest {
  RayKind kind = RayKind::Camera;
  uint32_t randomBits = 0;          ///< Seeds stochastic transparency for this ray.
  bool towardEnvironment = false;   ///< Shadow ray to sun/sky: sky surfaces let it through.
  bool overlay = false;             ///< Trace the drawOnTop instances instead of the world.
  AdditiveHits* additive = nullptr; ///< Collects additive surfaces (camera and bounce rays).
};

/// A camera ray traced ahead of its sample (RenderScene::intersectCameraPacket): what the
/// integrator's first closest-hit query would have returned.
struct TracedCameraRay {
  Ray ray;                  ///< In: the camera ray; out: tmax shortened to the hit.
  uint32_t randomBits = 0;  ///< In: TraceRequest::randomBits of the camera ray.
  Hit hit;                  ///< Out: the closest hit (valid when found).
  bool found = false;       ///< Out: something was hit.
  bool onOverlay = false;   ///< Out: the hit is on a drawOnTop instance.
  AdditiveHits additive;    ///< Out: additive surfaces crossed (TraceRequest::additive).
  /// Out (RenderScene::markFogFreeEnds): no fog volume holds the hit; false from intersectCameraPacket.
  bool fogFreeEnd = false;
};

/// How much of a SurfaceHit RenderScene::surfaceAt works out.
enum class SurfaceParts : uint8_t {
  All,
  /// What a see-through layer's colour reads (once per additive surface a camera ray crosses in
  /// front of its hit): position, uv, emissiveUv, uvArea and vertexColor as baseFactor reads it, and
  /// the winding normal where the material emits (emission's side), with All's bits. Left out:
  /// the shading normal (the geometric one), lightmap and shine uvs (0), the winding normal and
  /// worldArea of a material that does not emit ((0, 0, 1) and 0), and a vertex-lit material's
  /// baked light (StockLook::useVertexLight: vertexColor's RGB stays 1, of which baseFactor reads
  /// only the alpha).
  LayerColour,
  /// All but the shading normal: shadingNormal is the winding normal (geometricNormal), every
  /// other member as All gives it, with All's bits. What a Lightmap sample reads when nothing
  /// reads its normal AOV (RenderSettings::normalAov).
  NoShadingNormal,
};

/// What RenderScene::surfaceAt works out once per triangle (corners in world space, winding
/// normal, uv-space areas), kept for the next hit on the same triangle: the camera rays of a
/// 4x4 packet mostly end on a few. For one thread's consecutive surfaceAt calls while the scene
/// does not change; surfaceAt gives the same bits with or without one.
struct TriangleMemo {
  const RenderInstance* instance = nullptr;   ///< Key (null: holds nothing), with prim and parts.
  uint32_t prim = 0;
  SurfaceParts parts = SurfaceParts::All;
  const MaterialRecord* material = nullptr;
  uint32_t i0 = 0, i1 = 0, i2 = 0;            ///< The corners' vertex indices.
  glm::vec3 p0{0.0f}, p1{0.0f}, p2{0.0f};     ///< The corners in world space.
  glm::vec3 geometricNormal{0.0f, 0.0f, 1.0f};
  float len = 0.0f;                           ///< Length of the corners' cross product.
  float uvArea = 0.0f, shineUvArea = 0.0f;
};

/// Everything the integrator needs about a hit point.
struct SurfaceHit {
  const RenderInstance* instance = nullptr;
  const MaterialRecord* material = nullptr;
  uint32_t prim = 0;
  glm::vec2 bary{0.0f};                 ///< (u, v) weights of vertices 1 and 2.
  glm::vec3 position{0.0f};
  glm::vec3 geometricNormal{0.0f};      ///< Unit winding normal in world space (front side).
  glm::vec3 shadingNormal{0.0f};        ///< Unit interpolated normal in world space (front side).
  glm::vec2 uv{0.0f};                   ///< Base uv after the material's uvTransform.
  glm::vec2 emissiveUv{0.0f};           ///< The emissive texture's uv (the base's, or emissiveUvTransform's).
  glm::vec2 lightmapUv{0.0f};
  glm::vec2 shineUv{0.0f};              ///< Shine texture uv (StockLook::shineTexCoords) after shineUvTransform.
  float shineUvArea = 0.0f;             ///< Triangle area in shine uv space (mip level).
  /// The interpolated vertex colour (linear); with StockLook::useVertexLight its RGB is the baked
  /// light in display values instead (interpolated in display values, as Gouraud shading does).
  glm::vec4 vertexColor{1.0f};
  float worldArea = 0.0f;               ///< Triangle area in world space.
  float uvArea = 0.0f;                  ///< Triangle area in (transformed) uv space.
};

/// RenderScene::coverAt's answer: the cover's colour and how much of the base it covers.
struct CoverTexel {
  glm::vec3 color{0.0f};
  float weight = 0.0f;   ///< In [0, 1].
};

/// The committed scene. Filled by SceneStore::commit(); read-only while rendering.
struct RenderScene {
  std::vector<std::shared_ptr<const Texture>> textures;
  std::vector<MaterialRecord> materials;
  MaterialRecord defaultMaterial;               ///< For kNoId: grey (0.5) diffuse.
  std::vector<RenderInstance> world;            ///< Indexed by the world TLAS instance index.
  std::vector<RenderInstance> overlay;          ///< drawOnTop instances.
  Tlas worldTlas;
  Tlas overlayTlas;
  std::vector<uint32_t> emissiveLookup;         ///< Per emissive instance and triangle: light index or kNoId.
  Sky sky;
  std::vector<PortalDesc> portals;              ///< Mirror-material windows (see scene_types.h).
  std::vector<FogVolume> fogs;                  ///< Fog volumes (media/fog_volumes.h).
  std::vector<StockDynamicLight> stockDlights;  ///< The Lightmap look's dynamic lights (lights/stock_dlights.h).
  LightSampler lights;
  Bounds bounds;

  /// The instances traced by world (false) or drawOnTop (true) queries.
  const std::vector<RenderInstance>& instancesOf(bool drawOnTop) const { return drawOnTop ? overlay : world; }
  /// Material of triangle `prim` of an instance (override, mesh material or default).
  const MaterialRecord& materialOf(const RenderInstance& instance, uint32_t prim) const {
    MaterialId id = instance.materialOverride;
    if (id == kNoId) id = instance.mesh->geometry.materialOf(prim);
    return id < materials.size() ? materials[id] : defaultMaterial;
  }
  /// Closest hit; on a hit shortens ray.tmax and fills hit.
  bool intersect(Ray& ray, Hit& hit, const TraceRequest& request) const;
  /// Closest hits of up to kMaxPacketRays camera rays traced together: for each, what
  /// intersect() with RayKind::Camera and its additive collection gives, drawOnTop instances
  /// first (as the integrator's camera query), the same hit per ray as one by one.
  void intersectCameraPacket(std::span<TracedCameraRay> rays) const;
  /// Sets fogFreeEnd on every ray of a packet traced by intersectCameraPacket when every ray hit
  /// something and no fog volume can hold any of the hits (fogMayHoldEndsIn over the hits' box):
  /// their segments' FogSegment with endInsideOnly is empty (the Lightmap look's camera rays).
  void markFogFreeEnds(std::span<TracedCameraRay> rays) const;
  /// Any blocking hit (shadow rays).
  bool occluded(const Ray& ray, const TraceRequest& request) const;
  /// Interpolated surface data at a hit from intersect() with the same `overlay` choice.
  /// `memo`, when given, keeps the triangle's part for the next call on the same triangle.
  SurfaceHit surfaceAt(const Hit& hit, bool overlay, SurfaceParts parts = SurfaceParts::All,
                       TriangleMemo* memo = nullptr) const;
  /// The same, seen along `ray`: a material with TexCoordSource::ReflectionSphere gets its base
  /// uv (and the uv area that picks its mip level) from the ray (world/reflection_texcoords.cpp).
  SurfaceHit surfaceAt(const Hit& hit, bool overlay, const Ray& ray, SurfaceParts parts = SurfaceParts::All,
                       TriangleMemo* memo = nullptr) const;
  /// Base colour (texture x baseColor x vertex colour x tint, the cover over it, brightened by
  /// StockLook::lightmapStageScale in display values), RGB linear, A = coverage.
  /// footprint: world-space width of the ray's footprint on the surface (picks the mip level;
  /// 0 = full resolution).
  /// `filter`: how the base texture is read (default: two mip levels blended, bilinear).
  glm::vec4 baseColor(const SurfaceHit& s, float footprint, TextureFilter filter = {}) const;
  /// baseColor's factors besides the texture (baseColor x vertex colour x tint, linear).
  glm::vec4 baseFactor(const SurfaceHit& s) const;
  /// baseColor's mip level of the base texture (0 without one).
  float baseLod(const SurfaceHit& s, float footprint) const;
  /// The cover (MaterialDesc::coverTexture) at a hit, mip level from `footprint` as baseColor's:
  /// its RGB (display values with `displayValues`: an sRGB texture read as stored, another
  /// encoded; else linear) and the weight it covers the base with, 0 without a cover.
  CoverTexel coverAt(const SurfaceHit& s, float footprint, TextureFilter filter, bool displayValues) const;
  /// Shine colour (shine texture x shineColor, linear RGB, A = texture alpha; 0 when the
  /// material has none), mip level from `footprint` as baseColor's.
  glm::vec4 shineColor(const SurfaceHit& s, float footprint, TextureFilter filter = {}) const;
  /// Emitted radiance toward the given side (front = the winding normal's side).
  glm::vec3 emission(const SurfaceHit& s, bool frontSide) const;
  /// Emitted radiance as camera rays see it before their first scattering
  /// (MaterialDesc::seenEmission; emission() where the material has none).
  glm::vec3 seenEmission(const SurfaceHit& s, bool frontSide) const;
  /// Unnormalised world-space winding normal of a triangle (front side).
  glm::vec3 windingNormal(const RenderInstance& instance, uint32_t prim) const;
  /// Alpha coverage at barycentrics (full-resolution texture alpha x baseColor.a x vertex alpha
  /// x tint alpha): the cheap path used by alpha tests during traversal.
  float coverageAt(const RenderInstance& instance, uint32_t prim, glm::vec2 bary) const;
  /// The portal entered by a ray along `direction` hitting a surface point with this (unit)
  /// geometric normal: one whose plane holds the point and faces the ray; null if none.
  const PortalDesc* portalAt(const glm::vec3& position, const glm::vec3& normal, const glm::vec3& direction) const;
  /// Index of the hit triangle in lights.triangles(), or kNoId.
  uint32_t emissiveIndex(const SurfaceHit& s) const;
};

}  // namespace pa
