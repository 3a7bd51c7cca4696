#include "port/engine_glue/portals.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/world/world_scene.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

/// An entity this far from a portal's plane (either side) can own it.
constexpr float kPortalEntityReach = 64.0f;
/// Planes closer than this (normal and distance) are one portal.
constexpr float kSameNormal = 1e-3f, kSameDist = 0.1f;
constexpr float kDegrees = 3.14159265358979f / 180.0f;

/// The engine's PerpendicularVector: the axis of the smallest component, projected onto the plane.
glm::vec3 perpendicular(const glm::vec3& n) {
  int axis = 0;
  float smallest = 1.0f;
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(n[k]) < smallest) {
      axis = k;
      smallest = std::fabs(n[k]);
    }
  }
  glm::vec3 e(0.0f);
  e[axis] = 1.0f;
  return glm::normalize(e - glm::dot(e, n) / glm::dot(n, n) * n);
}

/// `v` turned by `degrees` about the unit axis `k` (right-handed, as RotatePointAroundVector).
glm::vec3 rotateAbout(const glm::vec3& v, const glm::vec3& k, float degrees) {
  const float c = std::cos(degrees * kDegrees), s = std::sin(degrees * kDegrees);
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0f - c);
}

bool finiteVec(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

bool samePlane(const PortalPlane& a, const PortalPlane& b) {
  return glm::length(a.normal - b.normal) < kSameNormal && std::fabs(a.dist - b.dist) < kSameDist;
}

}  // namespace

std::vector<PortalPlane> findPortalPlanes(const q3::BspFile& bsp, const std::vector<bool>& portalShader) {
  std::vector<PortalPlane> planes;
  if (bsp.models.empty()) return planes;
  const q3::BspModel& world = bsp.models[0];
  for (int32_t i = 0; i < world.numSurfaces; ++i) {
    const size_t index = static_cast<size_t>(world.firstSurface) + static_cast<size_t>(i);
    if (index >= bsp.surfaces.size()) break;
    const q3::BspSurface& s = bsp.surfaces[index];
    const auto shader = static_cast<size_t>(s.shader);
    if (shader >= portalShader.size() || !portalShader[shader] || s.numVerts < 3) continue;
    if (s.type != q3::SurfaceType::Planar && s.type != q3::SurfaceType::TriangleSoup) continue;   // patches: no plane
    const auto vertex = [&](int32_t k) { return bsp.drawVerts[static_cast<size_t>(s.firstVert + k)].position; };
    const auto corner = [&](int32_t k) { return vertex(bsp.drawIndexes[static_cast<size_t>(s.firstIndex + k)]); };
    PortalPlane plane;
    glm::vec3 onPlane = vertex(0);
    if (s.type == q3::SurfaceType::Planar) plane.normal = s.lightmapVecs[2];
    // Soups use their first triangle (PlaneFromPoints on Quake's clockwise winding). So do faces
    // without a stored normal: q3map leaves it zero on `nolightmap` faces, which every portal
    // shader of OpenArena is, and the engine then has no usable plane at all.
    if (!(glm::length(plane.normal) > 1e-6f) && s.numIndexes >= 3) {
      plane.normal = glm::cross(corner(2) - corner(0), corner(1) - corner(0));
      onPlane = corner(0);
    }
    const float length = glm::length(plane.normal);
    if (!(length > 1e-6f) || !std::isfinite(length)) continue;
    plane.normal /= length;
    plane.dist = glm::dot(plane.normal, onPlane);
    if (!std::isfinite(plane.dist)) continue;
    bool known = false;
    for (const PortalPlane& p : planes) known = known || samePlane(p, plane);
    if (!known) planes.push_back(plane);
  }
  return planes;
}

