#pragma once
// What the Lightmap compositor (lightmap_compositor.h) and the Direct/Path integrator
// (path_integrator.h) do alike along a camera path: the closest hit with the drawOnTop overlay
// first, portal crossings, the contribution clamp and the first hit's AOVs.
#include <algorithm>
#include <cstdint>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "renderer/bvh/ray_offset.h"
#include "renderer/scene/film/film.h"
#include "renderer/scene/world/render_scene.h"

namespace pa::trace {

/// Distance of a miss.
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// Mirror and portal bounces allowed beyond maxBounces.
inline constexpr uint32_t kExtraDeltaBounces = 8;
/// Smallest cosine the ray-cone footprint divides by (grazing hits).
inline constexpr float kMinCosForFootprint = 0.05f;

/// The largest of the three components.
inline float maxComponent(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

/// Applies the optional clamp to one contribution. Emitters, sky and additive surfaces seen
/// directly by the camera (depth 0) are exempt so that light sources keep their look.
inline glm::vec3 clampContribution(const glm::vec3& c, uint32_t depth, float limit) {
  if (limit <= 0.0f || depth == 0) return c;
  const float m = maxComponent(c);
  return m > limit ? c * (limit / m) : c;
}

/// The shading normal `ns` (on the viewer's side of the face), bent toward the viewer `wo` where
/// the viewer would see it from below its horizon: a model whose vertex normals disagree with its
/// faces (the first-person rocket launcher's top) would take light from nowhere there and show
/// black. Elsewhere `ns` is returned unchanged.
inline glm::vec3 viewerFacingShadingNormal(const glm::vec3& ns, const glm::vec3& wo) {
  constexpr float kLeastCosine = 0.05f;   // as kMinCosForFootprint
  const float cosine = glm::dot(ns, wo);
  if (cosine >= kLeastCosine) return ns;
  return glm::normalize(ns + (kLeastCosine - cosine) * wo);   // its dot with wo is then > 0
}

/// Closest hit for the vertex at `depth`: the drawOnTop overlay first for camera rays.
/// Additive surfaces are collected only when `seeAdditive` (camera and mirror chains): they
/// are visual effects (glows, flames), not light sources.
inline bool traceClosest(const RenderScene& scene, Ray& ray, Hit& hit, uint32_t depth, uint32_t bits, bool seeAdditive,
                         AdditiveHits& additive, bool& onOverlay) {
  TraceRequest request;
  request.kind = depth == 0 ? RayKind::Camera : RayKind::Bounce;
  request.randomBits = bits;
  request.additive = seeAdditive ? &additive : nullptr;
  onOverlay = false;
  if (depth == 0 && !scene.overlay.empty()) {
    Ray overlayRay = ray;
    request.overlay = true;
    if (scene.intersect(overlayRay, hit, request)) {
      ray = overlayRay;
      onOverlay = true;
      return true;
    }
    request.overlay = false;
  }
  return scene.intersect(ray, hit, request);
}

/// One segment's closest hit: the camera ray traced ahead (`traced`, at depth 0) or a new trace.
struct SegmentHit {
  Hit hit;
  bool found = false;
  bool onOverlay = false;
  AdditiveHits collected;                       ///< Additive surfaces of a new trace.
  const AdditiveHits* additive = &collected;    ///< Additive surfaces along the segment.
};

/// Fills `segment` for the vertex at `depth` (see traceClosest; the camera ray ahead when given).
inline void traceSegment(const RenderScene& scene, Ray& ray, uint32_t depth, uint32_t bits, bool seeAdditive,
                         const TracedCameraRay* traced, SegmentHit& segment) {
  if (depth == 0 && traced) {   // the camera ray was traced ahead (as traceClosest would have)
    segment.hit = traced->hit;
    segment.onOverlay = traced->onOverlay;
    segment.additive = &traced->additive;
    segment.found = traced->found;
    return;
  }
  segment.found = traceClosest(scene, ray, segment.hit, depth, bits, seeAdditive, segment.collected, segment.onOverlay);
}

/// The portal a hit on a mirror material enters (null: none, the material stays a mirror).
inline const PortalDesc* portalEntered(const RenderScene& scene, const SurfaceHit& s, const glm::vec3& dir) {
  if (!s.material->desc.mirror || scene.portals.empty()) return nullptr;
  return scene.portalAt(s.position, s.geometricNormal, dir);
}

/// The ray leaving `portal` on its far side, for a ray along `dir` that met it at `position`.
inline Ray throughPortal(const PortalDesc& portal, const glm::vec3& position, const glm::vec3& dir) {
  const glm::mat3 linear(portal.transform);
  const glm::vec3 exit = portal.transform * glm::vec4(position, 1.0f);
  const glm::vec3 exitDir = glm::normalize(linear * dir);
  const glm::vec3 exitSide = glm::normalize(linear * -portal.normal);
  Ray ray;
  ray.origin = offsetRayOrigin(exit, exitSide);
  ray.dir = exitDir;
  return ray;
}

/// The AOVs of a camera path that sees the sky along `dir`.
inline void recordSkyAovs(const RenderScene& scene, const glm::vec3& dir, PixelSample& out) {
  out.albedo = glm::min(scene.sky.radiance(dir), glm::vec3(1.0f));
  out.normal = glm::vec3(0.0f);
  out.depth = kInfinity;
}

/// The index of a hit's material in scene.materials (kNoId: the default material).
inline MaterialId materialIdOf(const RenderScene& scene, const SurfaceHit& s) {
  return s.material == &scene.defaultMaterial ? kNoId : static_cast<MaterialId>(s.material - scene.materials.data());
}

/// The AOVs of a camera path's first seen surface; reprojection ids only when no portal lies
/// between it and the camera (through a portal the hit does not move with the camera's view).
inline void recordSurfaceAovs(const RenderScene& scene, const SurfaceHit& s, float t, const glm::vec3& albedo,
                              const glm::vec3& ns, bool throughPortal, PixelSample& out) {
  out.albedo = albedo;
  out.normal = ns;
  out.depth = t;
  if (throughPortal) return;
  out.instance = s.instance != nullptr ? s.instance->id : kNoId;
  out.material = materialIdOf(scene, s);
  out.position = s.position;
  out.prim = s.prim;
  out.bary = s.bary;
}

}  // namespace pa::trace
