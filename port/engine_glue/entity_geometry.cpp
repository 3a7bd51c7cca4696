#include "port/engine_glue/entity_geometry.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "port/engine_glue/scene.h"
#include "port/q3formats/model/md3.h"
#include "renderer/core/srgb.h"

namespace glue {
namespace {

constexpr float kDegToRad = 3.14159265358979f / 180.0f;
// Widths of the stock renderer's cvars at their defaults.
constexpr float kRailCoreWidth = 6.0f;     // r_railCoreWidth
constexpr float kRailRingsWidth = 16.0f;   // r_railWidth
constexpr float kLightningWidth = 8.0f;
constexpr float kBeamWidth = 8.0f;         // a 6-sided tube of radius 4 in the stock renderer

glm::vec3 vec(const float* v) { return {v[0], v[1], v[2]}; }

/// A quad of `width` from start to end, turned to face the viewer.
void addStrip(const glm::vec3& start, const glm::vec3& end, float width, const Viewer& viewer,
              const glm::vec4& color, q3abi::qhandle_t shader, float uRepeat, GeometryBatch& out) {
  const glm::vec3 along = end - start;
  const float length = glm::length(along);
  if (!(length > 1e-3f)) return;
  glm::vec3 side = glm::cross(along, viewer.origin - start);
  const float sideLength = glm::length(side);
  if (!(sideLength > 1e-6f)) side = viewer.up;   // looking straight down the beam
  else side /= sideLength;
  const glm::vec3 half = side * (width * 0.5f);
  out.addQuad(start + half, end + half, end - half, start - half, color, shader, {0, 0},
              {uRepeat, 1});
}

}  // namespace

void GeometryBatch::clear() {
  positions.clear();
  normals.clear();
  uvs.clear();
  colors.clear();
  indices.clear();
  triangleShaders.clear();
  triangleLayers.clear();
  triangleShaderTimes.clear();
}

void GeometryBatch::addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                            const glm::vec3& d, const glm::vec4& color, q3abi::qhandle_t shader,
                            const glm::vec2& uv0, const glm::vec2& uv1) {
  const auto base = static_cast<uint32_t>(positions.size());
  glm::vec3 normal = glm::cross(b - a, d - a);
  const float length = glm::length(normal);
  normal = length > 1e-12f ? normal / length : glm::vec3(0, 0, 1);
  positions.insert(positions.end(), {a, b, c, d});
  normals.insert(normals.end(), 4, normal);
  uvs.insert(uvs.end(), {{uv0.x, uv0.y}, {uv1.x, uv0.y}, {uv1.x, uv1.y}, {uv0.x, uv1.y}});
  colors.insert(colors.end(), 4, color);
  indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  triangleShaders.insert(triangleShaders.end(), 2, shader);
}

glm::vec4 entityColor(const q3abi::refEntity_t& entity) {
  return {pa::srgbByteToLinear(entity.shaderRGBA[0]), pa::srgbByteToLinear(entity.shaderRGBA[1]),
          pa::srgbByteToLinear(entity.shaderRGBA[2]), entity.shaderRGBA[3] / 255.0f};
}

bool appendEffect(const q3abi::refEntity_t& e, const Viewer& viewer, GeometryBatch& out) {
  const glm::vec4 color = entityColor(e);
  switch (e.reType) {
    case q3abi::RT_SPRITE: {
      if (!(e.radius > 0.0f)) return false;
      const float angle = e.rotation * kDegToRad;
      const float s = std::sin(angle) * e.radius, c = std::cos(angle) * e.radius;
      const glm::vec3 left = viewer.left * c + viewer.up * s;
      const glm::vec3 up = viewer.up * c - viewer.left * s;
      const glm::vec3 o = vec(e.origin);
      out.addQuad(o + left + up, o - left + up, o - left - up, o + left - up, color,
                  e.customShader);
      return true;
    }
    case q3abi::RT_BEAM:
      addStrip(vec(e.origin), vec(e.oldorigin), kBeamWidth, viewer, color, e.customShader, 1.0f, out);
      return true;
    case q3abi::RT_RAIL_CORE: {
      const glm::vec3 start = vec(e.oldorigin), end = vec(e.origin);
      addStrip(start, end, kRailCoreWidth, viewer, color, e.customShader, 1.0f, out);
      return true;
    }
    case q3abi::RT_RAIL_RINGS: {
      // The stock spiral of rings, approximated by a band with the rings texture repeated
      // every r_railSegmentLength (32) units.
      const glm::vec3 start = vec(e.oldorigin), end = vec(e.origin);
      addStrip(start, end, kRailRingsWidth, viewer, color, e.customShader,
               glm::length(end - start) / 32.0f, out);
      return true;
    }
    case q3abi::RT_LIGHTNING: {
      const glm::vec3 start = vec(e.origin), end = vec(e.oldorigin);
      addStrip(start, end, kLightningWidth, viewer, color, e.customShader,
               glm::length(end - start) / 128.0f, out);
      return true;
    }
    default:
      return false;   // RT_MODEL is handled by the caller; RT_POLY / RT_PORTALSURFACE draw nothing
  }
}

