#pragma once
// Quake III light semantics (q3map2, the compiler that baked OpenArena's lightmaps) and their
// conversion to physical units for the path tracer, chosen so that the path-traced Direct/Path
// images have the brightness of the lightmapped one at exposure 1.
//
// q3map2 accumulates "light values" per lightmap texel (point light: photons / d^2 * cos,
// photons = light * 7500, d clamped to >= 16; linear light: cos * light * 7500 / 8000 - d;
// sun: intensity * cos; surface light: value * 3 * 0.25 * F, F the point-to-polygon form
// factor of the emitting surface) and stores them as bytes. The engine multiplies lightmap bytes by 2^r_mapOverBrightBits = 4, so a light value
// of 64 shows a texture unmodified ("full bright", kQ3FullBright).
// Our renderer: a Lambertian surface of albedo a under irradiance E has radiance a * E / pi;
// exposure 1 maps radiance 1 to white. Matching a * (value / 64) = a * E / pi gives
// E = pi * value / 64, hence the factors below (scene length unit = Quake unit).
#include <cmath>
#include <numbers>

namespace q3 {

inline constexpr float kQ3mapPointScale = 7500.0f;        ///< q3map2 pointScale.
inline constexpr float kQ3mapLinearScale = 1.0f / 8000.0f;///< q3map2 linearScale.
inline constexpr float kQ3mapAreaScale = 0.25f;           ///< q3map2 areaScale (surface lights).
inline constexpr float kQ3mapFormFactorValueScale = 3.0f; ///< q3map2 formFactorValueScale (surface lights).
inline constexpr float kQ3FullBright = 64.0f;             ///< Light value shown as "texture unmodified".
inline constexpr float kQ3DefaultLight = 300.0f;          ///< `light` key default.
inline constexpr float kQ3DefaultSpotRadius = 64.0f;      ///< Spot `radius` key default (at the target).

/// Point/spot light intensity (W/sr per unit^2 of scene length) of a q3map2 inverse-square light.
inline float pointLightIntensity(float quakeLight) {
  return std::numbers::pi_v<float> * quakeLight * kQ3mapPointScale / kQ3FullBright;
}
/// Distance (Quake units) at which a q3map2 linear light reaches zero on a facing surface.
inline float linearLightRange(float quakeLight) { return quakeLight * kQ3mapPointScale * kQ3mapLinearScale; }
/// Peak irradiance factor of a linear light: E(d) = this * max(0, 1 - d / range) * cos.
inline float linearLightIntensity(float quakeLight) {
  return std::numbers::pi_v<float> * linearLightRange(quakeLight) / kQ3FullBright;
}
/// Irradiance of a q3map_sun of the given intensity on a surface facing the sun.
inline float sunIrradiance(float sunIntensity) { return std::numbers::pi_v<float> * sunIntensity / kQ3FullBright; }
/// Emitted radiance of a q3map_surfacelight surface (per unit of its normalised colour).
/// A Lambertian emitter of radiance L seen with form factor F gives irradiance pi * L * F;
/// q3map2 gives the light value 0.75 * value * F, i.e. irradiance pi * 0.75 * value * F / 64.
inline float surfaceLightRadiance(float surfaceLight) {
  return surfaceLight * kQ3mapFormFactorValueScale * kQ3mapAreaScale / kQ3FullBright;
}

/// Ambient radiance (reflected radiance per unit albedo) of a worldspawn `_ambient` / `_minlight`
/// light value: the compiler adds (or floors) `value` on every texel, which shows the texture
/// times value / 64; a Lambertian surface under a uniform radiance L reflects albedo x L.
inline float ambientLightRadiance(float value) { return value / kQ3FullBright; }

/// Uniform sky radiance that lights an upward surface like q3map_skylight (value, iterations):
/// q3map2 spreads `value` over 4(n-1)^2 + 1 suns on n-1 elevation rings (90/n degrees apart,
/// the first at half a step) plus one at the zenith, so an unshadowed upward surface receives
/// value * mean(sin elevation); a uniform sky of radiance L gives irradiance pi * L.
inline float skyLightRadiance(float value, int iterations) {
  if (!(value > 0.0f) || iterations < 2) return 0.0f;
  const int rings = iterations - 1, perRing = 4 * rings;
  const double step = std::numbers::pi / 2.0 / iterations;
  double sum = 1.0;   // the zenith sun
  for (int i = 0; i < rings; ++i) sum += perRing * std::sin((i + 0.5) * step);
  const double meanSin = sum / double(perRing * rings + 1);
  return float(double(value) * meanSin / kQ3FullBright);
}

}  // namespace q3