std::optional<pa::PortalDesc> portalFor(const PortalPlane& plane, std::span<const q3abi::refEntity_t> entities,
                                        int timeMs) {
  for (const q3abi::refEntity_t& e : entities) {
    if (e.reType != q3abi::RT_PORTALSURFACE || !finiteVec(e.origin) || !finiteVec(e.oldorigin)) continue;
    const glm::vec3 origin(e.origin[0], e.origin[1], e.origin[2]);
    const glm::vec3 cameraOrigin(e.oldorigin[0], e.oldorigin[1], e.oldorigin[2]);
    const float offset = glm::dot(origin, plane.normal) - plane.dist;
    if (offset > kPortalEntityReach || offset < -kPortalEntityReach) continue;

    // The surface frame: the plane normal and the engine's choice of in-plane axes.
    const glm::mat3 surface(plane.normal, perpendicular(plane.normal),
                            glm::cross(plane.normal, perpendicular(plane.normal)));
    glm::vec3 surfaceOrigin, cameraAt;
    glm::mat3 camera;
    if (origin == cameraOrigin) {
      // A mirror: the camera frame is the surface frame turned to face back.
      surfaceOrigin = cameraAt = plane.normal * plane.dist;
      camera = glm::mat3(-surface[0], surface[1], surface[2]);
    } else {
      surfaceOrigin = origin - offset * plane.normal;
      cameraAt = cameraOrigin;
      const glm::vec3 forward(e.axis[0][0], e.axis[0][1], e.axis[0][2]);
      const glm::vec3 left(e.axis[1][0], e.axis[1][1], e.axis[1][2]);
      const glm::vec3 up(e.axis[2][0], e.axis[2][1], e.axis[2][2]);
      camera = glm::mat3(-forward, -left, up);
      float roll = 0.0f;
      bool rolled = false;
      if (e.oldframe != 0) {
        roll = e.frame != 0 ? timeMs / 1000.0f * static_cast<float>(e.frame)
                            : static_cast<float>(e.skinNum) + std::sin(static_cast<float>(timeMs) * 0.003f) * 4.0f;
        rolled = true;
      } else if (e.skinNum != 0) {
        roll = static_cast<float>(e.skinNum);
        rolled = true;
      }
      if (rolled) {
        camera[1] = rotateAbout(camera[1], camera[0], roll);
        camera[2] = glm::cross(camera[0], camera[1]);
      }
    }
    // R_MirrorPoint: p -> cameraAt + sum_i dot(p - surfaceOrigin, surface_i) camera_i.
    const glm::mat3 linear = camera * glm::transpose(surface);
    pa::PortalDesc portal;
    portal.normal = plane.normal;
    portal.distance = plane.dist;
    portal.transform = glm::mat4x3(linear[0], linear[1], linear[2], cameraAt - linear * surfaceOrigin);
    const float det = glm::determinant(linear);
    if (!std::isfinite(det) || std::fabs(det) < 1e-3f) return std::nullopt;   // degenerate axes
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(portal.transform[c][k])) return std::nullopt;
    return portal;
  }
  return std::nullopt;   // the engine draws no portal view without an entity
}

void PortalViews::load(const q3::BspFile& bsp, const q3::WorldScene& scene) {
  clear();
  std::unordered_set<std::string> portalNames;
  for (const q3::WorldMaterial& m : scene.materials)
    if (m.mirror) portalNames.insert(m.shaderName);
  if (portalNames.empty()) return;
  std::vector<bool> portalShader(bsp.shaders.size(), false);
  for (size_t i = 0; i < bsp.shaders.size(); ++i) portalShader[i] = portalNames.count(bsp.shaders[i].name) > 0;
  planes_ = findPortalPlanes(bsp, portalShader);
}

void PortalViews::clear() {
  planes_.clear();
  current_.clear();
}

void PortalViews::update(std::span<const q3abi::refEntity_t> entities, int timeMs, pa::Renderer& renderer) {
  std::vector<pa::PortalDesc>& portals = candidate_;
  portals.clear();
  for (const PortalPlane& plane : planes_)
    if (auto portal = portalFor(plane, entities, timeMs)) portals.push_back(*portal);
  const bool same = portals.size() == current_.size() &&
                    std::equal(portals.begin(), portals.end(), current_.begin(), [](const auto& a, const auto& b) {
                      return a.normal == b.normal && a.distance == b.distance && a.transform == b.transform;
                    });
  if (same) return;
  renderer.setPortals(portals);
  current_.swap(portals);
}

}  // namespace glue
