#pragma once
// Accumulation film: per-pixel running means over any number of frames, kept in double
// precision (exact to ~1e-12 relative over millions of samples), a Welford variance of each
// pixel's luminance samples, and the resolved float/RGBA8 buffers handed out by render().
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "renderer/scene/scene_types.h"

namespace pa {

/// Running mean and variance of a stream of values (Welford), in double precision.
class RunningStats {
 public:
  /// Adds one value.
  void add(double x) {
    ++count_;
    const double delta = x - mean_;
    mean_ += delta / static_cast<double>(count_);
    m2_ += delta * (x - mean_);
  }
  /// Number of values.
  uint64_t count() const { return count_; }
  /// Mean of the values (0 when empty).
  double mean() const { return mean_; }
  /// Unbiased sample variance (0 with fewer than two values).
  double variance() const { return count_ > 1 ? m2_ / static_cast<double>(count_ - 1) : 0.0; }
  /// Variance of the mean estimate: variance() / count().
  double varianceOfMean() const { return count_ > 1 ? variance() / static_cast<double>(count_) : 0.0; }

 private:
  uint64_t count_ = 0;
  double mean_ = 0.0;
  double m2_ = 0.0;
};

/// What one camera sample measured.
struct PixelSample {
  glm::vec3 radiance{0.0f};
  /// The part of radiance gathered before the path's first diffuse or glossy scattering (emitters,
  /// sky, glows seen directly or through mirrors and portals): exact per sample, never denoised.
  /// With LightingLook::DisplaySpace, the linear value of its parts' summed display values.
  glm::vec3 emission{0.0f};
  glm::vec3 albedo{0.0f};
  glm::vec3 normal{0.0f};
  float depth = std::numeric_limits<float>::infinity();
  bool overlay = false;   ///< The camera ray's first hit was on a drawOnTop instance.
  /// First camera-visible hit for reprojection: its instance (kNoId = sky, or seen through a
  /// portal), material index (kNoId = the default material), world position, and the triangle
  /// and barycentrics (weights of vertices 1 and 2) it lies at (for meshes whose vertices move).
  InstanceId instance = kNoId;
  MaterialId material = kNoId;
  glm::vec3 position{0.0f};
  uint32_t prim = 0;
  glm::vec2 bary{0.0f};
};

/// Sums of one pixel's samples.
struct PixelAccumulator {
  double radiance[3] = {0.0, 0.0, 0.0};
  double emission[3] = {0.0, 0.0, 0.0};
  double albedo[3] = {0.0, 0.0, 0.0};
  double normal[3] = {0.0, 0.0, 0.0};
  double depthSum = 0.0;
  uint64_t depthCount = 0;
  uint64_t samples = 0;
  RunningStats luminance;

  /// Adds one sample (non-finite radiance counts as black, emission included, so one bad path
  /// cannot poison the mean).
  void add(const PixelSample& s);
};

/// Maps linear radiance to display-referred [0, 1] (before sRGB encoding).
glm::vec3 tonemap(const glm::vec3& linear, Tonemap op);

/// The 8-bit sRGB byte of a display value in [0, 1] (lround(clamp(linearToSrgb(x)) x 255), NaN
/// -> 0) without a power function: the byte is the number of the 255 values where it steps up
/// that lie at or below x, those found once by bisection over floats with the exact curve, so
/// every float encodes as with it. A table of the byte at each 1/4096 of [0, 1] starts the count,
/// then two comparisons without branches (the curve never climbs more than two bytes in 1/4096:
/// the constructor checks it).
class SrgbByteEncoder {
 public:
  SrgbByteEncoder();
  /// The byte of display value x.
  uint8_t operator()(float x) const {
    if (!(x > 0.0f)) return 0;   // NaN too
    if (x >= 1.0f) return 255;
    const uint32_t start = bucketStart_[static_cast<uint32_t>(x * float(kBuckets))];   // exact: a power of two
    return static_cast<uint8_t>(start + (steps_[start] <= x) + (steps_[start + 1] <= x));
  }

