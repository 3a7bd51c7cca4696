#pragma once
// Fog volumes (scene_types.h FogVolumeDesc): convex regions of a homogeneous medium that hides
// what lies behind it and glows with its colour. A ray segment running a length L inside a
// volume gets the opacity a(L) = sqrt(clamp(L / depthForOpaque - 1/64, 0, 1)), the curve of
// Quake III's fog table (its fog image starts half a texel in, hence the 1/64). Seen as a
// medium, that is an optical depth -ln(1 - a(L)) per segment: radiance arriving through the
// segment is (1 - a) * behind + a * color.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/scene/scene_types.h"

namespace pa {

/// A validated fog volume: unit outward plane normals (inside where dot(n, p) <= w).
struct FogVolume {
  std::vector<glm::vec4> planes;
  glm::vec3 color{0.0f};
  float depthForOpaque = 1.0f;
  /// A box holding the volume with a margin past fogInterval's rounding, when it is bounded and
  /// has at most kMaxBoxedFogPlanes planes (else `boxed` is false): FogSegment skips the volume
  /// for a finite segment whose own box lies outside it, without clipping it plane by plane.
  bool boxed = false;
  glm::vec3 boxMin{0.0f}, boxMax{0.0f};
};

/// Most planes one volume may have (Quake brushes have 6 to a few dozen sides).
inline constexpr size_t kMaxFogPlanes = 256;
/// Most fog volumes one scene may have (a BSP's fog lump is capped at 256 by the engine).
inline constexpr size_t kMaxFogVolumes = 1024;
/// Most planes of a volume whose box makeFogVolume works out (its corners, three planes at a time;
/// Quake fog brushes have 6 to about 20 sides).
inline constexpr size_t kMaxBoxedFogPlanes = 32;

/// Validates a description (finite numbers, non-zero normals, 1..kMaxFogPlanes planes,
/// depthForOpaque > 0, colour >= 0), normalises its planes and works out its box (FogVolume::boxed);
/// throws SceneError naming `what`.
FogVolume makeFogVolume(const FogVolumeDesc& desc, const std::string& what);

/// Opacity of a segment of length `length` inside a fog of the given distance to opaque.
float fogOpacity(float length, float depthForOpaque);

/// The part [t0, t1] of origin + t * dir, t in [0, tEnd], inside the volume (dir need not be
/// unit: t is in its units). False when the ray misses it or only grazes it.
bool fogInterval(const FogVolume& volume, const glm::vec3& origin, const glm::vec3& dir, float tEnd, float& t0,
                 float& t1);

/// How far beyond one of its volume's planes the finite end of a segment origin + t dir, t in
/// [0, tEnd], may lie while FogSegment's endInsideOnly still counts that volume as holding it,
/// for every segment that ends in the box [lo, hi] with tEnd <= maxT and |dir| (L1) <= maxDir:
/// the end slack (at most 1e-4 max(1, tEnd) |dir|) twice over, plus 1e-4 of |origin| + |end|
/// (L1) for fogInterval's rounding (hundreds of times it).
float fogEndAllowance(const glm::vec3& lo, const glm::vec3& hi, float maxT, float maxDir);

/// False when no volume can hold any segment end in the box [lo, hi] whose fogEndAllowance is
/// at most `allowance` (as FogSegment's endInsideOnly counts it): each volume has a plane the
/// whole box lies beyond by more than that (+ 1e-4 of the plane's distance). Then FogSegment
/// of each such segment with endInsideOnly is empty; true says nothing. One test per plane up to
/// the first that rules a volume out, for a packet of segments at once.
bool fogMayHoldEndsIn(std::span<const FogVolume> volumes, const glm::vec3& lo, const glm::vec3& hi, float allowance);

/// The stock renderer's fog blend, done on display (sRGB-encoded) values as its framebuffer
/// blend does: lin((1 - opacity) * srgb(min(behind, 1)) + opacity * srgb(min(color, 1))).
/// The Lightmap integrator composites camera-ray fog this way.
glm::vec3 blendInDisplaySpace(const glm::vec3& behind, float opacity, const glm::vec3& color);

/// The fog volumes one ray segment crosses, nearest entry first, with what they do to the
/// light coming along the segment toward its origin.
class FogSegment {
 public:
  /// Volumes beyond kCapacity along one segment are ignored (the nearest are kept).
  static constexpr uint32_t kCapacity = 8;

  /// A segment through no fog (transmittance 1, no glow). User-provided, so that `FogSegment()`
  /// leaves the unused crossings unset instead of zeroing them for every camera ray.
  FogSegment() {}
  /// Clips origin + t * dir, t in [0, tEnd] (tEnd may be infinite) against every volume.
  /// `lengthScale` multiplies the distances inside (|dir| for non-unit directions; the
  /// Lightmap integrator's camera rays also fold in the eye-space depth factor).
  /// endInsideOnly: only volumes that hold the segment's end count (the stock renderer fogs
  /// only surfaces inside a fog brush; an infinite end is inside none).
  FogSegment(std::span<const FogVolume> volumes, const glm::vec3& origin, const glm::vec3& dir, float tEnd,
             float lengthScale, bool endInsideOnly = false);

  /// True when the segment touches no fog.
  bool empty() const { return count_ == 0; }
  /// Fraction of the light from the segment's end that reaches its origin.
  float transmittance() const { return transmittance_; }
  /// Fraction of light from the point at parameter t that reaches the origin.
  float transmittanceTo(float t) const;
  /// Radiance the fog adds along the whole segment (its glow, attenuated by nearer fog).
  glm::vec3 glow() const { return glow_; }
  /// The segment's fog as one layer: opacity 1 - transmittance() of colour glow() / opacity.
  glm::vec3 layerColor() const;

 private:
  struct Crossing {
    float t0;
    float t1;
    const FogVolume* volume;
  };
  std::array<Crossing, kCapacity> crossings_;   ///< First count_ are set (no fill per ray segment).
  uint32_t count_ = 0;
  float lengthScale_ = 1.0f;
  float transmittance_ = 1.0f;
  glm::vec3 glow_{0.0f};
};

}  // namespace pa
