#include "renderer/bvh/testing/embree_oracle.h"

#include <cstring>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace pa::testing {
namespace {

void throwOnError(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree error in ") + what + ": " + std::to_string(err));
}

RTCRayHit toRtc(const Ray& r, uint32_t mask) {
  RTCRayHit rh{};
  rh.ray.org_x = r.origin.x; rh.ray.org_y = r.origin.y; rh.ray.org_z = r.origin.z;
  rh.ray.dir_x = r.dir.x; rh.ray.dir_y = r.dir.y; rh.ray.dir_z = r.dir.z;
  rh.ray.tnear = r.tmin;
  rh.ray.tfar = r.tmax;
  rh.ray.mask = mask;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

/// A mesh whose one-sided triangles' back faces the filter functions reject.
struct EmbreeScene::CulledMesh {
  TestMesh mesh;

  /// Embree intersect and occluded filter: clears valid[i] for back-face hits on one-sided triangles.
  static void reject(const RTCFilterFunctionNArguments* args) {
    const auto& self = *static_cast<const CulledMesh*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
      if (args->valid[i] != -1) continue;
      const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
      if (self.mesh.rules.empty() || self.mesh.rules[prim] != HitRule::OneSided) continue;
      const glm::vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                          RTCRayN_dir_z(args->ray, args->N, i));
      const auto vertex = [&](int c) { return self.mesh.positions[self.mesh.indices[3 * prim + c]]; };
      if (glm::dot(glm::cross(vertex(1) - vertex(0), vertex(2) - vertex(0)), dir) > 0.0f) args->valid[i] = 0;
    }
  }
};

EmbreeDevice::EmbreeDevice(const std::string& config) {
  device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (device_ == nullptr) throw std::runtime_error("rtcNewDevice failed");
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

std::string EmbreeDevice::isaDescription() const {
  if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return "AVX-512 (native ray16)";
  if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) return "AVX/AVX2 (native ray8)";
  if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED)) return "SSE (native ray4)";
  return "scalar";
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device, const EmbreeSceneOptions& options) : device_(device.get()) {
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, options.quality);
  if (options.robust) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  throwOnError(device_, "rtcNewScene");
}

EmbreeScene::~EmbreeScene() { rtcReleaseScene(scene_); }

uint32_t EmbreeScene::addMesh(const TestMesh& mesh, bool cullBackFaces) {
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.positions.size()));
  std::memcpy(v, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  auto* ix = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(uint32_t), mesh.triangleCount()));
  std::memcpy(ix, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  if (cullBackFaces) {
    culledMeshes_.push_back(std::make_unique<CulledMesh>(CulledMesh{mesh}));
    rtcSetGeometryUserData(geom, culledMeshes_.back().get());
    rtcSetGeometryIntersectFilterFunction(geom, &CulledMesh::reject);
    rtcSetGeometryOccludedFilterFunction(geom, &CulledMesh::reject);
  }
  rtcCommitGeometry(geom);
  const uint32_t id = rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  throwOnError(device_, "addMesh");
  return id;
}

uint32_t EmbreeScene::addInstance(const EmbreeScene& scene, const glm::mat4x3& objectToWorld, uint32_t mask) {
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, scene.get());
  rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, &objectToWorld[0][0]);
  rtcSetGeometryMask(geom, mask);
  rtcCommitGeometry(geom);
  const uint32_t id = rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  hasInstances_ = true;
  throwOnError(device_, "addInstance");
  return id;
}

void EmbreeScene::commit() {
  rtcCommitScene(scene_);
  throwOnError(device_, "rtcCommitScene");
}

bool EmbreeScene::intersect(Ray& ray, Hit& hit, uint32_t mask) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = toRtc(ray, mask);
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  ray.tmax = rh.ray.tfar;
  hit = {rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID, hasInstances_ ? rh.hit.instID[0] : rh.hit.geomID};
  return true;
}

bool EmbreeScene::occluded(const Ray& ray, uint32_t mask) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = toRtc(ray, mask).ray;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0.0f;
}

namespace {

/// Up to 16 rays into Embree's packet layout: lanes past rays.size() are idle (valid 0).
void packRays16(std::span<const Ray> rays, RTCRay16& packet, int (&valid)[16]) {
  for (size_t i = 0; i < 16; ++i) {
    valid[i] = i < rays.size() ? -1 : 0;
    const Ray r = i < rays.size() ? rays[i] : Ray{};
    packet.org_x[i] = r.origin.x; packet.org_y[i] = r.origin.y; packet.org_z[i] = r.origin.z;
    packet.dir_x[i] = r.dir.x; packet.dir_y[i] = r.dir.y; packet.dir_z[i] = r.dir.z;
    packet.tnear[i] = r.tmin;
    packet.tfar[i] = r.tmax;
    packet.mask[i] = 0xffffffffu;
    packet.flags[i] = 0;
  }
}

/// A context that tells Embree the packet's rays are coherent.
RTCIntersectContext coherentContext() {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  return context;
}

}  // namespace

void EmbreeScene::intersect16(std::span<Ray> rays, std::span<Hit> hits) const {
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[16];
  packRays16(rays, packet.ray, valid);
  for (size_t i = 0; i < 16; ++i) {
    packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context = coherentContext();
  rtcIntersect16(valid, scene_, &context, &packet);
  for (size_t i = 0; i < rays.size(); ++i) {
    if (packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
      hits[i] = Hit{};
      continue;
    }
    rays[i].tmax = packet.ray.tfar[i];
    hits[i] = {packet.ray.tfar[i], packet.hit.u[i], packet.hit.v[i], packet.hit.primID[i],
               hasInstances_ ? packet.hit.instID[0][i] : packet.hit.geomID[i]};
  }
}

uint32_t EmbreeScene::occluded16(std::span<const Ray> rays) const {
  alignas(64) RTCRay16 packet;
  alignas(64) int valid[16];
  packRays16(rays, packet, valid);
  RTCIntersectContext context = coherentContext();
  rtcOccluded16(valid, scene_, &context, &packet);
  uint32_t occluded = 0;   // Embree sets tfar to -inf where a ray hit something
  for (size_t i = 0; i < rays.size(); ++i)
    if (packet.tfar[i] == -std::numeric_limits<float>::infinity()) occluded |= 1u << i;
  return occluded;
}

}  // namespace pa::testing
