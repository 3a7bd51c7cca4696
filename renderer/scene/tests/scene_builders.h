#pragma once
// Small procedural scenes for the pa_scene tests.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>

#include "renderer/scene/renderer.h"

namespace pa::test {

/// Owned mesh arrays that can be handed to the Renderer.
struct MeshArrays {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> colors;
  std::vector<MaterialId> materials;

  MeshDesc desc() const { return meshDescOf(*this, materials); }
  /// Sets every triangle's material.
  void setMaterial(MaterialId id) { materials.assign(indices.size() / 3, id); }
};

/// Parallelogram p0, p0+u, p0+u+v, p0+v; front face (winding normal) along cross(u, v). uv (0,0) at p0.
inline MeshArrays quad(const glm::vec3& p0, const glm::vec3& u, const glm::vec3& v) {
  MeshArrays m;
  m.positions = {p0, p0 + u, p0 + u + v, p0 + v};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

/// Flat-faceted UV sphere with outward winding (front faces outside).
inline MeshArrays sphere(const glm::vec3& center, float radius, uint32_t rings = 24, uint32_t segments = 48) {
  MeshArrays m;
  const float pi = std::numbers::pi_v<float>;
  for (uint32_t r = 0; r <= rings; ++r) {
    const float theta = pi * static_cast<float>(r) / static_cast<float>(rings);
    for (uint32_t s = 0; s <= segments; ++s) {
      const float phi = 2.0f * pi * static_cast<float>(s) / static_cast<float>(segments);
      m.positions.push_back(center + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                        std::sin(theta) * std::sin(phi), std::cos(theta)));
      m.uvs.emplace_back(static_cast<float>(s) / segments, static_cast<float>(r) / rings);
    }
  }
  const uint32_t stride = segments + 1;
  for (uint32_t r = 0; r < rings; ++r) {
    for (uint32_t s = 0; s < segments; ++s) {
      const uint32_t a = r * stride + s, b = a + 1, c = a + stride, d = c + 1;
      // cross(theta-hat, phi-hat) points outward: (a, c, b) and (b, c, d) face out; pole triangles are skipped.
      if (r != 0) m.indices.insert(m.indices.end(), {a, c, b});
      if (r != rings - 1) m.indices.insert(m.indices.end(), {b, c, d});
    }
  }
  return m;
}

/// Adds `mesh` with every triangle in `material` to a Renderer or a SceneStore (same member names).
template <typename Target>
void addMesh(Target& target, MeshArrays mesh, MaterialId material) {
  mesh.setMaterial(material);
  target.addInstance({target.addMesh(mesh.desc())});
}

/// Camera at origin looking at target (Z-up world; +X up when looking along Z).
inline Camera lookAt(const glm::vec3& origin, const glm::vec3& target, float fovDegrees) {
  Camera c;
  c.origin = origin;
  c.forward = glm::normalize(target - origin);
  const glm::vec3 worldUp = std::abs(c.forward.z) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  c.left = glm::normalize(glm::cross(worldUp, c.forward));
  c.up = glm::cross(c.forward, c.left);
  c.fovX = fovDegrees;
  c.fovY = fovDegrees;
  return c;
}

/// Material with a constant colour.
inline MaterialDesc diffuse(float albedo) {
  MaterialDesc m;
  m.baseColor = glm::vec4(albedo, albedo, albedo, 1.0f);
  return m;
}

/// Settings for a small square image.
inline RenderSettings settingsFor(Integrator integrator, uint32_t size, uint32_t spp, uint32_t maxBounces = 4) {
  RenderSettings s;
  s.width = size;
  s.height = size;
  s.integrator = integrator;
  s.samplesPerPixel = spp;
  s.maxBounces = maxBounces;
  return s;
}

/// Mean luminance-free statistics of a frame: mean of the green channel and the standard
/// error of that image mean from the film's per-pixel variances (luminance of grey = grey).
struct FrameStats {
  double mean = 0.0;
  double standardError = 0.0;
  double minValue = 1e30;
  double maxValue = -1e30;
};

inline FrameStats greyStats(const FrameView& f) {
  FrameStats s;
  const size_t n = f.radiance.size();
  double varSum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double g = f.radiance[i].g;
    s.mean += g;
    s.minValue = std::min(s.minValue, g);
    s.maxValue = std::max(s.maxValue, g);
    varSum += f.variance[i];
  }
  s.mean /= static_cast<double>(n);
  s.standardError = std::sqrt(varSum) / static_cast<double>(n);
  return s;
}

/// A frame's buffers as bytes, for bit-exact comparisons: radiance, albedo, normal, depth,
/// variance and RGBA8; with `history` also the picture shown, the motion and the temporal history.
inline std::vector<uint8_t> frameBytes(const FrameView& f, bool history = false) {
  std::vector<uint8_t> out;
  const auto append = [&out](auto span) {
    const auto* bytes = reinterpret_cast<const uint8_t*>(span.data());
    out.insert(out.end(), bytes, bytes + span.size_bytes());
  };
  append(f.radiance);
  append(f.albedo);
  append(f.normal);
  append(f.depth);
  append(f.variance);
  append(f.rgba8);
  if (history) {
    append(f.output);
    append(f.motion);
    append(f.historyLength);
  }
  return out;
}

/// 1x1 or larger RGBA8 texture filled with one colour.
inline std::vector<uint8_t> solidPixels(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  std::vector<uint8_t> p(size_t{w} * h * 4);
  for (size_t i = 0; i < p.size(); i += 4) {
    p[i] = r;
    p[i + 1] = g;
    p[i + 2] = b;
    p[i + 3] = a;
  }
  return p;
}

/// Adds a 10x10 quad in the plane z = 0 with material m, every vertex at the centre of its
/// lightmap, and commits.
inline void addLightmappedFloor(Renderer& r, const MaterialDesc& m) {
  MeshArrays q = quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  q.setMaterial(r.addMaterial(m));
  const std::vector<glm::vec2> lightmapUvs(4, glm::vec2(0.5f));
  MeshDesc desc = q.desc();
  desc.lightmapUvs = lightmapUvs;
  r.addInstance({r.addMesh(desc)});
  r.commit();
}

}  // namespace pa::test
