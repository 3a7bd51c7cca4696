#include "renderer/scene/temporal/motion.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "renderer/core/reuse.h"

namespace pa::temporal {

namespace {

/// What an instance's mesh did since the last frame, and its history brought up to this frame:
/// 0 (another mesh or topology, or moved vertices without a copy of the old ones), kRigid (the
/// vertices stayed) or kVertices (they moved; `then` holds where they were).
template <typename History>
uint8_t noteVertices(History& h, const MeshRecord* mesh, uint8_t rigid, uint8_t vertices) {
  if (mesh == nullptr) {
    h.mesh = nullptr;
    h.hasNow = false;
    return 0;
  }
  const bool sameMesh = h.mesh == mesh && h.topologyStamp == mesh->topologyStamp;
  const bool moved = h.positionsStamp != mesh->positionsStamp;
  const std::vector<glm::vec3>& positions = mesh->geometry.positions;
  uint8_t state = 0;
  if (sameMesh && !moved) state = rigid;
  else if (sameMesh && h.hasNow && h.now.size() == positions.size()) state = vertices;
  if (state == vertices) std::swap(h.now, h.then);
  if (!mesh->geometry.dynamic) {
    h.hasNow = false;   // static meshes keep no copy: an update to one counts as disoccluded
  } else if (moved || !sameMesh || !h.hasNow) {
    if (positions.size() > h.now.capacity()) {   // as much as the mesh holds room for, in both halves
      h.now.reserve(positions.capacity());
      h.then.reserve(positions.capacity());
    }
    h.now.assign(positions.begin(), positions.end());   // memory kept between frames
    h.hasNow = true;
  }
  h.mesh = mesh;
  h.positionsStamp = mesh->positionsStamp;
  h.topologyStamp = mesh->topologyStamp;
  return state;
}

}  // namespace

void InstanceMotion::record(std::span<const RenderInstance> instances) {
  for (const RenderInstance& instance : instances) {
    // Hidden instances (reused slots showing nothing) are not recorded: an instance shown again
    // has no previous transform and its pixels count as disoccluded.
    if (instance.id == kNoId || (instance.mask & kMaskCamera) == 0) continue;
    if (instance.id >= current_.size()) {   // grown geometrically: new instances keep coming in play
      reserveGeometric(current_, instance.id + 1);
      reserveGeometric(currentKnown_, instance.id + 1);
      current_.resize(instance.id + 1, glm::mat4x3(1.0f));
      currentKnown_.resize(instance.id + 1, 0);
    }
    if (instance.id >= history_.size()) {   // these are not swapped: they may be longer than current_
      reserveGeometric(vertexState_, instance.id + 1);
      reserveGeometric(history_, instance.id + 1);
      vertexState_.resize(instance.id + 1, 0);
      history_.resize(instance.id + 1);
    }
    current_[instance.id] = instance.objectToWorld;
    currentKnown_[instance.id] = 1;
    vertexState_[instance.id] = noteVertices(history_[instance.id], instance.mesh, kRigid, kVertices);
  }
}

void InstanceMotion::reserveIds(std::span<const RenderInstance> world, std::span<const RenderInstance> overlay) {
  size_t ids = 0;
  for (const auto span : {world, overlay})
    for (const RenderInstance& instance : span)
      if (instance.id != kNoId) ids = std::max(ids, size_t(instance.id) + 1);
  // Both halves of each swapped pair and the per-frame arrays at once: an instance id seen for
  // the first time then costs one growth, not one in each of the next frames.
  reserveGeometric(current_, ids);
  reserveGeometric(previous_, ids);
  reserveGeometric(currentKnown_, ids);
  reserveGeometric(previousKnown_, ids);
  reserveGeometric(vertexState_, ids);
  reserveGeometric(history_, ids);
  reserveGeometric(pointToPrevious_, ids);
  reserveGeometric(normalToPrevious_, ids);
  reserveGeometric(valid_, ids);
}

void InstanceMotion::beginFrame(std::span<const RenderInstance> world, std::span<const RenderInstance> overlay) {
  reserveIds(world, overlay);
  std::swap(current_, previous_);
  std::swap(currentKnown_, previousKnown_);
  std::fill(currentKnown_.begin(), currentKnown_.end(), uint8_t{0});
  record(world);
  record(overlay);
  const size_t n = current_.size();
  pointToPrevious_.assign(n, glm::mat4x3(1.0f));
  normalToPrevious_.assign(n, glm::mat3(1.0f));
  valid_.assign(n, 0);
  for (size_t id = 0; id < n; ++id) {
    if (currentKnown_[id] == 0 || id >= previousKnown_.size() || previousKnown_[id] == 0) continue;
    if (vertexState_[id] == 0) continue;   // another mesh, or vertices moved with no record of where
    const glm::mat4x3& now = current_[id];
    const glm::mat4x3& then = previous_[id];
    if (now == then) {   // the common case (the world): identity, exactly
      valid_[id] = vertexState_[id];
      continue;
    }
    const glm::mat3 linearNow(now);
    const float det = glm::determinant(linearNow);
    if (!std::isfinite(det) || std::abs(det) < 1e-12f) continue;
    const glm::mat3 inverseNow = glm::inverse(linearNow);
    const glm::mat3 linear = glm::mat3(then) * inverseNow;   // world now -> object -> world then
    glm::mat4x3 m(linear);
    m[3] = then[3] - linear * now[3];
    pointToPrevious_[id] = m;
    normalToPrevious_[id] = glm::transpose(glm::inverse(linear));
    valid_[id] = vertexState_[id];
  }
}

bool InstanceMotion::previousOnVertices(InstanceId id, uint32_t prim, glm::vec2 bary, glm::vec3& point) const {
  const VertexHistory& h = history_[id];
  const std::vector<uint32_t>& indices = h.mesh->geometry.indices;
  const size_t first = size_t{prim} * 3;
  if (first + 2 >= indices.size()) return false;
  const uint32_t a = indices[first], b = indices[first + 1], c = indices[first + 2];
  if (a >= h.then.size() || b >= h.then.size() || c >= h.then.size()) return false;
  const glm::vec3 object = (1.0f - bary.x - bary.y) * h.then[a] + bary.x * h.then[b] + bary.y * h.then[c];
  point = previous_[id] * glm::vec4(object, 1.0f);
  return true;
}

void InstanceMotion::reset() {
  std::fill(currentKnown_.begin(), currentKnown_.end(), uint8_t{0});
  std::fill(previousKnown_.begin(), previousKnown_.end(), uint8_t{0});
  std::fill(valid_.begin(), valid_.end(), uint8_t{0});
}

void GBuffer::resize(uint32_t w, uint32_t h) {
  width = w;
  height = h;
  const size_t n = size_t{w} * h;
  instance.resize(n);
  material.resize(n);
  motion.resize(n);
  previousDepth.resize(n);
  previousNormal.resize(n);
}

void GBuffer::write(size_t i, const PixelSample& sample, float px, float py, const InstanceMotion& motions,
                    const CameraRays* previousCamera, bool previousSurface) {
  writeIds(i, sample);
  motion[i] = glm::vec2(kNoMotion);
  if (previousSurface) {
    previousDepth[i] = std::numeric_limits<float>::infinity();
    previousNormal[i] = glm::vec3(0.0f);
  }
  if (sample.instance == kNoId || previousCamera == nullptr) return;
  glm::vec3 point = sample.position;
  glm::vec3 normal = sample.normal;
  if (!motions.toPrevious(sample.instance, sample.prim, sample.bary, point, normal)) return;
  float previousX = 0.0f, previousY = 0.0f;
  if (!previousCamera->project(point, previousX, previousY)) return;
  motion[i] = glm::vec2(previousX - px, previousY - py);
  if (!previousSurface) return;
  previousDepth[i] = glm::length(point - previousCamera->origin());
  const float length = glm::length(normal);
  previousNormal[i] = length > 0.0f ? normal / length : glm::vec3(0.0f);
}

}  // namespace pa::temporal
