#pragma once
// The denoiser's edge-stopping weight, scalar and for taau::lanes (kCount pixels of a row at a
// time). Both forms run the same IEEE operations in the same order, so a lane's value is the
// scalar function's bit for bit (tests/weight_lanes_test.cpp).
#include <bit>
#include <cmath>
#include <cstdint>

#include "renderer/scene/taau/lanes.h"

namespace pa::denoise {

/// Weight exponents are clamped here (e^-80 ~ 2e-35: nothing); NaN exponents land here too.
inline constexpr float kMinExponent = -80.0f;

/// negativeExp(kMinExponent): the value of the polynomial below at that point with each operation
/// rounded on its own (as the compiler folds the constant), 1 ulp below what fused multiply-adds
/// give there; both forms return it for every exponent at or below kMinExponent.
inline constexpr float kMinExponentWeight = 0x1.7fd9p-116f;

/// e^x for x <= 0 without branches: 2^(x log2 e) from an exponent-bit shift and a degree-5
/// polynomial of the fraction (relative error below 1e-5). Exponents at or below kMinExponent,
/// and NaN, give kMinExponentWeight; positive ones count as 0.
inline float negativeExp(float x) {
  const bool least = !(x > kMinExponent);
  x = x > kMinExponent ? x : kMinExponent;
  x = x < 0.0f ? x : 0.0f;
  const float t = x * 1.44269504f;
  const float whole = std::floor(t);
  const float f = t - whole;   // [0, 1)
  const float p =
      1.0f + f * (0.69314718f + f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
  return least ? kMinExponentWeight : std::bit_cast<float>(std::bit_cast<int32_t>(p) + (static_cast<int32_t>(whole) << 23));
}

namespace lanes = taau::lanes;

/// Per lane, negativeExp(x) (the same bits).
inline lanes::F negativeExp(lanes::F x) {
  const lanes::I above = x > kMinExponent;
  x = lanes::select(above, x, lanes::splat(kMinExponent));
  x = lanes::select(x < 0.0f, x, lanes::splat(0.0f));
  const lanes::F t = x * 1.44269504f;
  const lanes::I whole = lanes::floorToInt(t);   // t in [-116, 0]
  const lanes::F f = t - lanes::toFloat(whole);
  const lanes::F p =
      1.0f + f * (0.69314718f + f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
  return lanes::select(above, std::bit_cast<lanes::F>(std::bit_cast<lanes::I>(p) + (whole << 23)),
                       lanes::splat(kMinExponentWeight));
}

/// Per lane, |v| as std::abs gives it (the sign bit cleared, also of -0 and NaN).
inline lanes::F absolute(lanes::F v) {
  return std::bit_cast<lanes::F>(std::bit_cast<lanes::I>(v) & lanes::splat(int32_t{0x7fffffff}));
}
/// Per lane, std::max(a, b): b where a < b, else a (a where either is NaN).
inline lanes::F maxOf(lanes::F a, lanes::F b) { return lanes::select(a < b, b, a); }

/// Rec. 709 luminance of linear RGB.
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
/// Per lane, luminance(r, g, b).
inline lanes::F luminance(lanes::F r, lanes::F g, lanes::F b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace pa::denoise