void appendPolys(const std::vector<ScenePoly>& polys, const std::vector<q3abi::polyVert_t>& verts,
                 const Viewer& viewer, const std::function<bool(int32_t shader)>& isDecal, GeometryBatch& out) {
  for (const ScenePoly& poly : polys) {
    if (poly.numVerts < 3 || size_t(poly.firstVert) + poly.numVerts > verts.size()) continue;
    const auto base = static_cast<uint32_t>(out.positions.size());
    const q3abi::polyVert_t* v = &verts[poly.firstVert];
    glm::vec3 normal = glm::cross(vec(v[2].xyz) - vec(v[0].xyz), vec(v[1].xyz) - vec(v[0].xyz));
    const float length = glm::length(normal);
    normal = length > 1e-12f ? normal / length : glm::vec3(0, 0, 1);
    const float lift = isDecal && isDecal(poly.shader) ? kDecalLift : 0.0f;
    for (uint32_t i = 0; i < poly.numVerts; ++i) {
      const glm::vec3 corner = vec(v[i].xyz);
      out.positions.push_back(lift > 0.0f ? corner + (viewer.origin - corner) * lift : corner);
      out.normals.push_back(normal);
      out.uvs.emplace_back(v[i].st[0], v[i].st[1]);
      out.colors.emplace_back(pa::srgbByteToLinear(v[i].modulate[0]), pa::srgbByteToLinear(v[i].modulate[1]),
                              pa::srgbByteToLinear(v[i].modulate[2]), v[i].modulate[3] / 255.0f);
    }
    for (uint32_t i = 1; i + 1 < poly.numVerts; ++i) {
      out.indices.insert(out.indices.end(), {base, base + i, base + i + 1});
      out.triangleShaders.push_back(poly.shader);
    }
  }
}

SpriteAxes spriteAxesFor(const q3abi::refEntity_t& entity, const Viewer& viewer) {
  SpriteAxes axes;
  glm::vec3 left, up;
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 axis = vec(entity.axis[k]);
    left[k] = glm::dot(viewer.left, axis);
    up[k] = glm::dot(viewer.up, axis);
  }
  if (entity.nonNormalizedAxes) {
    // The stock renderer divides by the first axis' length to undo the entity's scale.
    const float length = glm::length(vec(entity.axis[0]));
    if (length > 1e-6f) {
      left /= length;
      up /= length;
    }
  }
  axes.left = left;
  axes.up = up;
  return axes;
}

void appendMd3(const q3::Md3Model& model, const q3abi::refEntity_t& entity,
               const std::vector<q3abi::qhandle_t>& surfaceShaders, GeometryBatch& out,
               const std::vector<bool>& autosprite, const SpriteAxes& axes) {
  std::vector<q3::Md3Vec3>& positions = out.scratch.md3Positions;
  std::vector<q3::Md3Vec3>& normals = out.scratch.md3Normals;
  const glm::vec4 white(1.0f);
  for (size_t s = 0; s < model.surfaces.size(); ++s) {
    const q3::Md3Surface& surface = model.surfaces[s];
    q3::lerpSurface(surface, model.frames.size(), entity.frame, entity.oldframe,
                    std::isfinite(entity.backlerp) ? entity.backlerp : 0.0f, positions, normals);
    const q3abi::qhandle_t shader = s < surfaceShaders.size() ? surfaceShaders[s] : 0;
    if (s < autosprite.size() && autosprite[s] && surface.numVerts >= 4) {
      for (int v = 0; v + 3 < surface.numVerts; v += 4) {
        glm::vec3 corners[4];
        for (int c = 0; c < 4; ++c) corners[c] = {positions[v + c][0], positions[v + c][1], positions[v + c][2]};
        const glm::vec3 mid = 0.25f * (corners[0] + corners[1] + corners[2] + corners[3]);
        const float radius = glm::length(corners[0] - mid) * 0.707f;
        const glm::vec3 left = axes.left * radius, up = axes.up * radius;
        // The stock quad stamp: (mid + left + up) at (0, 0), then (1, 0), (1, 1), (0, 1).
        out.addQuad(mid + left + up, mid - left + up, mid - left - up, mid + left - up, white, shader);
      }
      continue;
    }
    const auto base = static_cast<uint32_t>(out.positions.size());
    for (int v = 0; v < surface.numVerts; ++v) {
      out.positions.emplace_back(positions[v][0], positions[v][1], positions[v][2]);
      out.normals.emplace_back(normals[v][0], normals[v][1], normals[v][2]);
      out.uvs.emplace_back(surface.texCoords[v][0], surface.texCoords[v][1]);
      out.colors.push_back(white);
    }
    // MD3 triangles wind clockwise seen from the front, like the BSP: flip to counter-clockwise.
    for (const auto& tri : surface.triangles) {
      out.indices.insert(out.indices.end(), {base + tri[0], base + tri[2], base + tri[1]});
      out.triangleShaders.push_back(shader);
    }
  }
}

}  // namespace glue
