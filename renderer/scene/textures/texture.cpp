#include "renderer/scene/textures/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <glm/glm.hpp>

namespace pa {

namespace {

/// Linear RGBA texels of one level while the chain is built.
struct LinearLevel {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<glm::vec4> texels;
};

LinearLevel downsample(const LinearLevel& src) {
  LinearLevel dst;
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

/// Texture::decode_'s table: 256 colour entries (srgbToLinear(byte / 255) for sRGB, byte / 255
/// for linear data), then 256 alpha entries (byte / 255).
const std::array<float, 512>& decodeTable(bool srgb) {
  static const auto tables = [] {
    std::array<std::array<float, 512>, 2> t{};
    for (int i = 0; i < 256; ++i) {
      const float c = static_cast<float>(i) / 255.0f;
      for (auto& table : t) table[size_t(256 + i)] = c;
      t[0][size_t(i)] = c;
      t[1][size_t(i)] = srgbToLinear(c);
    }
    return t;
  }();
  return tables[srgb ? 1 : 0];
}

/// The byte whose entry in an increasing 256-entry decode table is nearest to v (the lower one
/// on a tie), by binary search.
uint8_t searchNearestByte(const float* table, float v) {
  const float* above = std::lower_bound(table, table + 256, v);
  if (above == table) return 0;
  if (above == table + 256) return 255;
  const float* below = above - 1;
  return static_cast<uint8_t>((v - *below <= *above - v ? below : above) - table);
}

/// searchNearestByte for one decode table without a search per value: the nearest byte at the
/// start of each of kBuckets buckets of [0, 1], then steps up past the midpoints below v (at
/// most a step or two: sRGB bytes lie at least 3e-4 apart in linear values, a bucket is 2.4e-4).
class NearestByte {
 public:
  explicit NearestByte(const float* table) {
    for (size_t b = 0; b < 255; ++b) mid_[b] = table[b] + 0.5f * (table[b + 1] - table[b]);
    for (uint32_t k = 0; k < kBuckets; ++k)
      start_[k] = searchNearestByte(table, static_cast<float>(k) / static_cast<float>(kBuckets));
  }
  uint8_t operator()(float v) const {
    if (!(v > 0.0f)) return 0;   // NaN too
    if (v >= 1.0f) return 255;
    uint32_t b = start_[std::min(static_cast<uint32_t>(v * float(kBuckets)), kBuckets - 1)];
    while (b < 255 && v > mid_[b]) ++b;
    return static_cast<uint8_t>(b);
  }

 private:
  static constexpr uint32_t kBuckets = 4096;
  std::array<float, 255> mid_;
  std::array<uint8_t, kBuckets> start_;
};

/// NearestByte of the colour half (sRGB or linear) and of the alpha half of decodeTable(srgb).
const std::array<NearestByte, 2>& nearestBytes(bool srgb) {
  static const std::array<std::array<NearestByte, 2>, 2> finders{
      std::array<NearestByte, 2>{NearestByte(decodeTable(false).data()), NearestByte(decodeTable(false).data() + 256)},
      std::array<NearestByte, 2>{NearestByte(decodeTable(true).data()), NearestByte(decodeTable(true).data() + 256)}};
  return finders[srgb ? 1 : 0];
}

MipLevel quantize(const LinearLevel& linear, const std::array<NearestByte, 2>& nearest) {
  MipLevel level;
  level.width = linear.width;
  level.height = linear.height;
  level.texels.resize(linear.texels.size());
  const NearestByte& rgb = nearest[0];
  const NearestByte& alpha = nearest[1];
  for (size_t i = 0; i < linear.texels.size(); ++i) {
    const glm::vec4& t = linear.texels[i];
    level.texels[i] = {rgb(t.r), rgb(t.g), rgb(t.b), alpha(t.a)};
  }
  return level;
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
  Texture tex;
  tex.wrap_ = desc.wrap;
  tex.srgb_ = desc.srgb;
  tex.decode_ = decodeTable(desc.srgb).data();
  MipLevel base;
  base.width = desc.width;
  base.height = desc.height;
  base.texels.resize(size_t{desc.width} * desc.height);
  for (size_t i = 0; i < base.texels.size(); ++i) {
    const uint8_t* p = &desc.rgba8[i * 4];
    base.texels[i] = {p[0], p[1], p[2], p[3]};
  }
  LinearLevel linear;
  linear.width = desc.width;
  linear.height = desc.height;
  linear.texels.resize(base.texels.size());
  for (size_t i = 0; i < base.texels.size(); ++i) linear.texels[i] = tex.decode(base.texels[i]);
  tex.levels_.push_back(std::move(base));
  if (!desc.mipmaps) {
    // Exact mean for non-mipmapped textures (the box chain is exact only for powers of two).
    glm::dvec4 sum(0.0);
    for (const glm::vec4& t : linear.texels) sum += glm::dvec4(t);
    tex.average_ = glm::vec4(sum / static_cast<double>(linear.texels.size()));
    return tex;
  }
  // The chain goes down to 1x1; its last level, before rounding to bytes, is average().
  const std::array<NearestByte, 2>& nearest = nearestBytes(desc.srgb);
  while (linear.width > 1 || linear.height > 1) {
    linear = downsample(linear);
    tex.levels_.push_back(quantize(linear, nearest));
  }
  tex.average_ = linear.texels.front();
  return tex;
}

glm::vec4 Texture::decode(const std::array<uint8_t, 4>& t) const {
  // Four loads, not an AVX2 gather: on the Xeon of docs/performance.md the gather held this
  // function at 4% of a lightmap frame on wrackdm17; the loads do not wait on one another.
  return {decode_[t[0]], decode_[t[1]], decode_[t[2]], decode_[256 + t[3]]};
}

glm::vec4 Texture::texel(uint32_t levelIndex, uint32_t x, uint32_t y) const {
  const MipLevel& level = levels_.at(levelIndex);
  return decode(level.texels.at(size_t{std::min(y, level.height - 1)} * level.width + std::min(x, level.width - 1)));
}

namespace {

/// The two levels around level of detail `lod` blended (trilinear), each read by `read(level)`:
/// level 0 up to lod 0, the last level from `maxLevel` on.
template <class Read>
glm::vec4 blendLevels(const Read& read, float lod, float maxLevel) {
  if (!(lod > 0.0f)) return read(0);
  if (lod >= maxLevel) return read(static_cast<uint32_t>(maxLevel));
  const float base = std::floor(lod);
  const auto l = static_cast<uint32_t>(base);
  return glm::mix(read(l), read(l + 1), lod - base);
}

}  // namespace

template <bool Stored>
glm::vec4 Texture::sampleAs(glm::vec2 uv, float lod) const {
  const glm::vec2 at = wrapped(uv);
  return blendLevels([&](uint32_t level) { return sampleLevel<Stored>(level, at); }, lod,
                     static_cast<float>(levels_.size() - 1));
}

template <bool Stored>
glm::vec4 Texture::nearestTexel(uint32_t levelIndex, glm::vec2 uv) const {
  const MipLevel& level = levels_[std::min<size_t>(levelIndex, levels_.size() - 1)];
  const auto index = [repeat = wrap_ == TextureWrap::Repeat](float coordinate, uint32_t n) {
    const int i = static_cast<int>(std::floor(coordinate * static_cast<float>(n)));
    const int last = static_cast<int>(n) - 1;
    if (!repeat) return static_cast<uint32_t>(std::clamp(i, 0, last));
    return static_cast<uint32_t>(i > last ? i - static_cast<int>(n) : (i < 0 ? i + static_cast<int>(n) : i));
  };
  const std::array<uint8_t, 4>& t = level.texels[size_t{index(uv.y, level.height)} * level.width + index(uv.x, level.width)];
  return Stored ? stored(t) : decode(t);
}

template <bool Stored>
glm::vec4 Texture::sampleFiltered(glm::vec2 uv, float lod, TextureFilter filter) const {
  if (levels_.size() == 1) return sampleLevel<Stored>(0, wrapped(uv));   // no mip chain: bilinear
  if (filter.mips == MipFilter::Linear && !filter.nearestTexels) return sampleAs<Stored>(uv, lod);
  const glm::vec2 at = wrapped(uv);
  const auto read = [&](uint32_t level) {
    return filter.nearestTexels ? nearestTexel<Stored>(level, at) : sampleLevel<Stored>(level, at);
  };
  const float maxLevel = static_cast<float>(levels_.size() - 1);
  switch (filter.mips) {
    case MipFilter::None: return read(0);
    case MipFilter::Nearest:
      // OpenGL: level 0 up to a level of detail of 0.5, then ceil(lod + 0.5) - 1 (the nearest).
      if (!(lod > 0.5f)) return read(0);
      return read(static_cast<uint32_t>(std::ceil(std::min(lod, maxLevel) + 0.5f)) - 1u);
    case MipFilter::Linear: break;
  }
  return blendLevels(read, lod, maxLevel);
}

// Flattened: the lookup's whole call tree inlined here, so that the result is stored from the
// register it was blended in.
[[gnu::flatten]] void Texture::sampleInto(glm::vec2 uv, float lod, TextureFilter filter, glm::vec4& out) const {
  out = sampleFiltered<false>(uv, lod, filter);
}

glm::vec4 Texture::sampleStored(glm::vec2 uv, float lod, TextureFilter filter) const {
  return sampleFiltered<true>(uv, lod, filter);
}

glm::vec4 Texture::sample(glm::vec2 uv, float lod) const { return sampleAs<false>(uv, lod); }

glm::vec4 Texture::sampleStored(glm::vec2 uv, float lod) const { return sampleAs<true>(uv, lod); }

}  // namespace pa
