#pragma once
// The temporal stage of SVGF (Schied et al. 2017) for the Direct and Path presets: this frame's
// demodulated radiance ((radiance - emission) / first-hit albedo, as the à-trous denoiser
// demodulates) is blended with last frame's history, fetched bilinearly at the pixel's previous
// position (GBuffer::motion). Each of the four taps counts only when the surface there had the
// same instance and material and a matching depth and normal; with none left the pixel is
// disoccluded and starts again. Per pixel it keeps the history length and the first and second
// moments of luminance: colour blends with alpha = max(1 / length, alphaMin), the moments give
// the variance that guides the à-trous filter, and the filter's first pass becomes the next
// history. Where the mean over the 5 x 5 neighbourhood of this frame's luminance minus the
// reprojected history mean (each clamped to a few standard deviations) departs from 0 by many
// standard errors (a light switched off, a door
// closed), the history is dropped. Where the temporal gradients (gradients.h) say the lighting
// changed, that share of the history is dropped too. Emission stays exact.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/scene/temporal/motion.h"

namespace pa::temporal {

/// Blend and rejection parameters.
struct Config {
  float alphaMin = 0.1f;            ///< Least weight of the new frame's colour (longest memory ~ 1 / alphaMin).
  float momentsAlphaMin = 0.2f;     ///< Least weight of the new frame's luminance moments.
  float maxHistory = 64.0f;         ///< History length cap (frames).
  float depthTolerance = 0.02f;     ///< Relative depth mismatch a tap may have (plus 2 pixels' depth slope).
  float normalCosine = 0.9f;        ///< Least cosine between a tap's normal and the pixel's previous normal.
  float rejectSigmas = 3.0f;        ///< Standard errors of the neighbourhood's mean change that drop a history.
  float rejectRelative = 0.1f;      ///< ... plus this fraction of the neighbourhood's history luminance.
  uint32_t minLengthForVariance = 4;   ///< Shorter histories get the denoiser's spatial variance estimate.
  bool rowLanes = true;   ///< Reprojects 8 (4 without AVX) pixels at a time; false: one by one (the same bits).
};

/// This frame's inputs (width * height each, row-major from the top row), as the film resolves them.
struct FrameInputs {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const glm::vec3> emission;   ///< Part of the radiance never filtered (Film::emission).
  std::span<const glm::vec3> albedo;     ///< Mean first-hit albedo.
  std::span<const glm::vec3> normal;     ///< Mean first-hit shading normal.
  std::span<const float> depth;          ///< Mean first-hit distance (inf = sky).
  const GBuffer* gbuffer = nullptr;      ///< Instance, material and motion of this frame.
  /// Per pixel, the share (0..1) of its history to drop because the lighting changed there
  /// (GradientEstimator::historyDrop); empty: none.
  std::span<const float> historyDrop;
};

/// Temporal accumulation with its history (one per view; reset when the view's kind changes).
class TemporalFilter {
 public:
  /// A filter with the given parameters and no history.
  explicit TemporalFilter(const Config& config = {});
  /// The parameters in use.
  const Config& config() const { return config_; }
  /// Forgets the history: every pixel of the next frame starts again.
  void reset();
  /// Replaces `radiance` (the frame's mean, width * height) by its blend with the history and
  /// fills variance() and historyLength(). Parallel over rows in the calling task arena; the
  /// result does not depend on the thread count. Throws std::invalid_argument on a size mismatch.
  void accumulate(const FrameInputs& frame, std::span<glm::vec3> radiance);
  /// Per pixel, after accumulate(): variance of the luminance in radiance units (the
  /// temporal moments' where the history has minLengthForVariance frames, else 0).
  std::span<const float> variance() const { return variance_; }
  /// Per pixel, after accumulate(): frames in the history (0 = not accumulated: sky, black).
  std::span<const float> historyLength() const { return length_; }
  /// Demodulated colour that becomes the next frame's history; accumulate() fills it with the
  /// blend, and the denoiser may overwrite it with its first pass (SVGF's feedback).
  std::span<glm::vec3> feedback() { return color_; }
  /// Ends the frame: what accumulate() wrote (and feedback() holds) becomes the history.
  void endFrame();

 private:
  /// History of one pixel besides its colour.
  struct State {
    float moment1 = 0.0f, moment2 = 0.0f;   ///< Mean luminance and mean squared luminance.
    float length = 0.0f;                    ///< Frames (0 = no history).
    float depth = 0.0f;
    glm::vec3 normal{0.0f};
    InstanceId instance = kNoId;
    MaterialId material = kNoId;
  };
  /// The reprojected history of one pixel (length 0 = none).
  struct Reprojected {
    glm::vec3 color{0.0f};
    float moment1 = 0.0f, moment2 = 0.0f, length = 0.0f;
    float variance = 0.0f;      ///< moment2 - moment1^2, at least 0.
  };
  /// What each pixel adds to its neighbours' rejection tests, one plane per term with a zero
  /// border of kRejectPad pixels (a pixel without history adds zeros): its luminance change
  /// clamped to the bound of temporal.cpp, its history's mean and variance, and 1 for the count.
  struct RejectTerms {
    std::vector<float> change, mean, variance, count;
    size_t stride = 0;
    size_t pad = 0;
    /// Index of pixel (x, y) in each plane.
    size_t at(uint32_t x, uint32_t y) const { return (y + pad) * stride + x + pad; }
  };
  void prepareRows(const FrameInputs& frame, std::span<const glm::vec3> radiance, uint32_t y0, uint32_t y1);
  void reprojectRows(const FrameInputs& frame, uint32_t y0, uint32_t y1);
  /// reprojectRows() for one pixel (any position).
  void reprojectPixel(const FrameInputs& frame, uint32_t x, uint32_t y);
  /// reprojectRows() for the kCount pixels of row y from x on (x > 0, x + kCount < width, 0 < y
  /// < height - 1, with a history).
  void reprojectLanes(const FrameInputs& frame, uint32_t x, uint32_t y);
  void blendRows(const FrameInputs& frame, std::span<glm::vec3> radiance, uint32_t y0, uint32_t y1);
  /// Per pixel of row y, whether the rejection test drops its history (-1) or not (0), into `out`
  /// (width rounded up to whole lanes).
  void rejectRow(uint32_t y, int32_t* out) const;

  Config config_;
  uint32_t width_ = 0, height_ = 0;
  bool haveHistory_ = false;
  std::vector<glm::vec3> color_, historyColor_;   // demodulated: this frame's, and last frame's
  std::vector<State> state_, history_;
  std::vector<float> variance_, length_;
  std::vector<glm::vec3> signal_;       // this frame's demodulated radiance
  std::vector<float> signalLuminance_;  // its luminance (NaN = not accumulated)
  std::vector<Reprojected> reprojected_;
  RejectTerms reject_;
  std::vector<int32_t> rejected_;   // rejectRow's answers, each row rounded up to whole lanes
};

}  // namespace pa::temporal
