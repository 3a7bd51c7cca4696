#pragma once
// RGBA textures stored as 8 bits per channel (as their images have them: sRGB or linear bytes)
// with a box-filtered mip chain and trilinear sampling that returns linear values.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "renderer/core/srgb.h"   // srgbToLinear / linearToSrgb, used with textures
#include "renderer/scene/scene_types.h"

namespace pa {

/// Largest accepted texture side (guards against absurd sizes from hostile files).
inline constexpr uint32_t kMaxTextureSize = 16384;

/// One mip level: RGBA8 texels (byte 0 red .. byte 3 alpha), row-major from the top row.
struct MipLevel {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<std::array<uint8_t, 4>> texels;
};

/// An immutable texture ready for sampling. Texels keep the source's bytes at level 0 (a
/// quarter of the memory of float texels); lookups decode each texel through a 256-entry table
/// (srgbToLinear when the source is sRGB, byte / 255 otherwise) before filtering, so level-0
/// lookups equal those of float texels decoded at load. Coarser levels average the linear
/// values of the level above and keep the byte whose decoded value is nearest. RGB is linear,
/// alpha is linear coverage.
class Texture {
 public:
  /// Validates and converts a description; throws SceneError naming `what` on bad input.
  static Texture fromDesc(const TextureDesc& desc, const char* what);

  /// Trilinear lookup at mip level `lod` (0 = full resolution, fractional blends two levels).
  glm::vec4 sample(glm::vec2 uv, float lod) const;
  /// Bilinear lookup in the full-resolution level (alpha tests).
  glm::vec4 sampleFull(glm::vec2 uv) const;
  /// sample() of the stored values, byte / 255, filtered as stored (display values for an sRGB
  /// texture, blended as a raster engine's texture unit blends its 8-bit texels).
  glm::vec4 sampleStored(glm::vec2 uv, float lod) const;
  /// sampleFull() of the stored values (byte / 255, filtered as stored).
  glm::vec4 sampleFullStored(glm::vec2 uv) const;
  /// sample() with a texture unit's filtering. Level `lod` picks the levels as OpenGL does
  /// (nearest: level 0 up to 0.5, then the nearest); a texture without a mip chain is read
  /// bilinearly at level 0 whatever the filter, as stock filters images without mipmaps.
  /// Inline over sampleInto(): a vec4 returned from a call comes back in two halves, which a
  /// caller that multiplies it as one vector reassembles through memory (two narrow stores read
  /// by one wide load: a store-forwarding stall per lookup).
  glm::vec4 sample(glm::vec2 uv, float lod, TextureFilter filter) const;
  /// sample(uv, lod, filter) stored into `out` whole, from the register it was blended in.
  void sampleInto(glm::vec2 uv, float lod, TextureFilter filter, glm::vec4& out) const;
  /// sampleStored() with a texture unit's filtering (as sample(uv, lod, filter)).
  glm::vec4 sampleStored(glm::vec2 uv, float lod, TextureFilter filter) const;
  /// True when the colour channels are stored sRGB-encoded.
  bool srgb() const { return srgb_; }
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
  /// Texel (x, y) of a level, decoded to linear (tests).
  glm::vec4 texel(uint32_t level, uint32_t x, uint32_t y) const;

 private:
  /// uv as every level's lookup takes it: NaN or infinite -> 0, then wrapped into [0, 1]
  /// (repeat) or clamped to [-1, 2]; done once per lookup, for both levels of a trilinear one.
  glm::vec2 wrapped(glm::vec2 uv) const;
  /// Bilinear lookup in one level at a wrapped() uv.
  template <bool Stored>
  glm::vec4 sampleLevel(uint32_t level, glm::vec2 uv) const;
  template <bool Stored>
  glm::vec4 sampleAs(glm::vec2 uv, float lod) const;
  /// The texel a point at a wrapped() uv falls in, in one level.
  template <bool Stored>
  glm::vec4 nearestTexel(uint32_t level, glm::vec2 uv) const;
  template <bool Stored>
  glm::vec4 sampleFiltered(glm::vec2 uv, float lod, TextureFilter filter) const;
  glm::vec4 decode(const std::array<uint8_t, 4>& t) const;   ///< Linear values.
  static glm::vec4 stored(const std::array<uint8_t, 4>& t) {   ///< byte / 255.
    return glm::vec4(t[0], t[1], t[2], t[3]) * (1.0f / 255.0f);
  }

  std::vector<MipLevel> levels_;
  /// 512 entries: byte -> linear of the colour channels, then byte -> byte / 255 (alpha).
  const float* decode_ = nullptr;
  TextureWrap wrap_ = TextureWrap::Repeat;
  bool srgb_ = true;
  glm::vec4 average_{0.0f};
};

}  // namespace pa

#include "renderer/scene/textures/texture_lookup.h"   // the inline lookups
