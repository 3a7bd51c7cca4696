#pragma once
// Thin RAII wrapper over Embree 3 for the oracle tests and the bench: one device, one scene of
// triangle meshes or of instances of such scenes; single-ray and 16-ray packet queries that
// speak our Ray/Hit types.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/mat4x3.hpp>

#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/core/ray.h"

namespace pa::testing {

/// Owns an RTCDevice.
class EmbreeDevice {
 public:
  /// config is Embree's device config string (e.g. "threads=1").
  explicit EmbreeDevice(const std::string& config = "");
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;
  /// The raw device.
  RTCDevice get() const { return device_; }
  /// Widest native packet ISA in words ("AVX-512 (ray16 native)", ...).
  std::string isaDescription() const;

 private:
  RTCDevice device_ = nullptr;
};

/// Build options for an Embree scene.
struct EmbreeSceneOptions {
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;   ///< Embree's default.
  bool robust = false;                                  ///< RTC_SCENE_FLAG_ROBUST.
};

/// An Embree scene. Geometry ids follow insertion order.
class EmbreeScene {
 public:
  explicit EmbreeScene(const EmbreeDevice& device, const EmbreeSceneOptions& options = {});
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Adds a triangle mesh (data copied into Embree buffers); returns its geometry id. With
  /// cullBackFaces, hits on its HitRule::OneSided triangles seen from behind
  /// (dot(cross(v1 - v0, v2 - v0), dir) > 0, in the scene's space) are rejected by Embree filter
  /// functions: the oracle of rays with HitFilter::cull = Back in a flat scene.
  uint32_t addMesh(const TestMesh& mesh, bool cullBackFaces = false);
  /// Adds an instance of a committed scene; returns its geometry id.
  uint32_t addInstance(const EmbreeScene& scene, const glm::mat4x3& objectToWorld, uint32_t mask = 0xffffffffu);
  /// Builds the acceleration structure (in the caller's TBB arena).
  void commit();

  /// Closest hit; fills hit.prim (primID), hit.instance (instID or geomID for a flat scene).
  bool intersect(Ray& ray, Hit& hit, uint32_t mask = 0xffffffffu) const;
  /// Any hit.
  bool occluded(const Ray& ray, uint32_t mask = 0xffffffffu) const;
  /// 16 rays as one coherent packet (rtcIntersect16); rays.size() <= 16, hits same size.
  void intersect16(std::span<Ray> rays, std::span<Hit> hits) const;
  /// Any hits of up to 16 rays as one coherent packet (rtcOccluded16): bit i set where rays[i]
  /// hits something.
  uint32_t occluded16(std::span<const Ray> rays) const;

  /// The raw scene.
  RTCScene get() const { return scene_; }

 private:
  struct CulledMesh;
  RTCDevice device_;
  RTCScene scene_ = nullptr;
  std::vector<std::unique_ptr<CulledMesh>> culledMeshes_;   ///< Filter functions' data.
  bool hasInstances_ = false;
};

}  // namespace pa::testing