 private:
  static constexpr uint32_t kBuckets = 4096;
  /// steps_[k]: the smallest float whose byte is k + 1; entries 255 and 256 are infinite.
  std::array<float, 257> steps_;
  std::array<uint8_t, kBuckets> bucketStart_;   ///< The byte of k / kBuckets.
};

/// The radiance `look` shows for a pixel of radiance, emission and albedo (first-hit AOVs):
/// unchanged when Physical; LightingLook::DisplaySpace's product otherwise (channels whose albedo
/// is under 1/255 keep their radiance).
glm::vec3 lightingLook(const glm::vec3& radiance, const glm::vec3& emission, const glm::vec3& albedo,
                       LightingLook look);

/// lightingLook of each pixel into `shown` (as many pixels as `radiance`), the sRGB curves
/// eight values at a time without powf (fastLinearToSrgb / fastSrgbToLinear: within 2e-7 of
/// lightingLook's curves over [0, 1]).
void lightingLookRows(std::span<const glm::vec3> radiance, std::span<const glm::vec3> emission,
                      std::span<const glm::vec3> albedo, LightingLook look, std::span<glm::vec3> shown);

/// Encodes linear radiance as display RGBA8: x exposure, tonemap, sRGB, alpha 255 (what the
/// film's rgba8 holds). `rgba8` has 4 bytes per radiance pixel; throws std::invalid_argument otherwise.
void encodeDisplay(std::span<const glm::vec3> linear, float exposure, Tonemap op, std::span<uint8_t> rgba8);

/// The accumulation buffer plus resolved outputs.
class Film {
 public:
  /// Resizes (and clears) when the size differs.
  void resize(uint32_t width, uint32_t height);
  /// Clears all sums and the frame count.
  void reset();
  /// Accumulator of pixel (x, y); callers give each pixel to one thread at a time.
  PixelAccumulator& pixel(uint32_t x, uint32_t y) { return pixels_[size_t{y} * width_ + x]; }
  /// True when a sample of pixel (x, y) in the last frame that set it met an overlay first.
  bool overlayAt(uint32_t x, uint32_t y) const { return overlay_[size_t{y} * width_ + x] != 0; }
  /// Records whether this frame's samples of pixel (x, y) met an overlay first.
  void setOverlayAt(uint32_t x, uint32_t y, bool overlay) { overlay_[size_t{y} * width_ + x] = overlay ? 1 : 0; }
  /// Starts a frame of one sample per pixel written straight into the resolved buffers
  /// (writeSample) instead of the accumulators; a later frame that keeps accumulating rebuilds
  /// them from those buffers first (resumeAccumulation). Without `aovs`, writeSample leaves the
  /// emission, albedo and normal buffers as they were (nothing reads them this frame: no
  /// denoiser, temporal stage or lighting look) and the accumulators cannot be rebuilt
  /// (canResume() is false until the next reset). With `filtered` the caller changes the
  /// resolved radiance in place afterwards (temporal stage, denoiser): it no longer holds the
  /// samples, and the accumulators cannot be rebuilt either.
  void beginSingleSampleFrame(bool aovs = true, bool filtered = false);
  /// The resolved values of pixel (x, y) for one sample: what add() then resolveMeanRows give
  /// (radiance, depth and variance only in a single-sample frame without AOVs).
  void writeSample(uint32_t x, uint32_t y, const PixelSample& s);
  /// True unless the last single-sample frame left the AOV buffers out or was filtered:
  /// resumeAccumulation can rebuild the accumulators (otherwise the next accumulating frame must
  /// reset()).
  bool canResume() const { return !accumulatorsStale_ || (aovsWritten_ && !filtered_); }
  /// Asks the cache for the storage of pixels [x, x + n) of row y ahead of their samples
  /// (writeSample's buffers in a single-sample frame, the accumulators otherwise).
  void prefetchPixels(uint32_t x, uint32_t y, uint32_t n) const;
  /// Makes the accumulators hold the last single-sample frame again (exactly: one sample each)
  /// when that frame skipped them; does nothing otherwise.
  void resumeAccumulation();
  /// Counts one finished render() call.
  void finishFrame() { ++frames_; }
  /// Frames in the mean.
  uint32_t frames() const { return frames_; }
  /// Resolves rows [rowBegin, rowEnd) into the float and RGBA8 buffers (resolveMeanRows + encodeRows).
  void resolveRows(uint32_t rowBegin, uint32_t rowEnd, float exposure, Tonemap op,
                   LightingLook look = LightingLook::Physical);
  /// Resolves rows [rowBegin, rowEnd) into the float buffers (means, AOVs, variance) only.
  void resolveMeanRows(uint32_t rowBegin, uint32_t rowEnd);
  /// Encodes rows [rowBegin, rowEnd) of the float radiance into RGBA8 (lighting look with the
  /// emission and albedo AOVs, exposure, tonemap, sRGB); the float radiance stays as traced.
  void encodeRows(uint32_t rowBegin, uint32_t rowEnd, float exposure, Tonemap op,
                  LightingLook look = LightingLook::Physical);
  /// The resolved radiance, writable between resolveMeanRows and encodeRows (denoising).
  std::span<glm::vec3> resolvedRadiance() { return radiance_; }
  /// Width in pixels.
  uint32_t width() const { return width_; }
  /// Height in pixels.
  uint32_t height() const { return height_; }
  /// Resolved buffers, valid after resolveRows over all rows.
  const std::vector<glm::vec3>& radiance() const { return radiance_; }
  /// Resolved mean of PixelSample::emission (the part of radiance() the denoiser leaves alone).
  const std::vector<glm::vec3>& emission() const { return emission_; }
  const std::vector<glm::vec3>& albedo() const { return albedo_; }
  const std::vector<glm::vec3>& normal() const { return normal_; }
  const std::vector<float>& depth() const { return depth_; }
  const std::vector<float>& variance() const { return variance_; }
  const std::vector<uint8_t>& rgba8() const { return rgba8_; }

 private:
  uint32_t width_ = 0;
  uint32_t height_ = 0;
  uint32_t frames_ = 0;
  std::vector<PixelAccumulator> pixels_;
  std::vector<glm::vec3> radiance_, emission_, albedo_, normal_;
  std::vector<float> depth_, variance_;
  std::vector<uint8_t> rgba8_;
  std::vector<uint8_t> overlay_;   ///< Per pixel: overlayAt.
  bool accumulatorsStale_ = false;   ///< The last frame was written by writeSample.
  bool aovsWritten_ = true;            ///< ... with the emission, albedo and normal buffers.
  bool filtered_ = false;              ///< ... and its resolved radiance was filtered after.
  SrgbByteEncoder encoder_;
};

}  // namespace pa
