#pragma once
// sRGB decoding by table, inline: srgbToLinear at k / kSrgbTableSteps, linearly interpolated
// (largest difference from srgbToLinear over [0, 1] 4.8e-7, tested; one 8-bit display step is
// 3e-4 or more in linear values): a lookup per channel instead of a chain of about twenty
// dependent operations. Inline, scalar and one colour a call, because a lightmap sample decodes two
// colours: a call, AVX2 gathers stored to memory, or a pair of colours returned, went through
// memory that the caller read back across two stores (a store-forwarding stall per sample).
#include <array>
#include <cstddef>

#include <glm/vec3.hpp>

namespace pa {

/// Steps of the decode table over [0, 1].
inline constexpr int kSrgbTableSteps = 1024;
/// srgbToLinear(k / kSrgbTableSteps) for k = 0..kSrgbTableSteps (display_composite.cpp).
extern const std::array<float, kSrgbTableSteps + 1> kSrgbDecodeTable;

/// tableSrgbToLinear (display_composite.h) of each channel of a colour.
inline glm::vec3 decodeColour(const glm::vec3& c) {
  const auto one = [](float v) {
    v = v > 0.0f ? v : 0.0f;   // NaN becomes 0
    v = v < 1.0f ? v : 1.0f;
    const float s = v * float(kSrgbTableSteps);
    int i = static_cast<int>(s);
    i = i < kSrgbTableSteps - 1 ? i : kSrgbTableSteps - 1;
    const float f = s - static_cast<float>(i);
    const float lo = kSrgbDecodeTable[size_t(i)], hi = kSrgbDecodeTable[size_t(i) + 1];
    return lo + f * (hi - lo);
  };
  return {one(c.x), one(c.y), one(c.z)};
}

}  // namespace pa
