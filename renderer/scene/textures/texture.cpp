#include "renderer/scene/textures/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <glm/glm.hpp>

namespace pa {

namespace {

MipLevel downsample(const MipLevel& src) {
  MipLevel dst;
  dst.width = std::max(1u, src.width / 2);
  dst.height = std::max(1u, src.height / 2);
  dst.texels.resize(size_t{dst.width} * dst.height);
  // Each destination texel averages the source texels it covers (2x2, or 2x1/1x2/3-wide
  // footprints on odd sizes are approximated by clamping to the last row/column).
  for (uint32_t y = 0; y < dst.height; ++y) {
    const uint32_t y0 = std::min(2 * y, src.height - 1);
    const uint32_t y1 = std::min(2 * y + 1, src.height - 1);
    for (uint32_t x = 0; x < dst.width; ++x) {
      const uint32_t x0 = std::min(2 * x, src.width - 1);
      const uint32_t x1 = std::min(2 * x + 1, src.width - 1);
      const glm::vec4 sum = src.texels[size_t{y0} * src.width + x0] + src.texels[size_t{y0} * src.width + x1] +
                            src.texels[size_t{y1} * src.width + x0] + src.texels[size_t{y1} * src.width + x1];
      dst.texels[size_t{y} * dst.width + x] = 0.25f * sum;
    }
  }
  return dst;
}

}  // namespace

Texture Texture::fromDesc(const TextureDesc& desc, const char* what) {
  const std::string name(what);
  if (desc.width == 0 || desc.height == 0) {
    throw SceneError(name + ": texture has zero size (" + std::to_string(desc.width) + "x" +
                     std::to_string(desc.height) + ")");
  }
  if (desc.width > kMaxTextureSize || desc.height > kMaxTextureSize) {
    throw SceneError(name + ": texture size " + std::to_string(desc.width) + "x" +
                     std::to_string(desc.height) + " exceeds " + std::to_string(kMaxTextureSize));
  }
  const size_t expected = size_t{desc.width} * desc.height * 4;
  if (desc.rgba8.size() != expected) {
    throw SceneError(name + ": rgba8 has " + std::to_string(desc.rgba8.size()) + " bytes, expected " +
                     std::to_string(expected) + " (width*height*4)");
  }
  std::array<float, 256> decode{};
  for (int i = 0; i < 256; ++i) {
    const float c = static_cast<float>(i) / 255.0f;
    decode[static_cast<size_t>(i)] = desc.srgb ? srgbToLinear(c) : c;
  }
  Texture tex;
  tex.wrap_ = desc.wrap;
  MipLevel base;
  base.width = desc.width;
  base.height = desc.height;
  base.texels.resize(size_t{desc.width} * desc.height);
  for (size_t i = 0; i < base.texels.size(); ++i) {
    const uint8_t* p = &desc.rgba8[i * 4];
    base.texels[i] = {decode[p[0]], decode[p[1]], decode[p[2]], static_cast<float>(p[3]) / 255.0f};
  }
  tex.levels_.push_back(std::move(base));
  // The chain is always built to 1x1 for average(); sampling ignores it when mipmaps are off.
  while (tex.levels_.back().width > 1 || tex.levels_.back().height > 1) {
    tex.levels_.push_back(downsample(tex.levels_.back()));
  }
  tex.average_ = tex.levels_.back().texels.front();
  if (!desc.mipmaps) tex.levels_.resize(1);
  if (!desc.mipmaps) {
    // Exact mean for non-mipmapped textures (the box chain above is exact only for powers of two).
    glm::dvec4 sum(0.0);
    for (const glm::vec4& t : tex.levels_.front().texels) sum += glm::dvec4(t);
    tex.average_ = glm::vec4(sum / static_cast<double>(tex.levels_.front().texels.size()));
  }
  return tex;
}

namespace {

/// The two texel indices along an axis of n texels that a bilinear lookup at integer i blends:
/// i and i + 1, wrapped (one division at most) or clamped to [0, n - 1].
std::array<uint32_t, 2> texelPair(int i, int n, bool repeat) {
  if (!repeat) return {uint32_t(std::clamp(i, 0, n - 1)), uint32_t(std::clamp(i + 1, 0, n - 1))};
  int first = i % n;
  if (first < 0) first += n;
  return {uint32_t(first), uint32_t(first + 1 == n ? 0 : first + 1)};
}

}  // namespace

glm::vec4 Texture::sampleLevel(uint32_t levelIndex, glm::vec2 uv) const {
  const MipLevel& level = levels_[std::min<size_t>(levelIndex, levels_.size() - 1)];
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = {0.0f, 0.0f};
  // Keep coordinates in a range where float -> int conversion is exact and safe.
  const bool repeat = wrap_ == TextureWrap::Repeat;
  if (repeat) {
    uv -= glm::floor(uv);
  } else {
    uv = glm::clamp(uv, glm::vec2(-1.0f), glm::vec2(2.0f));
  }
  const float px = uv.x * static_cast<float>(level.width) - 0.5f;
  const float py = uv.y * static_cast<float>(level.height) - 0.5f;
  const float fx0 = std::floor(px);
  const float fy0 = std::floor(py);
  const float fx = px - fx0;
  const float fy = py - fy0;
  const auto [x0, x1] = texelPair(static_cast<int>(fx0), static_cast<int>(level.width), repeat);
  const auto [y0, y1] = texelPair(static_cast<int>(fy0), static_cast<int>(level.height), repeat);
  const glm::vec4* row0 = &level.texels[size_t{y0} * level.width];
  const glm::vec4* row1 = &level.texels[size_t{y1} * level.width];
  const glm::vec4 a = row0[x0];
  const glm::vec4 b = row0[x1];
  const glm::vec4 c = row1[x0];
  const glm::vec4 d = row1[x1];
  return (a * (1.0f - fx) + b * fx) * (1.0f - fy) + (c * (1.0f - fx) + d * fx) * fy;
}

glm::vec4 Texture::sample(glm::vec2 uv, float lod) const {
  const float maxLevel = static_cast<float>(levels_.size() - 1);
  if (!(lod > 0.0f)) return sampleLevel(0, uv);
  if (lod >= maxLevel) return sampleLevel(static_cast<uint32_t>(maxLevel), uv);
  const float base = std::floor(lod);
  const float t = lod - base;
  const auto l = static_cast<uint32_t>(base);
  return glm::mix(sampleLevel(l, uv), sampleLevel(l + 1, uv), t);
}

}  // namespace pa
