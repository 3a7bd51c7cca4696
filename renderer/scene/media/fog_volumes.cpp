#include "renderer/scene/media/fog_volumes.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "renderer/core/finite.h"
#include "renderer/scene/textures/texture.h"

namespace pa {

namespace {

constexpr float kFogStart = 1.0f / 64.0f;     // fraction of depthForOpaque before any fog shows
constexpr float kParallel = 1e-12f;
constexpr float kEndSlack = 1e-4f;            // relative tolerance of "the segment ends inside"           // |dot(n, dir)| below this: the ray runs along the plane


/// Sets volume's box from its corners (every point where three planes meet that lies inside
/// the others), in double precision, when the volume is bounded: clipped to a cube of side
/// 2 kFar, a corner on the cube means it is not (nor is one with no corner at all).
void boxVolume(FogVolume& volume) {
  constexpr double kFar = 1e9;
  if (volume.planes.size() > kMaxBoxedFogPlanes) return;
  std::vector<glm::dvec4> planes(volume.planes.begin(), volume.planes.end());
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      glm::dvec4 p(0.0);
      p[axis] = sign;
      p.w = kFar;
      planes.push_back(p);
    }
  glm::dvec3 lo(kFar), hi(-kFar);
  bool any = false;
  const size_t n = planes.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        const glm::dvec3 a(planes[i]), b(planes[j]), c(planes[k]);
        const glm::dvec3 bc = glm::cross(b, c);
        const double det = glm::dot(a, bc);
        if (!(std::fabs(det) > 1e-9)) continue;   // two of them (nearly) parallel: no single corner
        const glm::dvec3 corner = (planes[i].w * bc + planes[j].w * glm::cross(c, a) + planes[k].w * glm::cross(a, b)) / det;
        const double slack = 1e-6 * (1.0 + glm::length(corner));
        if (!std::all_of(planes.begin(), planes.end(),
                         [&](const glm::dvec4& p) { return glm::dot(glm::dvec3(p), corner) - p.w <= slack; }))
          continue;
        lo = glm::min(lo, corner);
        hi = glm::max(hi, corner);
        any = true;
      }
  const glm::dvec3 far = glm::max(glm::abs(lo), glm::abs(hi));
  if (!any || glm::any(glm::greaterThanEqual(far, glm::dvec3(0.5 * kFar)))) return;
  // Wider than fogInterval's float rounding can reach past the planes (a few float steps of the
  // coordinates and distances involved): a segment outside it crosses none of the volume.
  const double margin = 1e-3 * (1.0 + std::max({far.x, far.y, far.z}));
  volume.boxMin = glm::vec3(lo - margin);
  volume.boxMax = glm::vec3(hi + margin);
  volume.boxed = true;
}

/// True when the segment from a to b (its box) lies wholly outside the volume's box.
bool passesWideOf(const FogVolume& volume, const glm::vec3& a, const glm::vec3& b) {
  return glm::any(glm::lessThan(glm::max(a, b), volume.boxMin)) || glm::any(glm::greaterThan(glm::min(a, b), volume.boxMax));
}

}  // namespace

FogVolume makeFogVolume(const FogVolumeDesc& desc, const std::string& what) {
  if (desc.planes.empty()) throw SceneError(what + ": no planes");
  if (desc.planes.size() > kMaxFogPlanes)
    throw SceneError(what + ": " + std::to_string(desc.planes.size()) + " planes (at most " +
                     std::to_string(kMaxFogPlanes) + ")");
  if (!finite(desc.color) || desc.color.r < 0.0f || desc.color.g < 0.0f || desc.color.b < 0.0f)
    throw SceneError(what + ": color must be finite and >= 0");
  if (!std::isfinite(desc.depthForOpaque) || !(desc.depthForOpaque > 0.0f))
    throw SceneError(what + ": depthForOpaque must be finite and > 0");
  FogVolume volume;
  volume.color = desc.color;
  volume.depthForOpaque = desc.depthForOpaque;
  volume.planes.reserve(desc.planes.size());
  for (size_t i = 0; i < desc.planes.size(); ++i) {
    const glm::vec4& p = desc.planes[i];
    const glm::vec3 n(p);
    if (!finite(n) || !std::isfinite(p.w)) throw SceneError(what + ": plane " + std::to_string(i) + " is not finite");
    const float length = glm::length(n);
    if (!(length > 1e-6f)) throw SceneError(what + ": plane " + std::to_string(i) + " has a zero normal");
    volume.planes.emplace_back(n / length, p.w / length);
  }
  boxVolume(volume);
  return volume;
}

float fogOpacity(float length, float depthForOpaque) {
  if (!(length > 0.0f) || !(depthForOpaque > 0.0f)) return 0.0f;
  const float x = std::clamp(length / depthForOpaque - kFogStart, 0.0f, 1.0f);
  return std::sqrt(x);
}

