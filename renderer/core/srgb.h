#pragma once
// The sRGB transfer curves (IEC 61966-2-1), exact (std::pow), for float or double: encoded
// display value <-> linear. For tables, per-material and per-vertex conversions; the per-pixel
// paths use their own tabulated / polynomial versions (texture decode table, display_composite).
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pa {

/// Encoded value -> linear. The curve continues past 1 (light values that multiply beyond
/// white); values <= 0.04045, negative ones included, take the linear segment.
template <typename T>
inline T srgbToLinear(T c) {
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

/// Encoded value clamped to [0, 1], then decoded.
template <typename T>
inline T srgbToLinearClamped(T c) {
  return srgbToLinear(std::clamp(c, T(0), T(1)));
}

/// An 8-bit encoded channel -> linear.
inline float srgbByteToLinear(uint8_t byte) { return srgbToLinear(float(byte) / 255.0f); }

/// Linear -> encoded value (the curve continues past 1; values <= 0.0031308 are scaled).
template <typename T>
inline T linearToSrgb(T c) {
  return c <= T(0.0031308) ? c * T(12.92) : T(1.055) * std::pow(c, T(1) / T(2.4)) - T(0.055);
}

}  // namespace pa
