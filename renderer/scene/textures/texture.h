#pragma once
// Linear float RGBA textures with a box-filtered mip chain and trilinear sampling.
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "renderer/core/srgb.h"   // srgbToLinear / linearToSrgb, used with textures
#include "renderer/scene/scene_types.h"

namespace pa {

/// Largest accepted texture side (guards against absurd sizes from hostile files).
inline constexpr uint32_t kMaxTextureSize = 16384;

/// One mip level: linear RGBA texels, row-major from the top row.
struct MipLevel {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<glm::vec4> texels;
};

/// An immutable texture ready for sampling. RGB is linear (sRGB decoded when the source
/// is sRGB), alpha is linear coverage.
class Texture {
 public:
  /// Validates and converts a description; throws SceneError naming `what` on bad input.
  static Texture fromDesc(const TextureDesc& desc, const char* what);

  /// Trilinear lookup at mip level `lod` (0 = full resolution, fractional blends two levels).
  glm::vec4 sample(glm::vec2 uv, float lod) const;
  /// Bilinear lookup in the full-resolution level (alpha tests).
  glm::vec4 sampleFull(glm::vec2 uv) const { return sampleLevel(0, uv); }
  /// Mean of all texels (the 1x1 level).
  glm::vec4 average() const { return average_; }
  /// Width of level 0.
  uint32_t width() const { return levels_.front().width; }
  /// Height of level 0.
  uint32_t height() const { return levels_.front().height; }
  /// Number of mip levels (1 when mipmaps are off).
  uint32_t levelCount() const { return static_cast<uint32_t>(levels_.size()); }
  /// Read access to a level (tests).
  const MipLevel& level(uint32_t i) const { return levels_[i]; }

 private:
  glm::vec4 sampleLevel(uint32_t level, glm::vec2 uv) const;

  std::vector<MipLevel> levels_;
  TextureWrap wrap_ = TextureWrap::Repeat;
  glm::vec4 average_{0.0f};
};


}  // namespace pa
