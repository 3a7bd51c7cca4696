#pragma once
// MD3 models ("IDP3" version 15): frames, tags and vertex-animated surfaces.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace q3 {

/// Three floats (positions, normals, axes) of the model formats.
using Md3Vec3 = std::array<float, 3>;

/// Limits checked on load. They are the format's MD3_MAX_* (qfiles.h) except vertices: the format
/// says 1024 per surface (and ioquake3's renderer refuses >= 1000), but map models compiled
/// into BSPs by q3map2 have more (OpenArena ships surfaces of 1210 and 1599 vertices), so
/// up to `maxVerts` are accepted; `formatMaxVerts` tells a caller what the engine would load.
struct Md3Limits {
  static constexpr int version = 15;
  static constexpr int maxLods = 3;
  static constexpr int maxTriangles = 8192;
  static constexpr int formatMaxVerts = 1024;
  static constexpr int maxVerts = 8192;
  static constexpr int maxShaders = 256;
  static constexpr int maxFrames = 1024;
  static constexpr int maxSurfaces = 32;
  static constexpr int maxTags = 16;
  static constexpr float xyzScale = 1.0f / 64.0f;  ///< stored positions are shorts in 1/64 units
};

/// One animation frame's bounds.
struct Md3Frame {
  Md3Vec3 mins{}, maxs{};
  Md3Vec3 localOrigin{};
  float radius = 0;
  std::string name;
};

/// An attachment point (e.g. tag_weapon) in one frame.
struct Md3Tag {
  std::string name;
  Md3Vec3 origin{};
  std::array<Md3Vec3, 3> axis{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

/// A surface's shader reference.
struct Md3Shader {
  std::string name;
  int index = 0;  ///< renderer-side index in the file (unused on load)
};

/// A triangle mesh with one position/normal set per frame.
struct Md3Surface {
  std::string name;
  int flags = 0;
  int numVerts = 0;
  std::vector<Md3Shader> shaders;
  std::vector<std::array<uint32_t, 3>> triangles;  ///< indices < numVerts (checked)
  std::vector<std::array<float, 2>> texCoords;     ///< numVerts
  std::vector<Md3Vec3> positions;                  ///< numFrames * numVerts, frame-major
  std::vector<Md3Vec3> normals;                    ///< numFrames * numVerts, unit length
};

/// A whole MD3 file.
struct Md3Model {
  std::string name;
  int flags = 0;
  std::vector<Md3Frame> frames;
  int numTags = 0;
  std::vector<Md3Tag> tags;  ///< frames.size() * numTags, frame-major
  std::vector<Md3Surface> surfaces;

  /// Tag `tagIndex` of `frame` (both must be in range).
  const Md3Tag& tag(size_t frame, size_t tagIndex) const { return tags[frame * static_cast<size_t>(numTags) + tagIndex]; }
};

/// Parses an MD3 file; every count and offset is checked against the buffer and Md3Limits.
/// Throws FormatError naming `name` and the field on malformed input.
Md3Model parseMd3(std::span<const std::byte> bytes, const std::string& name);

/// Decodes a packed MD3 normal: high byte latitude, low byte longitude, 360/256 degree steps.
Md3Vec3 decodeMd3Normal(uint16_t packed);

/// Vertices of a surface between two frames, as the engine does it:
/// position = frame * (1 - backlerp) + oldFrame * backlerp; normals lerped and renormalised.
/// A frame number out of range is replaced by 0 (as the engine does, with a warning).
void lerpSurface(const Md3Surface& surface, size_t numFrames, int frame, int oldFrame, float backlerp,
                 std::vector<Md3Vec3>& positions, std::vector<Md3Vec3>& normals);

/// An interpolated tag (like the renderer's LerpTag): origin lerped, axes lerped and normalised,
/// `fraction` 0 = startFrame, 1 = endFrame; frames are clamped to the last one. nullopt if the
/// model has no tag of that name.
std::optional<Md3Tag> lerpTag(const Md3Model& model, int startFrame, int endFrame, float fraction,
                              std::string_view tagName);

/// File name of a level of detail: lod 0 is `name`; lod n is "<name without .md3>_n.md3".
std::string md3LodName(std::string_view name, int lod);

}  // namespace q3
