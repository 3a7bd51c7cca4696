#include "renderer/scene/integrator/display_composite.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include <glm/common.hpp>

#include "renderer/scene/textures/texture.h"

namespace pa {
namespace {

// The sRGB curve without powf (9 calls per Lightmap sample took ~4% of a timedemo's time):
// eight channels at once (GCC/Clang vector extensions: one AVX2 register on x86-64-v3), x^p as
// exp2(p log2 x) with short series. log2 of the mantissa m in [sqrt(1/2), sqrt(2)) through
// atanh((m - 1) / (m + 1)) to s^9 (truncation < 4e-10); exp2 of the fraction in [-1/2, 1/2]
// by its Taylor series to degree 7 (truncation < 5e-9). Largest difference from
// linearToSrgb / srgbToLinear over [0, 1], measured on every 64th float there
// (display_composite_test): 1.2e-7 encoding, 1.8e-7 decoding (one or two float steps near 1).
using Lanes = float __attribute__((vector_size(32)));
using IntLanes = int32_t __attribute__((vector_size(32)));

Lanes clampUnit(Lanes x) {
  x = x > 0.0f ? x : 0.0f;   // NaN becomes 0
  return x < 1.0f ? x : 1.0f;
}

/// log2(x) for x > 0 (finite garbage, no trap, for x = 0: callers select those lanes away).
Lanes log2Lanes(Lanes x) {
  constexpr int32_t kSqrtHalfBits = 0x3f3504f3;   // bits of sqrt(1/2)
  // x = 2^e * m with m in [sqrt(1/2), sqrt(2)).
  const IntLanes offset = std::bit_cast<IntLanes>(x) - kSqrtHalfBits;
  const IntLanes exponent = offset >> 23;
  const Lanes m = std::bit_cast<Lanes>((offset & 0x007fffff) + kSqrtHalfBits);
  const Lanes s = (m - 1.0f) / (m + 1.0f);
  const Lanes s2 = s * s;
  const Lanes series = s * (1.0f + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9)))));
  return __builtin_convertvector(exponent, Lanes) + series * 2.8853900817779268f;   // 2 / ln 2
}

/// 2^y, y clamped to [-126, 127].
Lanes exp2Lanes(Lanes y) {
  y = y > -126.0f ? y : -126.0f;
  y = y < 127.0f ? y : 127.0f;
  constexpr float kRound = 12582912.0f;   // 1.5 * 2^23: adding and subtracting it rounds to an integer
  const Lanes whole = (y + kRound) - kRound;
  const Lanes f = (y - whole) * 0.69314718055994531f;   // ln 2: e^f with |f| <= ln 2 / 2
  const Lanes e = 1.0f + f * (1.0f + f * (1.0f / 2 + f * (1.0f / 6 + f * (1.0f / 24 + f * (1.0f / 120 +
                  f * (1.0f / 720 + f * (1.0f / 5040)))))));
  return e * std::bit_cast<Lanes>((__builtin_convertvector(whole, IntLanes) + 127) << 23);
}

/// linearToSrgb of each lane, clamped to [0, 1] first.
Lanes encodeLanes(Lanes c) {
  c = clampUnit(c);
  const Lanes curve = 1.055f * exp2Lanes(log2Lanes(c) * (1.0f / 2.4f)) - 0.055f;
  return c <= 0.0031308f ? c * 12.92f : curve;
}

/// srgbToLinear of each lane, clamped to [0, 1] first.
Lanes decodeLanes(Lanes c) {
  c = clampUnit(c);
  const Lanes curve = exp2Lanes(log2Lanes((c + 0.055f) * (1.0f / 1.055f)) * 2.4f);
  return c <= 0.04045f ? c * (1.0f / 12.92f) : curve;
}

glm::vec3 decode(const glm::vec3& display) {
  const Lanes d = decodeLanes(Lanes{display.x, display.y, display.z});
  return {d[0], d[1], d[2]};
}

}  // namespace

float fastLinearToSrgb(float c) { return encodeLanes(Lanes{c})[0]; }

float fastSrgbToLinear(float c) { return decodeLanes(Lanes{c})[0]; }

namespace {

/// Applies `curve` to each value in place, eight at a time (the last few through a padded register).
template <class Curve>
void applyLanes(std::span<float> values, Curve curve) {
  size_t at = 0;
  for (; at + 8 <= values.size(); at += 8) {
    Lanes v;
    std::memcpy(&v, values.data() + at, sizeof v);
    v = curve(v);
    std::memcpy(values.data() + at, &v, sizeof v);
  }
  if (at == values.size()) return;
  Lanes v{};
  std::memcpy(&v, values.data() + at, (values.size() - at) * sizeof(float));
  v = curve(v);
  std::memcpy(values.data() + at, &v, (values.size() - at) * sizeof(float));
}

}  // namespace

void fastLinearToSrgb(std::span<float> values) { applyLanes(values, encodeLanes); }

void fastSrgbToLinear(std::span<float> values) { applyLanes(values, decodeLanes); }

