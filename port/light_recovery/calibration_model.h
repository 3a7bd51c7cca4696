#pragma once
// The light model the calibrations share (calibration.cpp, emitter_calibration.cpp): lightmap
// texels sampled on the world's surfaces, q3map2's light at a texel from point lights, suns,
// emitting triangles and the open sky, and the bounded least-squares solver. Internal to
// pa_light_recovery.
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include <glm/vec3.hpp>

#include "port/light_recovery/calibration.h"
#include "port/light_recovery/emitter_index.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::recovery::model {

inline constexpr float kMinLightDistance = 16.0f;   ///< q3map2 clamps point-light distances here.
inline constexpr float kSunDistance = 65536.0f;     ///< Shadow rays towards a sun end this far away.

/// One sampled lightmap texel.
struct Sample {
  glm::vec3 position;
  glm::vec3 normal;
  float value;   ///< Texel light value, summed over RGB.
};

/// One fitted unknown's gain on one sample.
struct Entry {
  uint32_t light;
  float gain;
};

/// A uniform number in [0, 1) from the generator's top 24 bits.
float uniform01(std::mt19937& rng);

/// The random numbers of one sample's sky rays (splitmix64), seeded per sample: a sample gets
/// the same numbers whatever order or thread evaluates it.
class SampleRandom {
 public:
  /// The stream of sample `index` of a pass seeded with `seed`.
  SampleRandom(uint32_t seed, uint64_t index);
  /// A uniform number in [0, 1) (24 bits).
  float next01();

 private:
  uint64_t state_;
};

/// Calls body(begin, end) over sub-ranges of [0, count) on the current task arena's threads.
/// Each call must write only the results of its own indices; results then do not depend on the
/// thread count.
void parallelOverSamples(size_t count, const std::function<void(size_t, size_t)>& body, size_t grain = 64);

/// True when every component is finite.
bool finite3(const glm::vec3& v);

/// Area-weighted texel samples (options.maxSamples, options.seed) over the world model's
/// lightmapped, visible, opaque surfaces.
std::vector<Sample> sampleLightmaps(const q3::WorldScene& scene, const LightCalibrationOptions& options);

/// A light's colour summed over RGB (negative components count 0).
float colorSum(const q3::WorldLight& light);

/// Unshadowed light value a unit-valued inverse-square point light gives the sample (q3map2's
/// pointScale, cosine and 16-unit distance clamp), summed over RGB.
float pointGain(const Sample& s, const q3::WorldLight& light);

/// Light value (summed over RGB) an authored light gives the sample, shadows included; shadow
/// rays are counted in `rays`.
float authoredLight(const Sample& s, const q3::WorldLight& light, const glm::vec3& origin, const SegmentBlocked& blocked,
                    size_t& rays);

/// Cosine-weighted share of the hemisphere above the sample through which the sky is seen.
float openSky(const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked, SampleRandom& random, int rays);

/// Light value (summed over RGB) an emitting triangle gives the sample: the renderer's
/// irradiance L * A * cos * cos' / d^2 in light-value units, shadowed towards its centre.
float emitterLight(const Sample& s, const PreparedEmitter& e, const glm::vec3& origin, const SegmentBlocked& blocked,
                   const LightCalibrationOptions& o, size_t& rays);

/// Light value (summed over RGB) the scene's own light gives the sample: authored lights,
/// emitting triangles (those `emitters` finds near the sample, made for o.minTracedValue) and
/// the open sky, shadows included; `near` is scratch space.
float knownLight(const q3::WorldScene& scene, const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked,
                 const EmitterIndex& emitters, const LightCalibrationOptions& o, SampleRandom& random, size_t& rays,
                 std::vector<uint32_t>& near);

/// Least-squares weight of a texel: 1 (absolute errors) or 1 / (texel + 32) (relative).
double weightOf(float texel, const LightCalibrationOptions& o);

/// Appends {offset + i, gain} for each light i of `lights` whose unit gain on the sample is worth
/// tracing (above options.minTracedValue at 4x its value or minLightValue) and whose shadow ray
/// from `origin` is clear; every shadow ray traced is counted in `rays`.
void appendShadowedGains(const Sample& s, const glm::vec3& origin, const std::vector<const q3::WorldLight*>& lights,
                         uint32_t offset, const SegmentBlocked& blocked, const LightCalibrationOptions& o, size_t& rays,
                         std::vector<Entry>& entries);

/// Adds one sample's row (its entries' gains and the constant, the last of `n` unknowns) with
/// weight `w` and right-hand side `target` to the normal equations, and counts each entry's
/// unknown in `lit`.
void accumulateRow(const std::vector<Entry>& entries, double w, double target, size_t n, std::vector<double>& gram,
                   std::vector<double>& rhs, std::vector<size_t>& lit);

/// min 1/2 x'(G + L)x - (b + L x0)'x subject to lower <= x <= upper, by coordinate descent
/// (`gram` row-major n x n, the prior already folded into gram and rhs).
std::vector<double> solveBounded(const std::vector<double>& gram, const std::vector<double>& rhs, std::vector<double> x,
                                 const std::vector<double>& lower, const std::vector<double>& upper, int sweeps);

}  // namespace pa::recovery::model
