#pragma once
// sRGB decoding by table, inline: srgbToLinear at k / kSrgbTableSteps, linearly interpolated
// (largest difference from srgbToLinear over [0, 1] 4.8e-7, tested; one 8-bit display step is
// 3e-4 or more in linear values): six independent lookups instead of a chain of about twenty
// dependent operations. Inline and scalar because a lightmap sample decodes two colours once: a
// call, or AVX2 gathers stored to memory, returned them through memory that the caller read back
// narrower (a store-forwarding stall per sample; the gathers cost 2-5% of a lightmap frame's CPU).
#include <array>
#include <cstddef>
#include <utility>

#include <glm/vec3.hpp>

namespace pa {

/// Steps of the decode table over [0, 1].
inline constexpr int kSrgbTableSteps = 1024;
/// srgbToLinear(k / kSrgbTableSteps) for k = 0..kSrgbTableSteps (display_composite.cpp).
extern const std::array<float, kSrgbTableSteps + 1> kSrgbDecodeTable;

/// tableSrgbToLinear (display_composite.h) of each channel of two colours, in one pass.
inline std::pair<glm::vec3, glm::vec3> decodeTwo(const glm::vec3& a, const glm::vec3& b) {
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
  return {{one(a.x), one(a.y), one(a.z)}, {one(b.x), one(b.y), one(b.z)}};
}

}  // namespace pa