bool fogInterval(const FogVolume& volume, const glm::vec3& origin, const glm::vec3& dir, float tEnd, float& t0,
                 float& t1) {
  t0 = 0.0f;
  t1 = tEnd;
  for (const glm::vec4& plane : volume.planes) {
    const glm::vec3 n(plane);
    const float towardOutside = glm::dot(n, dir);
    const float clearance = plane.w - glm::dot(n, origin);   // >= 0: origin on the inner side
    if (std::fabs(towardOutside) < kParallel) {
      if (clearance < 0.0f) return false;
      continue;
    }
    const float t = clearance / towardOutside;
    if (towardOutside > 0.0f) t1 = std::min(t1, t);   // leaves through this plane
    else t0 = std::max(t0, t);                        // enters through it
    if (!(t0 < t1)) return false;
  }
  return t0 < t1;
}

// A volume that holds a finite end p = origin + tEnd dir has, for each of its planes, p inside
// (entering planes: p lies past their crossing; parallel ones: the origin is inside) or at most
// endSlack dot(n, dir) <= endSlack |dir| beyond it (leaving planes: their exit t + endSlack >=
// tEnd); fogInterval's rounding moves that by a few float steps of |w| + |origin| + |p|.
float fogEndAllowance(const glm::vec3& lo, const glm::vec3& hi, float maxT, float maxDir) {
  const glm::vec3 far = glm::max(glm::abs(lo), glm::abs(hi));
  const float end = far.x + far.y + far.z;   // bounds |end| (L1); |origin| <= |end| + tEnd |dir|
  return 2.0f * kEndSlack * std::max(1.0f, maxT) * maxDir + 1e-4f * (1.0f + 2.0f * end + maxT * maxDir);
}

bool fogMayHoldEndsIn(std::span<const FogVolume> volumes, const glm::vec3& lo, const glm::vec3& hi, float allowance) {
  const glm::vec3 centre = 0.5f * (lo + hi), half = 0.5f * (hi - lo);
  for (const FogVolume& volume : volumes) {
    bool ruledOut = false;
    for (const glm::vec4& plane : volume.planes) {
      const glm::vec3 n(plane);
      // The box's nearest point to the plane's inside, less a float step of the box for rounding.
      const float nearest = glm::dot(n, centre) - glm::dot(glm::abs(n), half) * 1.0001f;
      if (nearest - plane.w > allowance + 1e-4f * std::fabs(plane.w)) {
        ruledOut = true;
        break;
      }
    }
    if (!ruledOut) return true;
  }
  return false;
}

FogSegment::FogSegment(std::span<const FogVolume> volumes, const glm::vec3& origin, const glm::vec3& dir, float tEnd,
                       float lengthScale, bool endInsideOnly)
    : lengthScale_(lengthScale) {
  if (volumes.empty()) return;   // most maps: no fog, and no end point to work out per segment
  const bool endFinite = std::isfinite(tEnd);
  const float endSlack = endFinite ? kEndSlack * std::max(1.0f, tEnd) : 0.0f;   // hits on the boundary are inside
  const glm::vec3 end = origin + tEnd * dir;   // finite where endFinite (and the segment is)
  const bool boxable = endFinite && finite(end);
  for (const FogVolume& volume : volumes) {
    if (boxable && volume.boxed && passesWideOf(volume, origin, end)) continue;
    Crossing c;
    if (!fogInterval(volume, origin, dir, tEnd, c.t0, c.t1)) continue;
    const bool holdsEnd = endFinite ? c.t1 + endSlack >= tEnd : std::isinf(c.t1);
    if (endInsideOnly && !holdsEnd) continue;   // leaves the volume before the end
    c.volume = &volume;
    // Keep the nearest kCapacity crossings, sorted by entry.
    uint32_t at = count_;
    if (count_ == kCapacity) {
      if (c.t0 >= crossings_[kCapacity - 1].t0) continue;
      at = kCapacity - 1;
    } else {
      ++count_;
    }
    while (at > 0 && crossings_[at - 1].t0 > c.t0) {
      crossings_[at] = crossings_[at - 1];
      --at;
    }
    crossings_[at] = c;
  }
  for (uint32_t i = 0; i < count_; ++i) {
    const Crossing& c = crossings_[i];
    const float a = fogOpacity((c.t1 - c.t0) * lengthScale_, c.volume->depthForOpaque);   // infinite length: 1
    glow_ += transmittance_ * a * c.volume->color;
    transmittance_ *= 1.0f - a;
  }
}

float FogSegment::transmittanceTo(float t) const {
  float result = 1.0f;
  for (uint32_t i = 0; i < count_ && crossings_[i].t0 < t; ++i) {
    const Crossing& c = crossings_[i];
    result *= 1.0f - fogOpacity((std::min(t, c.t1) - c.t0) * lengthScale_, c.volume->depthForOpaque);
  }
  return result;
}

glm::vec3 FogSegment::layerColor() const {
  const float opacity = 1.0f - transmittance_;
  return opacity > 0.0f ? glow_ / opacity : glm::vec3(0.0f);
}

glm::vec3 blendInDisplaySpace(const glm::vec3& behind, float opacity, const glm::vec3& color) {
  const float a = std::clamp(opacity, 0.0f, 1.0f);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    const float back = linearToSrgb(std::clamp(behind[c], 0.0f, 1.0f));
    const float fog = linearToSrgb(std::clamp(color[c], 0.0f, 1.0f));
    out[c] = srgbToLinear((1.0f - a) * back + a * fog);
  }
  return out;
}

}  // namespace pa