void encodeColors(std::span<const glm::vec4> linear, std::vector<glm::vec3>& display) {
  display.resize(linear.size());
  for (size_t i = 0; i < linear.size(); ++i) display[i] = glm::vec3(linear[i]);
  fastLinearToSrgb(std::span<float>(&display.data()->x, 3 * display.size()));   // three packed floats each
}

glm::vec3 fastSrgbToLinear(const glm::vec3& c) { return decode(c); }

glm::vec3 displayProduct(const glm::vec3& a, const glm::vec3& b) {
  const Lanes e = encodeLanes(Lanes{a.x, a.y, a.z, b.x, b.y, b.z});
  const Lanes d = decodeLanes(Lanes{e[0] * e[3], e[1] * e[4], e[2] * e[5]});
  return {d[0], d[1], d[2]};
}

glm::vec3 fastLinearToSrgb(const glm::vec3& c) {
  const Lanes d = encodeLanes(Lanes{c.x, c.y, c.z});
  return {d[0], d[1], d[2]};
}

glm::vec3 displayProductWithDisplay(const glm::vec3& a, const glm::vec3& bDisplay) {
  const Lanes e = encodeLanes(Lanes{a.x, a.y, a.z});
  const Lanes d = decodeLanes(Lanes{e[0] * bDisplay.x, e[1] * bDisplay.y, e[2] * bDisplay.z});
  return {d[0], d[1], d[2]};
}

std::pair<glm::vec3, glm::vec3> encodeTwo(const glm::vec3& a, const glm::vec3& b) {
  const Lanes e = encodeLanes(Lanes{a.x, a.y, a.z, b.x, b.y, b.z});
  return {{e[0], e[1], e[2]}, {e[3], e[4], e[5]}};
}

const std::array<float, kSrgbTableSteps + 1> kSrgbDecodeTable = [] {
  std::array<float, kSrgbTableSteps + 1> t{};
  for (int k = 0; k <= kSrgbTableSteps; ++k) t[size_t(k)] = srgbToLinear(double(k) / kSrgbTableSteps);
  return t;
}();

float tableSrgbToLinear(float c) { return decodeColour(glm::vec3(c)).x; }

glm::vec3 composeShine(const glm::vec3& base, const glm::vec4& shine, LayerBlend blend, float baseRedrawn) {
  const auto [dst, src] = encodeTwo(base, glm::vec3(shine));
  glm::vec3 out = dst;
  switch (blend) {
    case LayerBlend::Add: out = dst + src; break;
    case LayerBlend::Over: {
      const float a = std::clamp(shine.a, 0.0f, 1.0f);
      out = dst * (1.0f - a) + src * a;
      break;
    }
    case LayerBlend::Multiply: out = dst * src; break;
    case LayerBlend::MultiplyInverse: out = dst * (1.0f - src); break;
    case LayerBlend::MultiplyAdd: out = dst * (1.0f + src); break;
    case LayerBlend::Modulate2x: out = 2.0f * dst * src; break;
    case LayerBlend::Factors: out = dst; break;   // not a shine blend: the scene store refuses it
  }
  out = glm::clamp(out, 0.0f, 1.0f);
  return decode(glm::mix(out, dst, std::clamp(baseRedrawn, 0.0f, 1.0f)));
}

void DisplayComposite::appendBefore(const AdditiveHits& hits, float t) {
  if (hits.count == 0) return;
  // A query leaves its entries in drawing order (AdditiveHits::entries): nearest first.
  const uint32_t first = count_;
  for (uint32_t i = 0; i < std::min(hits.count, AdditiveHits::kCapacity) && count_ < kCapacity; ++i) {
    const AdditiveHits::Entry& e = hits.entries[i];
    if (e.t < t) layers_[count_++] = {e.color, e.transmit};
  }
  if (hits.displayValues) return;
  for (uint32_t i = first; i < count_; i += 2) {   // linear colours (the traced presets' hits) encoded, two a call
    const bool pair = i + 1 < count_;
    const auto [a, b] = encodeTwo(layers_[i].color, pair ? layers_[i + 1].color : glm::vec3(0.0f));
    layers_[i].color = a;
    if (pair) layers_[i + 1].color = b;
  }
}

void DisplayComposite::append(const Layer& layer) {
  if (count_ < kCapacity) layers_[count_++] = {encodeTwo(layer.color, glm::vec3(0.0f)).first, layer.transmit};
}

glm::vec3 DisplayComposite::over(const glm::vec3& behind) const {
  if (count_ == 0) return behind;
  return overDisplay(encodeTwo(behind, glm::vec3(0.0f)).first);
}

glm::vec3 DisplayComposite::overDisplay(const glm::vec3& behind) const {
  glm::vec3 display = behind;
  for (uint32_t i = count_; i-- > 0;) {
    const Stored& layer = layers_[i];
    display = glm::clamp(display * glm::max(layer.transmit, glm::vec3(0.0f)) + layer.color, 0.0f, 1.0f);
  }
  return decode(display);
}

}  // namespace pa
